// A sweep's results: every planned run's record read back, classified (completed / noisy / not
// converged / blew up / no result) and compared with its reference run (sim/measure/metrics.hpp),
// then written as DIR/runs.csv, one row per run.
#pragma once
#include <limits>
#include <string>
#include <vector>

#include "app/sweep/plan.hpp"
#include "app/sweep/record.hpp"

namespace apiclab::sweep {

struct RunResult {
  const PlannedRun* run = nullptr;
  bool present = false;  // a complete record exists
  RunRecord rec;
  // completed | noisy | not_converged | blew_up | refused (its process left no record, its
  // cause in rec.fail_message) | no_result (not run yet)
  std::string outcome;
  metrics::ReferenceDistance ref;
  double rigid = std::numeric_limits<double>::quiet_NaN();  // distance to the known answer
  // By name (spec.hpp's error_names()): the reference distances and the conservation errors.
  double error(const std::string& name) const;
  bool stable() const { return outcome == "completed"; }
  double cost() const { return rec.step_wall_s; }  // seconds inside the steps
};

// Reads every run's record under out_dir/runs (missing ones give outcome no_result, refused ones
// refused). Throws OldFramesError (record.hpp) for a record of the older float frames format.
std::vector<RunResult> collect(const Spec& spec, const Plan& plan, const std::string& out_dir);

// out_dir/runs.csv; returns its path.
std::string write_runs_csv(const Spec& spec, const std::vector<RunResult>& results,
                           const std::string& out_dir);

// Indices of the runs on the Pareto front of (cost, error): completed or noisy runs with a finite
// error that no other such run beats on both. Sorted by cost.
// Only the runs of `scene` when it is not empty (errors of different scenes do not compare).
std::vector<std::size_t> pareto_front(const std::vector<RunResult>& results,
                                      const std::string& error, const std::string& scene = "");

// A number as the tables print it: 4 significant digits, "" for NaN.
std::string number_text(double v, int digits = 4);

}  // namespace apiclab::sweep
