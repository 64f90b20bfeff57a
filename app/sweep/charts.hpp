// The sweep's PNG charts, drawn by the project's own plot widget on the headless ChartCanvas
// (app/figures/chart_canvas.hpp), each written beside a CSV of the points it shows:
// error_vs_cost.png (log-log, one series per spec.series value, the Pareto front as a dashed
// line), stability_SCENE.png (coloured cells with the failure time) and convergence.png (error
// against dx with fitted slopes).
#pragma once
#include <imgui.h>

#include <string>
#include <vector>

#include "app/gui/plot.hpp"
#include "app/sweep/results.hpp"

namespace apiclab::sweep {

// The charts' styles, shared with the viewer's sweep panel (app/gui/sweep_panel.cpp).
ImU32 series_color(const Spec& spec, const std::string& value, std::size_t k);
// A scatter through the line plot: a NaN between points breaks the line, markers stay; point i
// of the data is sample 2 i of the series. x and y must outlive the series.
gui::PlotSeries scatter(const std::string& label, ImU32 color, const std::vector<double>& x,
                        const std::vector<double>& y);
std::string error_label(const std::string& error);
ImU32 outcome_color(const std::string& outcome);  // stability map cells

// Writes the charts into out_dir; returns their file names. Throws std::runtime_error when no
// offscreen GL context can be made.
std::vector<std::string> write_charts(const Spec& spec, const std::vector<RunResult>& results,
                                      const std::string& out_dir);

}  // namespace apiclab::sweep
