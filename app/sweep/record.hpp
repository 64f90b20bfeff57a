// One sweep run, recorded by `apiclab run SCENE ... --record DIR` (a separate process, so timed
// runs share no threads): DIR/diagnostics.csv, DIR/frames.bin (particle positions and energies
// at frame times) and DIR/result.json (cost, outcome, conservation, velocity noise). Everything is
// written under DIR.tmp-PID (DIR.partial with checkpoints) and renamed to DIR at the end, so a
// reader never sees a half-written run and a killed run leaves no DIR.
#pragma once
#include <stdexcept>
#include <string>

#include "app/cli.hpp"
#include "sim/measure/metrics.hpp"

namespace apiclab::cli {
struct CheckpointOptions;  // app/checkpoint.hpp
}

namespace apiclab::sweep {

// What result.json holds.
struct RunRecord {
  std::string id;
  long particles = 0, steps = 0, frames = 0;
  double step_wall_s = 0;   // inside the steps: the cost the charts use
  double total_wall_s = 0;  // the whole process: building, measuring, writing included
  double cpu_s = 0, peak_rss_mb = 0;
  double newton_iters = 0, cg_iters = 0;
  long unconverged_steps = 0;
  bool blew_up = false;
  long fail_step = 0;
  double fail_t = 0;
  std::string fail_quantity, fail_message;
  metrics::Conservation conservation;
  double noise = 0;  // max over frames of RMS |v_p − v_PIC| / RMS |v_p| (the larger of t = 0, t)
};

// `run --record DIR`: runs the scene of `o` and writes the record. Returns 0 whenever the run was
// recorded (a blow-up is a result); a bad scene throws SceneError before anything is written.
// With checkpoints on, the unfinished record grows in DIR.partial/ with its checkpoint (in
// DIR.partial/checkpoint/, or --checkpoint-dir): the same command run again resumes from it.
int record_run(const cli::RunOptions& o, const std::string& dir,
               const cli::CheckpointOptions& checkpoint);

// Whether DIR holds a complete record.
bool record_complete(const std::string& dir);
// A run whose process ended without a record (a configuration `run` refuses, exit 2; or a
// crash): DIR/refused.txt holds its exit status and the last line of its log. A later record
// of the run replaces DIR whole.
void write_refusal(const std::string& dir, int exit_status, const std::string& cause);
// The refusal's text, "exit 2: apiclab: ...", or "" when DIR holds none.
std::string read_refusal(const std::string& dir);
// Reads DIR/result.json; throws std::runtime_error naming the file.
RunRecord read_record(const std::string& dir);
// A frames.bin of the older format, positions as 32-bit floats whatever the run's precision:
// read, its distances would mix precisions, so it is refused (the runner records it again).
struct OldFramesError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// Reads DIR/frames.bin (positions at the run's precision, widened to double); throws
// OldFramesError for the older float format and std::runtime_error naming the file otherwise.
metrics::RunFrames read_frames(const std::string& dir);
// Whether DIR/frames.bin is not of the older float format (true when there is none).
bool frames_current(const std::string& dir);

}  // namespace apiclab::sweep
