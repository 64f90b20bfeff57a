// One pane of `compare --schemes` and `gui --schemes`: an MPM transfer scheme (`apic`, or
// `mpm:apic`) or a solver method without schemes (`eol`, `eulerian`). One parser for both
// commands, so they accept the same lists and reject bad ones with the same message.
#pragma once
#include <string>
#include <vector>

#include "sim/registry.hpp"

namespace apiclab {

struct PaneSpec {
  std::string key;               // as listed, minus a leading `mpm:`
  std::string method;            // "mpm", "eol", "eulerian"
  Scheme scheme = Scheme::apic;  // used by MPM panes
};

// A comma-separated list; throws std::invalid_argument naming the bad entry (unknown,
// listed twice) or an empty list.
std::vector<PaneSpec> parse_panes(const std::string& list);

}  // namespace apiclab
