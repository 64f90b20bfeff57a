// The frame loop of run, render, compare, figures and the GUI worker: frame 0 is the initial
// state, frame f is at f/fps, and the last frame lands exactly on time.end, so every command
// and the GUI reach the scene's end even when it is not a whole number of frames.
#pragma once
#include <functional>

#include "app/lockstep.hpp"
#include "sim/scene.hpp"

namespace apiclab {

struct FrameTimes {
  explicit FrameTimes(const SceneDesc& scene);
  int frames = 1;  // after frame 0: time.end·fps rounded, at least one
  double fps = 24, end = 1;
  // Frame f's time; the last frame is time.end.
  double time_of(int frame) const { return frame >= frames ? end : frame / fps; }
};

// Calls on_frame(0) on the initial state, then, for f = 1..frames, advances every pane to
// frame f's time and calls on_frame(f). Stops early when on_frame returns false.
void run_frame_loop(const FrameTimes& times, Lockstep& panes, const Lockstep::OnRow& on_row,
                    const std::function<bool(int frame)>& on_frame);

}  // namespace apiclab
