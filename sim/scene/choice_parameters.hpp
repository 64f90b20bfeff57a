// The scene keys whose value is a word chosen from a registry (sim/scene/registry.hpp) or a switch:
// each key declared once with what it chooses, its words and the reader's default, for help
// texts and docs/scene-keys.md (`apiclab docs scene-keys`). Numbers: sim/scene/parameters.hpp.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "sim/scene/scene.hpp"

namespace apiclab {

struct ChoiceOption {
  std::string key, help;
};

struct ChoiceParameter {
  std::string_view key;  // scene JSON path; '*' stands for an index
  std::string_view what;
  std::string default_key;  // "" when the scene must give it
  std::string_view method;  // as NumericParameter::method: "" every method, "mpm", "eol eulerian"
  std::vector<ChoiceOption> options;
};

// In the order a scene file reads: domain, time, solver, materials, objects, colliders.
const std::vector<ChoiceParameter>& choice_parameters();

// The Eulerian-on-Lagrangian contact kinds of `solver.contact`
// (sim/eol/contact/surface_contact.hpp).
const std::vector<Choice<EolSolverDesc::Contact>>& eol_contact_choices();

}  // namespace apiclab
