// Shared command-line plumbing for the subcommands (docs/architecture.md, Command line).
#pragma once
#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/assets.hpp"
#include "app/clock.hpp"  // now_seconds
#include "app/particle_export.hpp"
#include "app/run_length.hpp"
#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"

namespace apiclab::cli {

// A user error: printed as one line "apiclab: <message>", exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The common OPTIONS of run, render, compare, gui.
struct RunOptions {
  std::string scene;  // path or shipped scene name
  std::string scheme, kernel, integrator, precision = "double";
  std::optional<double> flip_alpha, lambda, t_end, fps, dt;
  std::optional<int> frames;
  std::string csv, dump;
  std::string dump_format;  // --dump-format: csv,vtk,ply,obj; empty: the method's default
  std::vector<std::string> sets;
  int threads = 0;  // 0: OpenMP default
  bool quiet = false;
  bool overwrite = false;  // --overwrite: replace outputs that are not this run's
  std::string max_memory;  // BYTES|auto|none; empty: auto
  // Refuse runs longer than these (app/run_length.hpp): --max-steps, --max-frames.
  double max_steps = kDefaultMaxSteps, max_frames = kDefaultMaxFrames;
};

// Which of the common options a subcommand takes (gui has its own --frames and no outputs).
struct RunOptionSet {
  bool scene_required = true;
  bool frames = true;   // --frames (gui has its own)
  bool outputs = true;  // --csv, --dump
  bool quiet = true;
};

// Registers the common options on a subcommand; the numeric ones take their help, unit,
// allowed range and default from the parameter registry (sim/scene/parameters.hpp).
void add_run_options(CLI::App* cmd, RunOptions& o, RunOptionSet which = {});

// The options as `--set` overrides, after checking each (app/cli_checks.hpp), so that the same
// strict scene parser validates them: the scene's own `--set`s come last.
std::vector<std::string> option_overrides(const RunOptions& o);

// Loads the scene and applies the options as `--set` overrides. Throws SceneError /
// UsageError (a run longer than --max-steps or --max-frames included); warns about overlapping
// objects.
SceneDesc load_scene_with_options(const RunOptions& o);
Precision precision_of(const RunOptions& o);
// --dump-format as a list; UsageError for an unknown or repeated format, or formats without --dump.
// Without --dump-format: csv, or vtk for a method without particles (`particles` false: eol).
std::vector<DumpFormat> dump_formats_of(const RunOptions& o, bool particles = true);
void apply_threads(int threads);

// Creates `dir` (and parents) and checks that a file can be written there; throws UsageError.
void ensure_writable_dir(const std::string& dir);
// Checks that `file` can be written: its directory is created and writable, an existing file
// opens for writing; a new file is not created (an output is whole or absent). UsageError.
void ensure_writable_file(const std::string& file);

// A duration as a person reads it: "12.3s", "4m05s", "3h20m", "2.5 days", "3.1e+143 years"
// (a stiff scene's dt can make the ETA a 150-digit number of seconds).
std::string format_duration(double seconds);

// Progress with ETA on stderr: on a terminal one line rewritten in place a few times a second;
// otherwise plain lines every few seconds, without \r or escape codes.
class Progress {
 public:
  Progress(std::string label, double total, bool quiet);
  void update(double done, const std::string& extra = "");
  void finish(const std::string& summary);

 private:
  std::string label_;
  double total_;
  bool quiet_, terminal_;  // terminal: stderr is a tty (\r rewrites; otherwise plain lines)
  double start_, last_ = -1;
};

}  // namespace apiclab::cli
