// The frame loop of run, render, compare, figures and the GUI worker: frame 0 is the initial
// state, frame f is at f/fps for every whole frame up to time.end, and when time.end is not a
// whole number of frames one more frame lands exactly on it, so every command and the GUI reach
// the scene's end and no frame time before it is skipped.
#pragma once
#include <functional>

#include "app/lockstep.hpp"
#include "app/run_length.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {

struct FrameTimes {
  explicit FrameTimes(const SceneDesc& scene, double max_steps = kDefaultMaxSteps);
  // After frame 0: floor(time.end·fps), plus one when time.end falls between two frame times;
  // at least one.
  int frames = 1;
  double fps = 24, end = 1;
  double max_steps = kDefaultMaxSteps;  // the run stops with an error past it (app/run_length.hpp)
  // Frame f's time; the last frame is time.end.
  double time_of(int frame) const { return frame >= frames ? end : frame / fps; }
};

// Calls on_frame(0) on the initial state, then, for f = 1..frames, advances every pane to
// frame f's time and calls on_frame(f). Stops early when on_frame returns false. Throws
// SceneError when a pane's first steps predict more than times.max_steps steps, or when a pane
// takes more (app/run_length.hpp). A resumed run (app/checkpoint.hpp) passes the last frame it
// wrote as `resume_after`: the loop goes on from the panes' time to frame resume_after + 1.
void run_frame_loop(const FrameTimes& times, Lockstep& panes, const Lockstep::OnRow& on_row,
                    const std::function<bool(int frame)>& on_frame, int resume_after = -1);

}  // namespace apiclab
