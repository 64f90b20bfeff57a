// Each transfer scheme's name, source and what it conserves, for people: the README's scheme
// table is generated from here (`apiclab docs schemes`), so a scheme added to the registry
// without its facts fails the docs test. docs/transfer-schemes.md holds the measurements.
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
  switch (s) {
    case Scheme::pic:
      return {"PIC", "Jiang et al. 2017, eqs 1-2",
              "mass, linear momentum; loses angular momentum and energy (dissipative)"};
    case Scheme::flip:
      return {"FLIP", "Jiang et al. 2017, eq 3 (PIC/FLIP blend α)",
              "mass, linear momentum; not angular momentum; keeps energy as noise"};
    case Scheme::apic:
      return {"APIC", "Jiang et al. 2017, eqs 24-26, 37-40",
              "mass, linear and angular momentum (Sec 5.3)"};
    case Scheme::rpic:
      return {"RPIC", "Jiang et al. 2017, Secs 2.1, 5.1",
              "mass, linear and angular momentum; damps non-rigid motion like PIC"};
    case Scheme::mls:
      return {"MLS", "Hu et al. 2018, Sec 4, eqs 17-18",
              "mass, linear and angular momentum (APIC's transfers)"};
    case Scheme::asflip:
      return {"ASFLIP", "Fei et al. 2021 (update of their demo pyasflip)",
              "mass, linear momentum; not angular momentum"};
    case Scheme::xpic:
      return {"XPIC", "Hammerquist and Nairn 2017, XPIC(m)",
              "mass, linear momentum; not angular momentum (as PIC)"};
    case Scheme::tpic:
      return {"TPIC", "Nakamura et al. 2023 (Taylor PIC)",
              "mass, linear momentum; angular momentum in P2G, not in G2P with B-splines"};
    case Scheme::polypic:
      return {"PolyPIC", "Fu et al. 2017 (MLS velocity modes, Hu et al. 2018 Sec 3.2)",
              "mass, linear and angular momentum"};
  }
  return {};
}

}  // namespace apiclab
