#include "sim/simulation.hpp"

#include <cmath>
#include <sstream>

#include "sim/method_registry.hpp"

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

Failure failure_at(long step, double t, const std::string& quantity, const std::string& detail) {
  std::ostringstream msg;
  msg << "simulation blew up at step " << step << ", t = " << t << ": " << quantity << " "
      << detail;
  return Failure{step, t, quantity, msg.str()};
}

std::optional<Failure> energy_failure(const DiagnosticsRow& r, long step, double t,
                                      const std::string& state, double factor,
                                      double energy_available) {
  if (!std::isfinite(r.total) || !std::isfinite(r.kinetic))
    return failure_at(step, t, state, "became non-finite (NaN or Inf)");
  if (r.kinetic + r.elastic > factor * energy_available) {
    std::ostringstream d;
    d << "grew to " << r.kinetic + r.elastic << ", more than " << factor
      << " x the energy available (" << energy_available << ")";
    return failure_at(step, t, "kinetic + elastic energy", d.str());
  }
  return std::nullopt;
}

std::unique_ptr<Simulation> make_simulation(const SceneDesc& scene, Precision precision) {
  const SolverMethod* method = find_method(scene.solver.method);
  if (!method)
    throw SceneError(scene.source + ": key 'solver.method': unknown solver method '" +
                     scene.solver.method + "'");
  return method->make(scene, precision);
}

}  // namespace apiclab
