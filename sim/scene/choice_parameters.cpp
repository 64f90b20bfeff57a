#include "sim/scene/choice_parameters.hpp"

#include "sim/method_registry.hpp"

namespace apiclab {
namespace {

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

std::string word(bool b) { return b ? "true" : "false"; }

std::vector<ChoiceParameter> make_table() {
  const SceneDesc d;  // the reader's defaults
  const auto& sv = d.solver;
  return {
      {"domain.boundary", "every wall's condition, or an object of walls x-, x+, y-, y+, z-, z+",
       std::string(key_of(BoundaryCondition::slip)), "", options_of(boundary_choices())},
      {"time.dt.rule", "time-step rule", std::string(key_of(d.time.rule)), "",
       options_of(dt_rule_choices())},
      {"time.dt.land_on_frames", "fixed rule: shorten the steps that would pass a frame time",
       word(d.time.land_on_frames), "",
       switch_options("frames exactly on f/fps", "the frame is the step at or just past f/fps")},
      {"solver.method", "solver family", sv.method, "", method_options()},
      {"solver.scheme", "transfer scheme", std::string(key_of(sv.scheme)), "mpm",
       options_of(scheme_choices())},
      {"solver.kernel", "interpolation kernel", std::string(key_of(sv.kernel)), "mpm",
       options_of(kernel_choices())},
      {"solver.integrator", "grid update", std::string(key_of(sv.integrator)), "mpm",
       options_of(integrator_choices())},
      {"solver.apic_linear_form", "APIC's C with the multilinear kernel",
       std::string(key_of(sv.apic_linear_form)), "mpm", options_of(apic_linear_form_choices())},
      {"solver.preconditioner", "CG preconditioner of the implicit solve",
       std::string(key_of(sv.preconditioner)), "mpm", options_of(cg_preconditioner_choices())},
      {"solver.stop_on_nonconvergence", "a missed implicit tolerance ends the run (exit 3)",
       word(sv.stop_on_nonconvergence), "mpm",
       switch_options("stop with exit 3", "count it and carry on")},
      {"solver.contact", "contact rows against walls and colliders",
       std::string(choice_key(eol_contact_choices(), sv.eol.contact)), "eol eulerian",
       options_of(eol_contact_choices())},
      {"materials.*.model", "constitutive model", std::string(key_of(MaterialDesc{}.model)), "",
       options_of(material_choices())},
      {"objects.*.shape.type", "shape", "", "", options_of(shape_choices())},
      {"objects.*.sampling.type", "how the shape is filled with particles",
       std::string(choice_key(sampling_choices(), SamplingDesc{}.type)), "",
       options_of(sampling_choices())},
      {"colliders.*.condition", "the plane's condition",
       std::string(key_of(ColliderDesc{}.condition)), "", collider_options()},
  };
}

}  // namespace

const std::vector<ChoiceParameter>& choice_parameters() {
  static const std::vector<ChoiceParameter> table = make_table();
  return table;
}

const std::vector<Choice<EolSolverDesc::Contact>>& eol_contact_choices() {
  static const std::vector<Choice<EolSolverDesc::Contact>> c = {
      {"surface", EolSolverDesc::Contact::surface,
       "rows of the object's surface behind a plane, eqs 27-29"},
      {"nodes", EolSolverDesc::Contact::nodes, "one row per node on or behind a plane"}};
  return c;
}

}  // namespace apiclab
