// How long a run may be: caps on its frames and steps, so that a step of 1e-30 s, a modulus of
// 1e308, a Courant number of 1e-12 or 1e9 frames per second is refused at once with its numbers
// instead of running for years. The caps are options (--max-steps, --max-frames; docs/cli.md).
#pragma once
#include <string>

#include "sim/measure/diagnostics.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {

inline constexpr double kDefaultMaxSteps = 1e8;
inline constexpr double kDefaultMaxFrames = 1e6;
// Steps whose Δt predicts the run's length: an adaptive rule's Δt is known only once it runs.
inline constexpr long kPredictingSteps = 10;

// The fewest steps the scene's time-step rule can take to time.end, and the bound that sets it
// ("a fixed step of 1e-30 s", "the elastic rule's step ...").
struct StepBound {
  double steps = 0;
  std::string why;
};
StepBound fewest_steps(const SceneDesc& scene);

// Throws SceneError with the numbers when the scene has more frames than max_frames or its
// time-step rule must take more steps than max_steps.
void check_run_length(const SceneDesc& scene, double max_steps, double max_frames);

// One step's row during a run: throws SceneError when one of the first kPredictingSteps steps
// predicts more than max_steps steps to `end`, or when the run passes max_steps.
void check_step_budget(const DiagnosticsRow& row, double end, double max_steps);

}  // namespace apiclab
