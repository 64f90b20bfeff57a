// Each transfer scheme's name, source and what it conserves, for people, as its own file states
// them (sim/scene/scheme_registry.hpp): the README's scheme table is generated from here
// (`apiclab docs schemes`). docs/transfer-schemes.md holds the measurements.
#pragma once
#include <string_view>

#include "sim/scene/registry.hpp"

namespace apiclab {

struct SchemeFacts {
  std::string_view name;       // as people write it: "APIC", "PolyPIC"
  std::string_view source;     // paper and equations
  std::string_view conserves;  // over a transfer, as docs/transfer-schemes.md measures it
};

inline SchemeFacts scheme_facts(Scheme s) {
  const SchemeInfo& i = scheme_info(s);
  return {i.name, i.source, i.conserves};
}

}  // namespace apiclab
