// The sweep's PNG charts, drawn by the project's own plot widget on the headless ChartCanvas
// (app/figures/chart_canvas.hpp), each written beside a CSV of the points it shows:
// error_vs_cost.png (log-log, one series per spec.series value, the Pareto front as a dashed
// line), stability_SCENE.png (coloured cells with the failure time) and convergence.png (error
// against dx with fitted slopes).
#pragma once
#include <string>
#include <vector>

#include "app/sweep/results.hpp"

namespace apiclab::sweep {

// Writes the charts into out_dir; returns their file names. Throws std::runtime_error when no
// offscreen GL context can be made.
std::vector<std::string> write_charts(const Spec& spec, const std::vector<RunResult>& results,
                                      const std::string& out_dir);

}  // namespace apiclab::sweep
