// `run --checkpoint-every N` / `--checkpoint-seconds S` and `run --resume DIR`
// (docs/outputs.md, "Checkpoints"): DIR/checkpoint.bin holds, in one file written whole, a JSON
// header (the build, the thread count, the run's settings and options, where the run started)
// and the state bytes (the run's output indexes and running diagnostics, then the solver's
// state, Simulation::save_state). Read back, the envelope is checked first (format, length,
// checksum), then the build and the settings: each refusal is one line naming the difference.
#pragma once
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/cli.hpp"
#include "app/particle_export.hpp"
#include "sim/measure/run_summary.hpp"
#include "sim/state_io.hpp"

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

// A run's checkpoints, one after another into DIR: the state goes into a buffer kept from one
// checkpoint to the next, and the file is checksummed, written and renamed on a thread of its
// own while the run goes on (a state under 1 MiB at once). The next checkpoint waits for that
// write; a write that failed throws its WriteError from the next call.
class CheckpointWriter {
 public:
  explicit CheckpointWriter(std::string dir);
  CheckpointWriter(const CheckpointWriter&) = delete;
  CheckpointWriter& operator=(const CheckpointWriter&) = delete;
  ~CheckpointWriter();  // waits for the write in flight
  const std::string& dir() const { return dir_; }
  // The buffer for the next state, emptied, once the write in flight is done.
  std::string& state();
  // Starts writing DIR/checkpoint.bin from `header` and the state in the buffer.
  void write(nlohmann::json header);
  // Throws the WriteError of a write that has failed; never waits.
  void check();
  // Waits for the write in flight; throws its WriteError.
  void finish();

 private:
  std::string dir_;
  std::string state_;
  struct Pending;  // the write in flight (app/checkpoint.cpp: <future> stays out of this header)
  std::unique_ptr<Pending> pending_;
};

// The run's part of a checkpoint's state, before the solver's (`run` and the viewer's panes):
// the output indexes, then the running diagnostics and the files series.pvd lists.
struct RunProgress {
  std::int32_t last_frame = -1;    // the last frame written
  std::uint64_t csv_bytes = 0;     // the CSV's bytes
  std::uint64_t frames_bytes = 0;  // frames.csv's bytes (0 without --dump)
  std::int64_t unconverged = 0;    // steps whose implicit solve did not converge
};
void save_run_state(StateWriter& w, const RunProgress& p, const RunSummary& summary,
                    const std::vector<PvdSeries::Entry>& series);
// StateError when the state is not a run's.
RunProgress load_run_state(StateReader& r, RunSummary& summary,
                           std::vector<PvdSeries::Entry>& series);

// The header of a run's checkpoint: the scene and `settings` of `sim`, the run's CSV, the folder
// it started in (`cwd`), its options (options_json), the thread count, and where it stands:
// the last frame written, the step and the time.
nlohmann::json run_header(const Simulation& sim, const nlohmann::json& settings,
                          const std::string& csv, const std::string& cwd, int frame,
                          nlohmann::json options);

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

}  // namespace apiclab::cli
