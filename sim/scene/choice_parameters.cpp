#include "sim/scene/choice_parameters.hpp"

#include "sim/method_registry.hpp"
#include "sim/scene/parameters.hpp"

namespace apiclab {
namespace {

using S = SceneDesc;

template <class E>
std::vector<ChoiceOption> options_of(const std::vector<Choice<E>>& choices) {
  std::vector<ChoiceOption> out;
  for (const Choice<E>& c : choices) out.push_back({std::string(c.key), std::string(c.help)});
  return out;
}

std::vector<ChoiceOption> method_options() {
  std::vector<ChoiceOption> out;
  for (const std::string& name : method_names()) out.push_back({name, find_method(name)->help});
  return out;
}

std::vector<ChoiceOption> collider_options() {
  std::vector<ChoiceOption> out = options_of(boundary_choices());
  std::erase_if(out, [](const ChoiceOption& o) { return o.key == "periodic"; });
  return out;
}

std::vector<ChoiceOption> switch_options(std::string_view on, std::string_view off) {
  return {{"true", std::string(on)}, {"false", std::string(off)}};
}

// A collider's shape (sim/geometry/collider_body.hpp).
const std::vector<Choice<ColliderType>>& collider_type_choices() {
  static const std::vector<Choice<ColliderType>> c = {
      {"plane", ColliderType::plane,
       "grid nodes behind the plane through point with normal get the condition"},
      {"box", ColliderType::box, "a box of size around center, turned by degrees"},
      {"rod", ColliderType::rod,
       "a capsule: every point within radius of a segment of length along its x axis"}};
  return c;
}

// The vertex rows of a triangulated box that anchors hold.
const std::vector<Choice<int>>& anchor_row_choices() {
  static const std::vector<Choice<int>> c = {{"top", 0, "the row at the box's max y"},
                                             {"bottom", 1, "the row at the box's min y"},
                                             {"left", 2, "the column at the box's min x"},
                                             {"right", 3, "the column at the box's max x"}};
  return c;
}

bool switch_value(std::string_view word) {
  if (word != "true" && word != "false")
    throw std::invalid_argument("expected true or false, got '" + message_text(std::string(word)) +
                                "'");
  return word == "true";
}

std::string word(bool b) { return b ? "true" : "false"; }

std::string solver_method(std::string_view word) {
  const std::string name(word);
  if (find_method(name)) return name;
  std::string names;
  for (const std::string& n : method_names()) names += (names.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown solver method '" + message_text(name) +
                              "' (one of: " + names + ")");
}

// The walls' condition where the scene names none, for all walls or one.
constexpr std::string_view kWallDefault = "slip";

// domain.boundary as an object: wall W's condition (x-, x+, y-, y+, z-, z+).
template <int W>
void set_wall(S& s, int, std::string_view w) {
  s.domain.walls[W] = parse_choice(boundary_choices(), w, "boundary condition");
}
template <int W>
std::string wall(const S& s, int) {
  return std::string(key_of(s.domain.walls[W]));
}

ChoiceParameter wall_key(std::string_view key, std::string_view what,
                         void (*set)(S&, int, std::string_view), std::string (*get)(const S&, int),
                         bool only_3d) {
  return {key,   what,   std::string(kWallDefault), "", options_of(boundary_choices()), set, get,
          false, only_3d};
}

std::vector<ChoiceParameter> make_table() {
  return {
      {"domain.boundary", "every wall's condition, or an object of walls x-, x+, y-, y+, z-, z+",
       std::string(kWallDefault), "", options_of(boundary_choices()),
       [](S& s, int, std::string_view w) {
         s.domain.walls.fill(parse_choice(boundary_choices(), w, "boundary condition"));
       },
       [](const S& s, int) { return std::string(key_of(s.domain.walls[0])); }},
      wall_key("domain.boundary.x-", "the wall at domain.min x", set_wall<0>, wall<0>, false),
      wall_key("domain.boundary.x+", "the wall at domain.max x", set_wall<1>, wall<1>, false),
      wall_key("domain.boundary.y-", "the wall at domain.min y", set_wall<2>, wall<2>, false),
      wall_key("domain.boundary.y+", "the wall at domain.max y", set_wall<3>, wall<3>, false),
      wall_key("domain.boundary.z-", "the wall at domain.min z (3D)", set_wall<4>, wall<4>, true),
      wall_key("domain.boundary.z+", "the wall at domain.max z (3D)", set_wall<5>, wall<5>, true),
      {"time.dt.rule", "time-step rule", "elastic", "", options_of(dt_rule_choices()),
       [](S& s, int, std::string_view w) {
         s.time.rule = parse_choice(dt_rule_choices(), w, "time-step rule");
       },
       [](const S& s, int) { return std::string(key_of(s.time.rule)); }},
      {"time.dt.land_on_frames", "fixed rule: shorten the steps that would pass a frame time",
       "false", "",
       switch_options("frames exactly on f/fps", "the frame is the step at or just past f/fps"),
       [](S& s, int, std::string_view w) { s.time.land_on_frames = switch_value(w); },
       [](const S& s, int) { return word(s.time.land_on_frames); }},
      {"solver.method", "solver family", "mpm", "", method_options(),
       [](S& s, int, std::string_view w) { s.solver.method = solver_method(w); },
       [](const S& s, int) { return s.solver.method; }},
      {"solver.scheme", "transfer scheme", "apic", "mpm", options_of(scheme_choices()),
       [](S& s, int, std::string_view w) {
         s.solver.scheme = parse_choice(scheme_choices(), w, "scheme");
       },
       [](const S& s, int) { return std::string(key_of(s.solver.scheme)); }},
      {"solver.kernel", "interpolation kernel", "quadratic", "mpm", options_of(kernel_choices()),
       [](S& s, int, std::string_view w) {
         s.solver.kernel = parse_choice(kernel_choices(), w, "kernel");
       },
       [](const S& s, int) { return std::string(key_of(s.solver.kernel)); }},
      {"solver.integrator", "grid update", "symplectic", "mpm", options_of(integrator_choices()),
       [](S& s, int, std::string_view w) {
         s.solver.integrator = parse_choice(integrator_choices(), w, "integrator");
       },
       [](const S& s, int) { return std::string(key_of(s.solver.integrator)); }},
      {"solver.apic_linear_form", "APIC's C with the multilinear kernel", "lagged", "mpm",
       options_of(apic_linear_form_choices()),
       [](S& s, int, std::string_view w) {
         s.solver.apic_linear_form =
             parse_choice(apic_linear_form_choices(), w, "APIC linear form");
       },
       [](const S& s, int) { return std::string(key_of(s.solver.apic_linear_form)); }},
      {"solver.preconditioner", "CG preconditioner of the implicit solve", "block-jacobi", "mpm",
       options_of(cg_preconditioner_choices()),
       [](S& s, int, std::string_view w) {
         s.solver.preconditioner =
             parse_choice(cg_preconditioner_choices(), w, "CG preconditioner");
       },
       [](const S& s, int) { return std::string(key_of(s.solver.preconditioner)); }},
      {"solver.stop_on_nonconvergence", "a missed implicit tolerance ends the run (exit 3)",
       "false", "mpm", switch_options("stop with exit 3", "count it and carry on"),
       [](S& s, int, std::string_view w) { s.solver.stop_on_nonconvergence = switch_value(w); },
       [](const S& s, int) { return word(s.solver.stop_on_nonconvergence); }},
      {"solver.ledger", "the conservation ledger's columns in the diagnostics CSV", "false", "",
       switch_options("each stage's change of mass, momentum, angular momentum and energy",
                      "the CSV's standard columns only"),
       [](S& s, int, std::string_view w) { s.solver.ledger = switch_value(w); },
       [](const S& s, int) { return word(s.solver.ledger); }},
      {"solver.contact", "contact rows against walls and colliders", "surface", "eol eulerian",
       options_of(eol_contact_choices()),
       [](S& s, int, std::string_view w) {
         s.solver.eol.contact = parse_choice(eol_contact_choices(), w, "contact");
       },
       [](const S& s, int) {
         return std::string(choice_key(eol_contact_choices(), s.solver.eol.contact));
       }},
      {"solver.elasticity", "the elastic forces' time integration", "explicit", "eol eulerian",
       options_of(eol_elasticity_choices()),
       [](S& s, int, std::string_view w) {
         s.solver.eol.elasticity = parse_choice(eol_elasticity_choices(), w, "elasticity");
       },
       [](const S& s, int) {
         return std::string(choice_key(eol_elasticity_choices(), s.solver.eol.elasticity));
       }},
      {"materials.*.model", "constitutive model", "neo-hookean", "", options_of(material_choices()),
       [](S& s, int i, std::string_view w) {
         s.materials[size_t(i)].model = parse_choice(material_choices(), w, "material model");
       },
       [](const S& s, int i) { return std::string(key_of(s.materials[size_t(i)].model)); }},
      {"objects.*.shape.type", "shape", "", "", options_of(shape_choices()),
       [](S& s, int i, std::string_view w) {
         s.objects[size_t(i)].shape.type = parse_choice(shape_choices(), w, "shape");
       },
       [](const S& s, int i) {
         return std::string(choice_key(shape_choices(), s.objects[size_t(i)].shape.type));
       }},
      {"objects.*.sampling.type", "how the shape is filled with particles", "ppc", "",
       options_of(sampling_choices()),
       [](S& s, int i, std::string_view w) {
         s.objects[size_t(i)].sampling.type = parse_choice(sampling_choices(), w, "sampling");
       },
       [](const S& s, int i) {
         return std::string(choice_key(sampling_choices(), s.objects[size_t(i)].sampling.type));
       }},
      {"objects.*.anchors.rows",
       "the vertex rows held by zero-length springs (a list of words; triangulated sampling)", "",
       "", options_of(anchor_row_choices()),
       [](S& s, int i, std::string_view w) {
         parse_choice(anchor_row_choices(), w, "anchor row");
         s.objects[size_t(i)].anchors.emplace_back(w);
       },
       [](const S& s, int i) {
         const auto& rows = s.objects[size_t(i)].anchors;
         return rows.empty() ? std::string() : rows.front();
       },
       true},
      {"colliders.*.type", "the collider's kind", "plane", "", options_of(collider_type_choices()),
       [](S& s, int i, std::string_view w) {
         s.colliders[size_t(i)].type = parse_choice(collider_type_choices(), w, "collider type");
       },
       [](const S& s, int i) {
         return std::string(choice_key(collider_type_choices(), s.colliders[size_t(i)].type));
       }},
      // Periodic is parsed (the reader refuses it on a collider by name) but not offered.
      {"colliders.*.condition", "the condition on the body's surface", "slip", "",
       collider_options(),
       [](S& s, int i, std::string_view w) {
         s.colliders[size_t(i)].condition =
             parse_choice(boundary_choices(), w, "boundary condition");
       },
       [](const S& s, int i) { return std::string(key_of(s.colliders[size_t(i)].condition)); }},
  };
}

}  // namespace

std::string ChoiceParameter::key_at(int index) const {
  std::string k(key);
  if (const auto star = k.find('*'); star != std::string::npos)
    k.replace(star, 1, std::to_string(index));
  return k;
}

bool ChoiceParameter::is_switch() const {
  return options.size() == 2 && options[0].key == "true" && options[1].key == "false";
}

bool ChoiceParameter::read_by(std::string_view solver_method) const {
  return method_listed(method, solver_method);
}

const std::vector<ChoiceParameter>& choice_parameters() {
  static const std::vector<ChoiceParameter> table = make_table();
  return table;
}

const ChoiceParameter* find_choice(std::string_view key, int* index) {
  for (const ChoiceParameter& c : choice_parameters())
    if (key_matches(c.key, key, index)) return &c;
  return nullptr;
}

const std::vector<Choice<EolSolverDesc::Contact>>& eol_contact_choices() {
  static const std::vector<Choice<EolSolverDesc::Contact>> c = {
      {"surface", EolSolverDesc::Contact::surface,
       "rows of the object's surface behind a plane, eqs 27-29"},
      {"nodes", EolSolverDesc::Contact::nodes, "one row per node on or behind a plane"}};
  return c;
}

const std::vector<Choice<EolSolverDesc::Elasticity>>& eol_elasticity_choices() {
  static const std::vector<Choice<EolSolverDesc::Elasticity>> c = {
      {"explicit", EolSolverDesc::Elasticity::explicit_euler,
       "the paper's: forces of the state now, the step capped by the elastic limit"},
      {"implicit", EolSolverDesc::Elasticity::backward_euler,
       "backward Euler on each object's grid: advection (eq 33), contact and 1/fps bound the "
       "step"}};
  return c;
}

}  // namespace apiclab
