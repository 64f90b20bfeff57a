// The sweep's PNG charts, drawn by the project's own plot widget on the headless ChartCanvas
// (app/figures/chart_canvas.hpp), each written beside a CSV of the points it shows:
// error_vs_cost_SCENE.png (log-log, one colour per spec.series value, a shape per configuration,
// failed runs at the top edge, the Pareto front dashed, the target error), stability_SCENE.png
// (coloured cells with the failure time) and convergence_SCENE.png (error against dx with fitted
// slopes, one line per configuration). The viewer's sweep panel draws the same plots.
#pragma once
#include <imgui.h>

#include <optional>
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
// Stability map cells and failed points, by outcome ("" for a cell with no run: excluded).
ImU32 outcome_color(const std::string& outcome);
// What the legends say of an outcome: "refused (its process left no record)".
std::string outcome_legend(const std::string& outcome);

// One chart's plot series, and for each series the run behind each sample (-1: none).
struct ChartPlots {
  std::vector<gui::PlotSeries> series;
  std::vector<std::vector<long>> runs;
  double edge = 0;  // the error axis's top edge, where runs without an error sit
};
// Error against cost for one scene: a series per spec.series value (points shaped and labelled
// by configuration, not-converged runs ringed), runs that blew up at the top edge at their cost,
// refused runs at the top edge at the smallest cost, the Pareto front, the target error.
ChartPlots cost_plots(const Spec& spec, const std::vector<RunResult>& results,
                      const std::string& scene, std::optional<double> target_error);
// Error against dx for one scene: one line per configuration, with its slope in the legend.
ChartPlots convergence_plots(const Spec& spec, const std::vector<RunResult>& results,
                             const std::string& scene);

// Writes the charts into out_dir; returns their file names. Throws std::runtime_error when no
// offscreen GL context can be made.
std::vector<std::string> write_charts(const Spec& spec, const std::vector<RunResult>& results,
                                      const std::string& out_dir,
                                      std::optional<double> target_error = std::nullopt);

}  // namespace apiclab::sweep
