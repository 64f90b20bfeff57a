#include "app/frame_loop.hpp"

#include <algorithm>
#include <cmath>

#include "app/stop_signal.hpp"

namespace apiclab {

FrameTimes::FrameTimes(const SceneDesc& scene)
    : frames(std::max(1, int(std::lround(scene.time.end * scene.time.fps)))),
      fps(scene.time.fps),
      end(scene.time.end) {}

void run_frame_loop(const FrameTimes& times, Lockstep& panes, const Lockstep::OnRow& on_row,
                    const std::function<bool(int frame)>& on_frame) {
  // SIGINT/SIGTERM (app/stop_signal.hpp) stops the loop between steps: a frame is whole or not
  // begun.
  if (!on_frame(0)) return;
  for (int f = 1; f <= times.frames && !stop_signal(); ++f) {
    panes.advance_to(times.time_of(f), on_row);
    if (stop_signal()) return;  // stopped between steps: frame f was not reached
    if (!on_frame(f)) return;
  }
}

}  // namespace apiclab
