#include "sim/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "sim/method_registry.hpp"
#include "sim/state_io.hpp"

namespace apiclab {

std::optional<Failure> Simulation::step(double t_limit, DiagnosticsRow* row) {
  if (failure_) return failure_;
  if (!(t_limit > time_)) return std::nullopt;
  const auto start = std::chrono::steady_clock::now();
  const TimeDesc& tm = scene().time;
  const FrameStep s = land_on_frame(tm, choose_dt(), t_limit - time_);
  if (s.by_frame) dt_set_by_frame();
  DiagnosticsRow r = step_fixed_measured(s.dt);
  // Landing on t_limit (a sum of steps is off by round-off): within 1e-12 of the time scale for
  // the landing rules; for an exact fixed step within 1e-6 of a step, which n·Δt accumulated in
  // double misses only after ~1e9 steps, so a frame time that is a whole number of steps is met.
  const double landing =
      tm.lands_on_frames() ? 1e-12 * std::max(1.0, std::abs(t_limit)) : 1e-6 * s.dt;
  if (std::abs(t_limit - time_) < landing) time_ = t_limit;
  if (time_ >= t_limit) reached_frame_time();
  r.t = time_;
  r.dt = s.dt;
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (row) *row = r;
  failure_ = check_step(r);
  return failure_;
}

void Simulation::save_state(StateWriter& w) const {
  w.tag("simulation");
  w.value(time_);
  w.value(steps_);
  save_family_state(w);
}

void Simulation::load_state(StateReader& r) {
  r.tag("simulation");
  r.value(time_);
  r.value(steps_);
  failure_.reset();
  load_family_state(r);
}

FrameStep land_on_frame(const TimeDesc& tm, double dt, double to_frame) {
  if (!tm.lands_on_frames()) return {dt, false};
  const double frame = 1.0 / tm.fps;
  FrameStep s{std::min(dt, frame), frame < dt};
  if (to_frame < 1.001 * s.dt) return {to_frame, true};
  if (to_frame < 2.0 * s.dt) return {0.5 * to_frame, true};
  return s;
}

std::shared_ptr<Snapshot> Simulation::scene_snapshot() const {
  auto s = std::make_shared<Snapshot>();
  const SceneDesc& sc = scene();
  s->dim = dim();
  s->step = steps_;
  s->time = time_;
  s->scene_name = sc.name;
  s->domain_min = sc.domain.min;
  s->domain_max = sc.domain.max;
  s->dx = sc.domain.dx;
  s->colliders = sc.colliders;  // as the scene gives them: the renderer places them at `time`
  for (const auto& m : sc.materials) s->material_names.push_back(m.name);
  s->failure = failure_;
  return s;
}

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
