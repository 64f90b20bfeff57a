// `run --checkpoint-every N` / `--checkpoint-seconds S` and `run --resume DIR`
// (docs/outputs.md, "Checkpoints"): DIR/checkpoint.bin holds, in one file written whole, a JSON
// header (the build, the thread count, the run's settings and options, where the run started)
// and the state bytes (the run's output indexes and running diagnostics, then the solver's
// state, Simulation::save_state). Read back, the envelope is checked first (format, length,
// checksum), then the build and the settings: each refusal is one line naming the difference.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "app/cli.hpp"

namespace apiclab::cli {

// The checkpoint options of `run`.
struct CheckpointOptions {
  int every_frames = 0;      // --checkpoint-every N: after every N-th frame
  double every_seconds = 0;  // --checkpoint-seconds S: after the first step S s past the last
  std::string dir;           // --checkpoint-dir; empty: the CSV's path with .checkpoint
  bool on() const { return every_frames > 0 || every_seconds > 0; }
};

// DIR/checkpoint.bin.
std::string checkpoint_path(const std::string& dir);
// The folder of a run's checkpoints: --checkpoint-dir, else CSV without .csv, plus .checkpoint.
std::string checkpoint_dir_of(const CheckpointOptions& c, const std::string& csv);

// Writes DIR/checkpoint.bin whole (a temporary file renamed): the envelope around `header`
// (with this build added) and `state`. WriteError when it cannot.
void write_checkpoint(const std::string& dir, nlohmann::json header, const std::string& state);

struct CheckpointFile {
  nlohmann::json header;
  std::string bytes;         // the whole file
  std::size_t state_at = 0;  // where the state bytes start
  std::size_t state_size = 0;
};
// Reads DIR/checkpoint.bin and checks its envelope and build: UsageError "checkpoint DIR: ..."
// when it is missing, truncated, corrupt, of another format or of another build.
CheckpointFile read_checkpoint(const std::string& dir);

// The run's options as the header keeps them, and back.
nlohmann::json options_json(const RunOptions& o, const std::string& summary,
                            const CheckpointOptions& c);
void options_from_json(const nlohmann::json& j, RunOptions& o, std::string& summary,
                       CheckpointOptions& c);

// "" or the first difference between the settings a checkpoint was written with and a run's,
// as "KEY is A there, B here" (compared without the --set spellings, `overrides`).
std::string settings_difference(const nlohmann::json& theirs, const nlohmann::json& ours);

}  // namespace apiclab::cli
