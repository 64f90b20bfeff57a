// One pane of `compare --schemes` and `gui --schemes`: an MPM transfer scheme (`apic`, or
// `mpm:apic`) or a solver method without schemes (`eol`, `eulerian`). One parser for both
// commands, so they accept the same lists and reject bad ones with the same message.
#pragma once
#include <string>
#include <vector>

#include "sim/scene/registry.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {

struct PaneSpec {
  std::string key;               // as listed, minus a leading `mpm:`
  std::string method;            // "mpm", "eol", "eulerian"
  Scheme scheme = Scheme::apic;  // used by MPM panes
};

// A comma-separated list; throws std::invalid_argument naming the bad entry (unknown,
// listed twice) or an empty list.
std::vector<PaneSpec> parse_panes(const std::string& list);

// "--schemes KEY: why" for the first MPM pane whose scheme cannot run with the scene's other
// solver settings (sim/method_registry.hpp scheme_conflict: mls needs symplectic Euler and a
// quadratic or cubic kernel); "" when every pane can.
std::string pane_conflict(const std::vector<PaneSpec>& panes, const SolverDesc& scene_solver);

}  // namespace apiclab
