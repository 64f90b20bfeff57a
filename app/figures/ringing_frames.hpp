// Fig 1 (Sec 6.7): the ringing test's frames, one row per time, one pane per scheme, velocity
// arrows on; DIR/fig1_ringing.png.
#pragma once
#include <string>
#include <vector>

#include "app/figures/chart_canvas.hpp"
#include "app/jobs.hpp"

namespace apiclab::figures {

// runs: one per scheme, each with a snapshot at every time (throws UsageError when one
// stopped early).
void write_ringing_frames(ChartCanvas& canvas, const std::vector<jobs::Run>& runs,
                          const std::vector<double>& times, const std::string& dir);

}  // namespace apiclab::figures
