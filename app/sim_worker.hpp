// The GUI's simulation thread (docs/architecture.md, Threads): owns one Simulation per pane,
// advances them in lockstep (app/lockstep.hpp) to the frame times of app/frame_loop.hpp, the
// last on time.end, and publishes immutable state the GUI only reads. Commands arrive through
// a queue; nothing here touches a window, so tests drive it headless.
#pragma once
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/frame_loop.hpp"
#include "app/lockstep.hpp"
#include "sim/measure/run_summary.hpp"
#include "sim/simulation.hpp"

namespace apiclab::gui {

struct PaneOrigin;  // app/gui/pane_checkpoint.hpp: the run a pane was opened from

// What one pane runs: the scheme switches live; method, kernel and integrator need a restart.
struct PaneConfig {
  Scheme scheme = Scheme::apic;  // MPM panes only
  double flip_alpha = 1.0;
  std::optional<KernelType> kernel;      // empty: the scene's
  std::optional<Integrator> integrator;  // empty: the scene's
  std::string method = "";               // solver.method ("mpm", "eol", ...); empty: the scene's
  // A pane with a scene of its own (a sweep run beside its reference, app/sweep/open.hpp):
  // it replaces the worker's scene for this pane; the frame times stay the worker scene's.
  std::shared_ptr<const SceneDesc> scene;
  std::optional<Precision> precision;  // empty: the worker's
  std::string label;                   // shown before the scheme in the pane's title
};

// Diagnostics rows since the start, append-only in immutable chunks: publishing shares the
// full chunks and copies only the short tail, so long runs cost nothing per frame.
class History {
 public:
  static constexpr std::size_t kChunk = 256;
  void push(const DiagnosticsRow& row);
  std::size_t size() const { return full_.size() * kChunk + tail_.size(); }
  bool empty() const { return size() == 0; }
  const DiagnosticsRow& operator[](std::size_t i) const {
    return i / kChunk < full_.size() ? (*full_[i / kChunk])[i % kChunk]
                                     : tail_[i - full_.size() * kChunk];
  }
  const DiagnosticsRow& back() const { return (*this)[size() - 1]; }

 private:
  std::vector<std::shared_ptr<const std::vector<DiagnosticsRow>>> full_;
  std::vector<DiagnosticsRow> tail_;
};

struct PaneState {
  PaneConfig config;
  std::shared_ptr<const Snapshot> snapshot;
  History history;                         // rows[0] is the initial state (step 0)
  std::shared_ptr<const DriftRule> drift;  // drift from rows[0], by run's rule
  double total_mass = 0;                   // of the pane's particles [kg]
  std::optional<Failure> failure;
};

// Everything the GUI shows of the worker, published as one immutable value.
struct Published {
  std::shared_ptr<const SceneDesc> scene;  // null until a scene loaded
  std::vector<PaneState> panes;
  bool playing = false, realtime = false, noise = false;
  bool busy = false;  // playing, or single frames still to compute
  double sim_seconds_per_wall_second = 0, particle_steps_per_second = 0;
  long frame = 0;                // frames completed since the last reset
  std::uint64_t generation = 0;  // bumps on every load or reset (GUI re-frames cameras)
  std::string error;             // the last command that failed, one line
  std::string notice;            // what the last with_pane command did, one line
};

// A pane as with_pane hands it over on the worker thread, between two steps.
struct PaneView {
  const Simulation& sim;
  const History& history;                           // rows since the pane started (or was opened)
  long frame;                                       // frames completed
  const std::shared_ptr<const PaneOrigin>& origin;  // null unless opened from a checkpoint
};

// What a pane restored from a run's checkpoint starts from (load_restored).
struct Restored {
  long frame = 0;                  // frames the run had completed
  std::optional<DriftRule> drift;  // the run's: from its first row
  DiagnosticsRow last;             // the run's last row: the pane's history starts there
  std::shared_ptr<const PaneOrigin> origin;
};

class SimWorker {
 public:
  SimWorker();
  ~SimWorker();  // stops and joins the thread
  SimWorker(const SimWorker&) = delete;
  SimWorker& operator=(const SimWorker&) = delete;

  // Commands: queued, run on the worker in order.
  void load(SceneDesc scene, std::vector<PaneConfig> panes, Precision precision = Precision::dbl);
  void play(bool on);
  void step_frame();  // one frame (to the next frame time) then pause
  void reset();       // every pane back to its initial particles, schemes kept
  void set_realtime(bool on);
  void set_scheme(std::size_t pane, Scheme scheme, double flip_alpha);
  void set_noise(bool on);  // snapshots carry FLIP's velocity noise (costs one P2G)
  // Runs `f` on the worker thread with pane `pane` as it stands (a checkpoint of it); what it
  // returns becomes Published::notice, the text of what it throws Published::error.
  void with_pane(std::size_t pane, std::function<std::string(const PaneView&)> f);
  // load() of one pane whose state `restore` then sets (a run's checkpoint), paused there; a
  // throw leaves what ran before, as a failed load does.
  void load_restored(SceneDesc scene, PaneConfig pane, Precision precision,
                     std::function<Restored(Simulation&)> restore);

  std::shared_ptr<const Published> latest() const;
  // Blocks until every command queued so far has run and, when `frames_done` is given,
  // until at least that many frames are complete (tests, screenshots).
  void sync(std::optional<long> frames_done = std::nullopt);

 private:
  struct Pane {
    PaneConfig config;
    std::unique_ptr<Simulation> initial, sim;
    History history;
    std::shared_ptr<const DriftRule> drift;
    double total_mass = 0;
    std::shared_ptr<const PaneOrigin> origin;
  };
  void install(SceneDesc scene, std::vector<PaneConfig> panes, Precision precision,
               const std::function<Restored(Simulation&)>& restore);
  void enqueue(std::function<void()> command);
  void run();
  bool run_commands();  // returns whether any ran
  void advance();       // steps toward the frame target, returning early when commands wait
  void publish();
  void restart_panes();
  void rewind_panes();
  void link_lockstep();  // after the panes' simulations changed

  // Shared with the GUI thread, under mutex_.
  mutable std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<std::function<void()>> queue_;
  std::uint64_t queued_ = 0, ran_ = 0;
  std::shared_ptr<const Published> published_;
  bool stop_ = false;

  // Owned by the worker thread alone.
  std::shared_ptr<const SceneDesc> scene_;
  Precision precision_ = Precision::dbl;
  std::optional<FrameTimes> times_;  // of scene_
  std::vector<Pane> panes_;
  Lockstep lockstep_;  // over panes_[k].sim
  bool playing_ = false, realtime_ = false, noise_ = false;
  int pending_frames_ = 0;
  double target_ = 0;  // time of the frame being computed
  long frame_ = 0;
  std::uint64_t generation_ = 0;
  std::string error_, notice_;
  double rt_wall0_ = 0, rt_sim0_ = 0;                      // real-time schedule origin
  double rate_wall0_ = 0, rate_sim0_ = 0, rate_work_ = 0;  // throughput window
  double sim_rate_ = 0, pstep_rate_ = 0, last_publish_ = -1;

  std::thread thread_;  // last: starts after everything above exists
};

}  // namespace apiclab::gui
