// A sweep's runs: the Cartesian product of the spec's axis groups less its exclusions, each run
// turned into `--set` overrides on its base scene (the derived axes resolution and dt_factor
// included), checked by the strict scene parser, keyed by a hash of its configuration, and
// given its reference run.
#pragma once
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "app/cli.hpp"
#include "app/sweep/spec.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab::sweep {

// `sweep --checkpoint-every/--checkpoint-seconds/--checkpoint-dir`: passed to every run's
// command, not part of its configuration (its id).
struct SweepCheckpoints {
  int every_frames = 0;
  double every_seconds = 0;
  std::string dir;  // a run's checkpoint goes into DIR/ID; empty: its record's DIR.partial
  bool on() const { return every_frames > 0 || every_seconds > 0; }
};

struct PlannedRun {
  std::vector<std::pair<std::string, Value>> config;  // every axis key and its value
  std::string scene_path;                             // resolved base scene
  std::vector<std::string> overrides;                 // KEY=VALUE, in order
  std::string precision = "double";
  int threads = 1;
  double dx = 0;              // grid spacing of this run
  double dt = 0;              // fixed step from dt_factor, 0 when the scene's own rule stands
  std::string id;             // 16 hex digits of a hash of the configuration
  std::size_t reference = 0;  // index of the run it is compared with

  const Value* value(const std::string& key) const;
  std::string value_text(const std::string& key) const;  // "" when not an axis
  std::string label() const;                             // "solver.scheme=apic, dt_factor=2"
  // The options of `apiclab run` for this run: the one place its configuration is built. The
  // runner's command line writes them out and the viewer loads scene_of() from them, so the two
  // cannot disagree.
  cli::RunOptions options() const;
  // The self-contained `apiclab run` command that records this run in DIR/runs/ID; with
  // dump formats (csv,vtk,…), also its particle dumps in DIR/runs/ID/dump/; with checkpoints,
  // the same options, so that the command run again resumes the run.
  std::vector<std::string> command(const std::string& exe, const std::string& out_dir,
                                   const std::string& dump_formats = "",
                                   const SweepCheckpoints& checkpoints = {}) const;
};

// The scene this run's `run --record` process simulates: options() through the same loader
// (cli::load_scene_with_options), every override and derived value (dx, sampling, Δt) applied.
SceneDesc scene_of(const PlannedRun& run);

struct Plan {
  std::vector<PlannedRun> runs;
  std::string dump_formats;  // `sweep --dump-format`: not part of a run's configuration (its id)
  SweepCheckpoints checkpoints;
};

// The number of runs: the configurations that no exclusion leaves out, counted without
// planning them (a sweep says its size before it plans, and refuses one too large).
std::size_t count_runs(const Spec& spec);

// Throws cli::UsageError naming the spec and the key for a configuration the scene rejects, a
// run longer than the default --max-steps or --max-frames, or a reference that is not in the
// sweep. Linear in the number of runs.
Plan make_plan(const Spec& spec);

// The folder of a run's record inside a sweep folder.
std::string run_dir(const std::string& out_dir, const PlannedRun& run);

// The folder of a run's checkpoint: DIR/ID under --checkpoint-dir DIR, else the unfinished
// record's own (runs/ID.partial/checkpoint, app/sweep/record.hpp).
std::string run_checkpoint_dir(const std::string& out_dir, const PlannedRun& run,
                               const SweepCheckpoints& checkpoints);

// A shell word (single-quoted where needed), for the exported command lines.
std::string shell_quote(const std::string& word);

}  // namespace apiclab::sweep
