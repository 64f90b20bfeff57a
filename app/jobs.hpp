// The job runner of `figures` (and sweeps): simulation runs described by scene, scheme and
// overrides, executed on a pool of threads. A run whose wall time is a result (`timed`) never
// shares the machine with another job, so that its wall time is honest.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/thread_pool.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"
#include "sim/simulation.hpp"

namespace apiclab::jobs {

// One simulation run: the diagnostics rows from t = 0 and, when asked, snapshots at given times.
struct Run {
  std::string scene, scheme;           // shipped scene name or path; solver.scheme
  std::string method;                  // solver.method instead of solver.scheme (EoL); or empty
  std::vector<std::string> overrides;  // `--set` style KEY=VALUE
  double t_end = 0;                    // 0: the scene's time.end
  std::vector<double> snapshot_times;
  double cost = 1;     // relative cost hint: costlier runs start first, so the pool ends together
  bool timed = false;  // `seconds` is a result: run alone, with every core free
  // Results.
  std::vector<DiagnosticsRow> rows;
  std::vector<std::shared_ptr<Snapshot>> snapshots;
  std::string failure;                 // the solver's failure, with its time; the rows stop there
  SchemeParameters scheme_parameters;  // of the scene it ran, for labels: "XPIC(2)"
  double flip_alpha = 1;
  double seconds = 0;  // wall time of the whole run, building the particles included
};

// A run that could not start (a bad scene or override), naming the run.
struct JobError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Runs one job on this thread. Throws SceneError for a bad scene or override.
void execute(Run& run);

using apiclab::run_pool;  // app/thread_pool.hpp

// Every run: the untimed ones on the pool, costliest first; then the timed ones one by one,
// alone. Throws JobError naming the first run that could not start.
void execute_all(const std::vector<Run*>& runs, int threads);

}  // namespace apiclab::jobs
