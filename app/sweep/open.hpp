// A finished or partial sweep folder opened for the viewer (`apiclab gui --sweep DIR`): its spec
// (DIR/spec.json, the copy `apiclab sweep` keeps), plan and results read back by the sweep's own
// code (plan.hpp, results.hpp, tables.hpp), and any run turned into live panes beside its
// reference, each built by scene_of() from the options the runner gave its process.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "app/sim_worker.hpp"
#include "app/sweep/tables.hpp"

namespace apiclab::sweep {

// The charts of one scene of the sweep, as `apiclab sweep` draws them (charts.cpp).
struct SceneCharts {
  std::string scene;
  std::vector<Series> cost;                 // error against cost, one per spec.series value
  std::vector<std::size_t> front;           // Pareto front (run indices), by cost
  std::vector<Series> convergence;          // error against dx; empty without a resolution axis
  const StabilityMap* stability = nullptr;  // into OpenedSweep::maps; null without columns
};

struct OpenedSweep {
  std::string dir;
  Spec spec;
  Plan plan;
  std::vector<RunResult> results;  // point into plan.runs: an OpenedSweep never moves
  std::vector<StabilityMap> maps;
  std::vector<SceneCharts> charts;  // one per scene, in spec order
  std::size_t missing = 0;          // runs without a result yet (a partial sweep)

  OpenedSweep() = default;
  OpenedSweep(const OpenedSweep&) = delete;
  OpenedSweep& operator=(const OpenedSweep&) = delete;
};

// The spec's file name inside a sweep folder.
inline constexpr const char* kSpecCopy = "spec.json";
// `apiclab sweep` keeps its spec as DIR/spec.json, byte for byte, so the folder can be reopened.
void write_spec_copy(const std::string& spec_path, const std::string& out_dir);

// Whose folder `out_dir` is: none yet (no spec.json) or the same spec as `spec_path` (as JSON,
// whatever its layout) is this sweep's, and a rerun resumes there. Another spec's folder is
// refused with one line naming its sweep, or with `overwrite` its spec-level files (spec.json,
// runs.csv, summary.md, the charts) are removed; run records stay, each named by its
// configuration.
void claim_sweep_folder(const std::string& spec_path, const std::string& out_dir, bool overwrite);

// Reads a sweep folder; throws cli::UsageError with one line naming the cause: no such folder,
// not a sweep (no spec.json), a spec the checks refuse, no finished run yet, a damaged record.
std::shared_ptr<const OpenedSweep> open_sweep(const std::string& dir);

// What a click on a run opens: the reference run's configuration and the run's, one pane each
// (one pane when the run is its own reference), both from t = 0. scene is the reference's, whose
// frame times the panes share (the plan gives every run of a scene the same frame times).
struct SweepLaunch {
  std::size_t run = 0, reference = 0;
  SceneDesc scene;
  std::vector<gui::PaneConfig> panes;  // [reference, run]
  Precision precision = Precision::dbl;
};
SweepLaunch launch_run(const OpenedSweep& sweep, std::size_t run);

// The run with this id (runs.csv's first column); throws cli::UsageError when none has it.
std::size_t run_with_id(const OpenedSweep& sweep, const std::string& id);

// One line on a run for tooltips: its configuration, outcome, cost and errors.
std::string run_summary(const OpenedSweep& sweep, std::size_t run);

}  // namespace apiclab::sweep
