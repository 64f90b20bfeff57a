// `apiclab sweep SPEC --out DIR`: runs a sweep of configurations (app/sweep/), then writes
// runs.csv, the charts and summary.md (docs/sweeps.md).
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>

#include "app/cli_checks.hpp"
#include "app/output_file.hpp"
#include "app/particle_export.hpp"
#include "app/sweep/open.hpp"
#include "app/sweep/plan.hpp"
#include "app/sweep/record.hpp"
#include "app/sweep/results.hpp"
#include "app/sweep/runner.hpp"
#include "app/sweep/spec.hpp"
#include "app/sweep/summary.hpp"
#include "cli.hpp"
#include "commands.hpp"
#ifdef APICLAB_HAVE_FIGURES
#include "app/sweep/charts.hpp"
#endif

namespace apiclab::cli {
namespace {

// A sweep larger than this is refused unless --max-runs raises it: planning and running that
// many configurations is rarely what was meant.
constexpr double kDefaultMaxRuns = 10000;
// A spec of more runs says its count before planning them (a smaller one plans at once).
constexpr double kAnnounceRuns = 1000;

std::string format_count(double n) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.15g", n);
  return buf;
}

struct SweepOptions {
  std::string spec, out, export_jobs, collect, dump_format;
  int jobs = 1;
  double max_runs = kDefaultMaxRuns;
  std::optional<double> target_error;
  bool quiet = false;
  bool overwrite = false;
  sweep::SweepCheckpoints checkpoints;  // passed to every run
};

int sweep_command(const SweepOptions& o) {
  using namespace apiclab::sweep;
  if (o.jobs < 1) throw UsageError("sweep: --jobs must be at least 1");
  if (o.target_error && !(*o.target_error > 0))
    throw UsageError("sweep: --target-error must be positive");
  const Spec spec = load_spec(o.spec);
  // The size first, and a refusal above the cap before any planning.
  const std::size_t runs = count_runs(spec);
  if (!o.quiet && double(runs) > kAnnounceRuns)
    std::fprintf(stderr, "apiclab: sweep %s: %zu runs; planning\n", spec.name.c_str(), runs);
  if (double(runs) > o.max_runs)
    throw UsageError("sweep " + o.spec + ": " + std::to_string(runs) +
                     " runs, more than --max-runs " + format_count(o.max_runs) +
                     " (raise --max-runs to plan and run them all, or narrow the axes)");
  Plan plan = make_plan(spec);  // every check before any run
  if (!o.dump_format.empty()) {
    try {
      parse_dump_formats(o.dump_format);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("sweep: --dump-format: ") + e.what());
    }
    plan.dump_formats = o.dump_format;
  }
  if (!o.checkpoints.dir.empty() && !o.checkpoints.on())
    throw UsageError("sweep: --checkpoint-dir needs --checkpoint-every or --checkpoint-seconds");
  if (!o.collect.empty() && o.checkpoints.on())
    throw UsageError("sweep: --collect DIR reads a finished sweep; it takes no checkpoint options");
  plan.checkpoints = o.checkpoints;
  if (!plan.checkpoints.dir.empty()) {
    ensure_writable_dir(plan.checkpoints.dir);
    plan.checkpoints.dir = std::filesystem::absolute(plan.checkpoints.dir).string();
  }
  if (!o.collect.empty() && (!o.out.empty() || !o.export_jobs.empty()))
    throw UsageError(
        "sweep: --collect DIR reads a finished sweep; it takes no --out or "
        "--export-jobs");
  const std::string out = o.collect.empty() ? o.out : o.collect;
  if (out.empty()) throw UsageError("sweep: --out DIR is required (or --collect DIR)");
  if (o.collect.empty())
    ensure_writable_dir(out);
  else if (!std::filesystem::is_directory(out))
    throw UsageError("sweep: --collect '" + out + "': no such folder");
  claim_sweep_folder(o.spec, out, o.overwrite);  // another spec's folder: refused
  if (!o.export_jobs.empty()) {
    std::error_code ec;
    if (std::filesystem::equivalent(o.export_jobs, o.spec, ec))
      throw UsageError("sweep: --export-jobs " + o.export_jobs +
                       " is the spec this sweep reads: an output never replaces an input; give "
                       "another path");
    write_spec_copy(o.spec, out);  // the folder reopens in the viewer (gui --sweep)
    export_jobs(plan, out, o.export_jobs);
    std::printf(
        "%zu run commands written to %s; run them (e.g. parallel --jobs 16 < %s), then "
        "apiclab sweep %s --collect %s\n",
        plan.runs.size(), o.export_jobs.c_str(), o.export_jobs.c_str(), o.spec.c_str(),
        out.c_str());
    return 0;
  }
  if (o.collect.empty()) {
    if (!o.quiet)
      std::fprintf(stderr, "apiclab: sweep %s: %zu runs, %d at a time, into %s\n",
                   spec.name.c_str(), plan.runs.size(), o.jobs, out.c_str());
    write_spec_copy(o.spec, out);
    run_plan(plan, out, o.jobs, o.quiet);
  } else {
    write_spec_copy(o.spec, out);
  }
  std::vector<RunResult> results;
  try {
    results = collect(spec, plan, out);
  } catch (const OldFramesError& e) {  // --collect of an older folder: never mix precisions
    throw UsageError(std::string("sweep: ") + e.what() + "; `apiclab sweep " + o.spec + " --out " +
                     out + "` records those runs again");
  }
  const std::string csv = write_runs_csv(spec, results, out);
  std::vector<std::string> charts;
#ifdef APICLAB_HAVE_FIGURES
  try {
    charts = write_charts(spec, results, out, o.target_error);
  } catch (const WriteError&) {
    throw;  // a chart that cannot be written: "cannot write FILE: REASON", exit 2
  } catch (const std::exception& e) {
    std::fprintf(stderr, "apiclab: sweep: charts not drawn: %s\n", e.what());
  }
#endif
  write_summary(spec, results, out, o.target_error, charts);
  std::size_t missing = 0, refused = 0;
  for (const RunResult& r : results) {
    missing += r.outcome == "no_result";
    refused += r.outcome == "refused";
  }
  std::printf("sweep %s: %zu runs; %s, %s/summary.md", spec.name.c_str(), results.size(),
              csv.c_str(), out.c_str());
  for (const std::string& c : charts) std::printf(", %s/%s", out.c_str(), c.c_str());
  std::printf("\n");
  if (missing)
    std::printf("apiclab: warning: %zu runs have no result yet (rows with outcome no_result)\n",
                missing);
  if (refused) {  // a configuration the sweep asked for and did not get: not a result
    std::fflush(stdout);
    std::fprintf(stderr,
                 "apiclab: sweep: %zu of %zu runs refused (outcome refused in runs.csv; the cause "
                 "in %s/runs/ID/refused.txt and logs/ID.log)\n",
                 refused, results.size(), out.c_str());
    return 2;
  }
  return 0;
}

}  // namespace

void register_sweep(CLI::App& root, CommandTable& table) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* cmd = root.add_subcommand(
      "sweep",
      "run a sweep spec: runs.csv, error-vs-cost, stability and convergence charts, "
      "summary.md");
  cmd->add_option("spec", o->spec, "sweep spec (JSON; docs/sweeps.md)")->required();
  cmd->add_option("--out", o->out, "output folder (runs are kept there; a rerun resumes)");
  cmd->add_option("--jobs", o->jobs,
                  "runs at a time, each its own process [allowed: 1-4096; default: 1]")
      ->check(whole_number(1, 4096));
  cmd->add_option("--export-jobs", o->export_jobs,
                  "write one self-contained `apiclab run` command per line instead of running");
  cmd->add_option("--collect", o->collect,
                  "build runs.csv, charts and summary from the records in this folder");
  cmd->add_option("--target-error", o->target_error,
                  "summary.md names the cheapest run whose selected errors are at most this (> 0)");
  cmd->add_option("--dump-format", o->dump_format,
                  "also dump every run's particles per frame into runs/ID/dump/ in these formats "
                  "(csv,vtk,vtk-raw,ply,obj, as run --dump-format) [default: no dumps]");
  cmd->add_option("--max-runs", o->max_runs,
                  "refuse a spec of more runs than this, before planning it [allowed: > 0; "
                  "default: 10000]")
      ->check(number_above(0));
  cmd->add_option("--checkpoint-every", o->checkpoints.every_frames,
                  "every run writes a checkpoint after every N-th frame; the same command run "
                  "again resumes unfinished runs from their last checkpoint (docs/sweeps.md) "
                  "[allowed: integer >= 1; default: none]")
      ->check(whole_number(1, std::numeric_limits<int>::max()));
  cmd->add_option("--checkpoint-seconds", o->checkpoints.every_seconds,
                  "every run writes a checkpoint after the first step S wall seconds past its "
                  "last one [allowed: > 0; default: none]")
      ->check(number_above(0));
  cmd->add_option("--checkpoint-dir", o->checkpoints.dir,
                  "the runs' checkpoints go into DIR/ID [default: beside each unfinished "
                  "record, runs/ID.partial/checkpoint]");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->add_flag("--overwrite", o->overwrite,
                "use a folder that holds another spec's sweep: its spec, runs.csv, summary and "
                "charts are replaced, its run records kept [default: off]");
  table.push_back({cmd, [o] { return sweep_command(*o); }});
}

}  // namespace apiclab::cli
