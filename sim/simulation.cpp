#include "simulation.hpp"

#include "method_registry.hpp"

namespace apiclab {

std::optional<Failure> Simulation::advance_to(
    double t_target, const std::function<void(const DiagnosticsRow&)>& on_step) {
  DiagnosticsRow row;
  while (time() < t_target) {
    if (auto f = step(t_target, &row)) return f;
    if (on_step) on_step(row);
  }
  return failure();
}

std::unique_ptr<Simulation> make_simulation(const SceneDesc& scene, Precision precision) {
  const SolverMethod* method = find_method(scene.solver.method);
  if (!method)
    throw SceneError(scene.source + ": key 'solver.method': unknown solver method '" +
                     scene.solver.method + "'");
  return method->make(scene, precision);
}

}  // namespace apiclab
