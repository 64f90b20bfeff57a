#include "app/pane_spec.hpp"

#include <set>
#include <sstream>
#include <stdexcept>

#include "sim/method_registry.hpp"

namespace apiclab {

std::vector<PaneSpec> parse_panes(const std::string& list) {
  std::vector<PaneSpec> specs;
  std::set<std::string> seen;
  std::istringstream in(list);
  for (std::string key; std::getline(in, key, ',');) {
    if (!seen.insert(key).second)
      throw std::invalid_argument("scheme '" + key + "' is listed twice in --schemes");
    const std::string bare = key.rfind("mpm:", 0) == 0 ? key.substr(4) : key;
    if (bare == key && key != "mpm" && find_method(key)) {
      specs.push_back({key, key});
      continue;
    }
    try {
      specs.push_back({bare, "mpm", parse_choice(scheme_choices(), bare, "scheme")});
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string(e.what()) +
                                  " or a solver method without schemes (eol, eulerian)");
    }
  }
  if (specs.empty())
    throw std::invalid_argument("--schemes needs at least one scheme, e.g. pic,flip,apic");
  return specs;
}

std::string pane_conflict(const std::vector<PaneSpec>& panes, const SolverDesc& scene_solver) {
  for (const PaneSpec& p : panes) {
    if (p.method != "mpm") continue;
    SolverDesc solver = scene_solver;
    solver.scheme = p.scheme;
    if (const std::string why = scheme_conflict(solver); !why.empty())
      return "--schemes " + p.key + ": " + why;
  }
  return "";
}

}  // namespace apiclab
