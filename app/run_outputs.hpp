// What a run leaves next to its numbers so that a person (or a script) can tell later what
// produced them: the settings as a sidecar `NAME.csv.json` beside every diagnostics CSV (the
// CSV itself stays plain, docs/architecture.md), the real time of every frame (a fixed --dt is
// taken exactly, so frame f is the step at or just past f/fps), and `run --summary FILE.json`.
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/output_file.hpp"
#include "app/version.hpp"
#include "sim/measure/diagnostics.hpp"
#include "sim/measure/run_summary.hpp"
#include "sim/scene/scene.hpp"
#include "sim/snapshot.hpp"

namespace apiclab {

// Every setting a run used: scene (name, file), solver choices, time-step rule, precision, the
// --set overrides given, and every numeric scene parameter with its value (registry keys,
// sim/scene/parameters.hpp), so the run can be repeated from it.
nlohmann::json run_settings(const SceneDesc& scene, Precision precision,
                            const std::vector<std::string>& overrides);

// One diagnostics row as text, newline included: a RowFile writes and checks it as a whole.
std::string diagnostics_row_text(const DiagnosticsRow& r);

// Writes `csv_path`.json whole: {"csv": the CSV's file name, "settings": settings}. Throws
// WriteError naming the file when it cannot be written.
void write_csv_sidecar(const std::string& csv_path, const nlohmann::json& settings);

// DIR/frames.csv: `frame,t,step`, the real time of each written frame and the step count it
// was reached at; with several panes (compare) one step column per pane, `step_<name>`. A row
// is written whole and flushed when its frame's files are complete (WriteError otherwise).
class FrameIndex {
 public:
  FrameIndex() = default;
  explicit FrameIndex(const std::string& dir, const std::vector<std::string>& panes = {});
  // A resumed run's index: DIR/frames.csv continued after its first `keep` bytes.
  FrameIndex(const std::string& dir, std::size_t keep);
  bool open() const { return out_.is_open(); }
  std::size_t size() const { return out_.size(); }
  void add(int frame, double t, const std::vector<long>& steps);

 private:
  RowFile out_;
};

// One line about how steps meet frames, for the start of a run ("" when nothing to say): a
// fixed step longer than a frame repeats frames; a fixed step that does not divide the frame
// interval puts frames just past their times; the adaptive rules land on frame times.
std::string time_step_note(const SceneDesc& scene);

// "dt min/median/max = a / b / c s" for the end-of-run line.
std::string dt_stats_text(const RunSummary::DtStats& dt);

struct RunCosts {
  double wall_seconds = 0, cpu_seconds = 0;
  std::size_t particles = 0;
  long long steps_timed = 0;  // the steps this process took in wall_seconds (a resume's own)
};

// The JSON of `run --summary`: settings, steps, final time, dt statistics, costs, drifts
// (|ΔL| relative or absolute, labelled) and the failure when there was one.
nlohmann::json run_summary_json(const SceneDesc& scene, const nlohmann::json& settings,
                                const RunSummary& summary, double final_time, const RunCosts& c,
                                const std::optional<Failure>& failure);

// Process CPU seconds, all threads.
double cpu_seconds();

}  // namespace apiclab
