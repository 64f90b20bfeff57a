#include "simulation.hpp"

#include "mpm.hpp"

namespace apiclab {

std::optional<Failure> Simulation::advance_to(double t_target,
                                              const std::function<void(const DiagnosticsRow&)>& on_step) {
  DiagnosticsRow row;
  while (time() < t_target) {
    if (auto f = step(t_target, &row)) return f;
    if (on_step) on_step(row);
  }
  return failure();
}

std::unique_ptr<Simulation> make_simulation(const SceneDesc& scene, Precision precision) {
  const bool single = precision == Precision::single;
  if (scene.dim == 2)
    return single ? std::unique_ptr<Simulation>(new MpmSimulation<float, 2>(scene))
                  : std::unique_ptr<Simulation>(new MpmSimulation<double, 2>(scene));
  return single ? std::unique_ptr<Simulation>(new MpmSimulation<float, 3>(scene))
                : std::unique_ptr<Simulation>(new MpmSimulation<double, 3>(scene));
}

}  // namespace apiclab
