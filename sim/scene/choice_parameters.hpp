// The scene keys whose value is a word chosen from a registry (sim/scene/registry.hpp) or a switch:
// each key declared once with what it chooses, its words, its default and how it sets the scene.
// The scene reader walks this table as it walks the numeric one (sim/scene/parameters.hpp), and
// help texts and docs/scene-keys.md (`apiclab docs scene-keys`) print it.
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
  // The one statement of the default: SceneDesc() starts from it (keys without '*') and the reader
  // keeps it for a key the file leaves out. "" when the scene must give it.
  std::string default_key;
  std::string_view method;  // as NumericParameter::method: "" every method, "mpm", "eol eulerian"
  std::vector<ChoiceOption> options;
  // Sets the value at `index` (a material, object or collider; 0 otherwise) from a word, a switch
  // from "true" or "false"; throws std::invalid_argument naming the word and the words allowed.
  void (*set)(SceneDesc&, int index, std::string_view word);
  std::string (*get)(const SceneDesc&, int index);  // a list: its first word
  bool list = false;     // the file gives an array of words, each set in turn
  bool only_3d = false;  // read in 3D scenes only (the z walls)

  std::string key_at(int index) const;  // "materials.*.model", 0 -> "materials.0.model"
  bool is_switch() const;               // the file gives true or false
  bool read_by(std::string_view solver_method) const;  // whether that method's scenes take it
};

// In the order a scene file reads: domain, time, solver, materials, objects, colliders.
const std::vector<ChoiceParameter>& choice_parameters();

// A key like "materials.0.model" or "solver.scheme" (or a pattern "materials.*.model"): its
// entry and the index its '*' stands for; null when the key is no word key.
const ChoiceParameter* find_choice(std::string_view key, int* index = nullptr);

// The Eulerian-on-Lagrangian contact kinds of `solver.contact`
// (sim/eol/contact/surface_contact.hpp).
const std::vector<Choice<EolSolverDesc::Contact>>& eol_contact_choices();

// The Eulerian-on-Lagrangian elastic integrations of `solver.elasticity`
// (sim/eol/grid/implicit_elasticity.hpp).
const std::vector<Choice<EolSolverDesc::Elasticity>>& eol_elasticity_choices();

}  // namespace apiclab
