#include "app/frame_loop.hpp"

#include <algorithm>
#include <cmath>

#include "app/stop_signal.hpp"

namespace apiclab {
namespace {

// Frames after frame 0: a time.end within round-off of a frame time ends on that frame.
int frame_count(double end, double fps) {
  const double x = end * fps;
  const double whole = std::round(x);
  if (std::abs(x - whole) <= 1e-9 * std::max(1.0, x)) return std::max(1, int(whole));
  return std::max(1, int(std::floor(x)) + 1);
}

}  // namespace

FrameTimes::FrameTimes(const SceneDesc& scene, double max_steps)
    : frames(frame_count(scene.time.end, scene.time.fps)),
      fps(scene.time.fps),
      end(scene.time.end),
      max_steps(max_steps) {}

void run_frame_loop(const FrameTimes& times, Lockstep& panes, const Lockstep::OnRow& on_row,
                    const std::function<bool(int frame)>& on_frame, int resume_after) {
  const auto checked_row = [&](std::size_t pane, const DiagnosticsRow& r) {
    check_step_budget(r, times.end, times.max_steps);
    if (on_row) on_row(pane, r);
  };
  // SIGINT/SIGTERM (app/stop_signal.hpp) stops the loop between steps: a frame is whole or not
  // begun.
  if (resume_after < 0 && !on_frame(0)) return;
  for (int f = std::max(1, resume_after + 1); f <= times.frames && !stop_signal(); ++f) {
    panes.advance_to(times.time_of(f), checked_row);
    if (stop_signal()) return;  // stopped between steps: frame f was not reached
    if (!on_frame(f)) return;
  }
}

}  // namespace apiclab
