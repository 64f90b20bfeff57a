#include "app/run_length.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/frame_loop.hpp"

namespace apiclab {
namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

double fastest_wave_speed(const SceneDesc& s) {
  double c = 0;
  for (const MaterialDesc& m : s.materials) c = std::max(c, m.wave_speed());
  return c;
}

}  // namespace

StepBound fewest_steps(const SceneDesc& s) {
  const TimeDesc& t = s.time;
  const double frames = FrameTimes(s).frames;
  StepBound b;
  auto at_least = [&](double steps, const std::string& why) {
    if (!(steps <= b.steps)) b = {steps, why};  // NaN or more: this bound
  };
  if (t.rule == DtRule::fixed) {
    at_least(std::ceil(t.end / t.dt * (1 - 1e-12)), "a fixed step of " + num(t.dt) + " s");
    if (t.land_on_frames) at_least(frames, "one step per frame");
    return b;
  }
  at_least(frames, "one step per frame (time.end x time.fps)");
  at_least(t.end / t.dt, "the cap time.dt.value = " + num(t.dt) + " s");
  // The explicit elastic limit ν Δx / c: MPM's elastic rule; every adaptive rule of the EoL
  // family, on its objects' cells (sim/eol/time_step.hpp).
  const bool eol = s.solver.method != "mpm";
  if (t.rule == DtRule::elastic || eol) {
    const double cell =
        s.solver.method == "eol" && s.solver.eol.cell > 0 ? s.solver.eol.cell : s.domain.dx;
    const double c = fastest_wave_speed(s), dt = t.nu * cell / c;
    at_least(t.end / dt, "the elastic rule's step nu dx / c = " + num(t.nu) + " x " + num(cell) +
                             " m / " + num(c) + " m/s = " + num(dt) + " s");
  }
  if (t.rule == DtRule::two_step && !eol) {  // Δt ≤ max(Δt_min, ν Δx / v_τ) (Sec 6.7)
    const double dt = std::max(t.dt_min, std::min(t.dt, t.nu * s.domain.dx / t.v_tau));
    at_least(t.end / dt, "the two-step rule's longest step " + num(dt) + " s");
  }
  return b;
}

void check_run_length(const SceneDesc& s, double max_steps, double max_frames) {
  const double frames = FrameTimes(s).frames;
  if (frames > max_frames)
    throw SceneError(s.source + ": " + num(frames) + " frames (time.end x time.fps = " +
                     num(s.time.end * s.time.fps) + "), more than --max-frames " + num(max_frames) +
                     " (raise --max-frames, or lower time.end or time.fps)");
  const StepBound b = fewest_steps(s);
  if (b.steps > max_steps)
    throw SceneError(s.source + ": " + b.why + " takes at least " + num(b.steps) +
                     " steps to time.end = " + num(s.time.end) + " s, more than --max-steps " +
                     num(max_steps) + " (raise --max-steps, or lower time.end)");
}

void check_step_budget(const DiagnosticsRow& r, double end, double max_steps) {
  if (double(r.step) > max_steps)
    throw SceneError("step " + std::to_string(r.step) + " passed --max-steps " + num(max_steps) +
                     " at t = " + num(r.t) + " s of time.end = " + num(end) +
                     " s (the last step's dt = " + num(r.dt) +
                     " s); raise --max-steps to run further");
  if (r.step > kPredictingSteps || !(r.dt > 0)) return;
  const double predicted = double(r.step) + (end - r.t) / r.dt;
  if (predicted > max_steps)
    throw SceneError("step " + std::to_string(r.step) + " took dt = " + num(r.dt) +
                     " s, which predicts " + num(predicted) + " steps to time.end = " + num(end) +
                     " s, more than --max-steps " + num(max_steps) +
                     " (raise --max-steps, or lower time.end)");
}

}  // namespace apiclab
