// The views of a sweep's results that summary.md and the charts share: the stability map, the
// convergence series with fitted slopes, the error-against-cost series and the cheapest run
// meeting a target error.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "app/sweep/results.hpp"

namespace apiclab::sweep {

// One stability map per scene: rows = the combinations of every other varying axis, columns =
// the values of spec.columns; each cell the index of its run (or -1).
struct StabilityMap {
  std::string scene, column_key;
  std::vector<std::string> row_labels, column_labels;
  std::vector<std::vector<long>> cells;  // [row][column]
};
std::vector<StabilityMap> stability_maps(const Spec& spec, const std::vector<RunResult>& results);
// "blew up t=0.42", "not converged", "noisy 0.23", "dE 1.2%": what a cell says.
std::string cell_text(const RunResult& r);

// Points of one series (runs sharing a value of `by`, per scene), sorted by x.
struct Series {
  std::string label;
  std::vector<double> x, y;
  std::vector<std::size_t> runs;
  double slope = 0;  // log-log least-squares slope (convergence)
};
// Error against cost (seconds in the steps) per value of spec.series for one scene: the runs
// with an error (completed, noisy, not converged); reference runs left out.
std::vector<Series> cost_series(const Spec& spec, const std::vector<RunResult>& results,
                                const std::string& error, const std::string& scene);
// The scenes of the sweep, in spec order.
std::vector<std::string> scenes(const Spec& spec);
// "scheme=apic, kernel=quadratic, resolution=2": the varying axes that do not follow the scene,
// with their keys' last part.
std::string config_text(const Spec& spec, const PlannedRun& run);
// The axes that tell a chart's points apart beyond `without` (the series axis, the x axis): the
// varying axes that do not follow the scene, of a zipped group only the first and the partners
// that tell its entries apart (integrator and dt_factor zipped: both, as midpoint runs at several
// dt_factors).
std::vector<std::string> distinguishing_axes(const Spec& spec,
                                             const std::vector<std::string>& without);
// "apic quadratic dt_factor=4": choice values as they are, numbers with their key's last part.
std::string axes_text(const PlannedRun& run, const std::vector<std::string>& keys);

// How a chart marks each point's configuration: a shape per combination of shape_keys (at most
// max_shapes of them), and the values of label_keys as a text beside the point. The axes with the
// fewest values take the shapes; the rest become the text.
struct Marking {
  std::vector<std::string> shape_keys, label_keys;
  std::vector<std::string> shapes;                 // per shape: "kernel=cubic, integrator=midpoint"
  std::size_t shape(const PlannedRun& run) const;  // index into shapes (0 when none)
  std::string label(const PlannedRun& run) const;  // "2" or "2/0.5"; "" without label keys
};
Marking marking(const Spec& spec, const std::vector<RunResult>& results, const std::string& scene,
                const std::vector<std::string>& without, std::size_t max_shapes);

// Error against dx per configuration (every distinguishing axis but resolution: the method and
// its Δt factor or rule, so no line crosses Δt factors), with the fitted slope; needs a
// resolution axis with two values or more.
std::vector<Series> convergence_series(const Spec& spec, const std::vector<RunResult>& results,
                                       const std::string& error, const std::string& scene);

// The cheapest completed run whose every selected error is at most `target`; reference runs
// are not candidates (their error against themselves is 0: they would answer every target).
std::optional<std::size_t> cheapest_meeting(const Spec& spec, const std::vector<RunResult>& results,
                                            double target, const std::string& scene);

// Whether the run is its own reference.
inline bool is_reference(const std::vector<RunResult>& results, std::size_t i) {
  return results[i].run->reference == i;
}

}  // namespace apiclab::sweep
