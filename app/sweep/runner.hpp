// Running a sweep's runs: each run is its own `apiclab run ... --record` process, N at a time
// (--jobs N), so that a timed run shares no threads with another; or the same command lines
// written to a file (--export-jobs) for GNU parallel or a Slurm array. Runs whose record is
// complete are skipped, so a killed sweep restarted on the same folder carries on.
#pragma once
#include <string>

#include "app/sweep/plan.hpp"

namespace apiclab::sweep {

// This executable's absolute path (/proc/self/exe), the program of every run command.
std::string self_executable();

struct RunnerReport {
  std::size_t skipped = 0, ran = 0, failed_to_record = 0;
};

// Runs every run of `plan` without a complete record in out_dir/runs, `jobs` at a time; each
// run's stdout and stderr go to out_dir/logs/ID.log. Leftover *.tmp-* folders of killed runs are
// removed first. With plan.dump_formats, a run recorded without its dump/ folder runs again.
RunnerReport run_plan(const Plan& plan, const std::string& out_dir, int jobs, bool quiet);

// One shell command line per run (all of them, complete or not).
void export_jobs(const Plan& plan, const std::string& out_dir, const std::string& file);

}  // namespace apiclab::sweep
