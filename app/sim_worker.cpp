#include "app/sim_worker.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>

#include "app/clock.hpp"
#include "sim/method_registry.hpp"
#include "sim/scene/memory_estimate.hpp"

namespace apiclab::gui {
namespace {

constexpr double kPublishInterval = 1.0 / 120;  // while playing: no faster than a fast display
constexpr double kRateWindow = 0.5;             // seconds of wall time per throughput reading
constexpr int kSimulationNice = 10;             // below the window thread's priority

// The window must answer at least once a second (tests/gui/gui_soak.sh), and under a software
// rasteriser a draw of a large 3D scene needs most of a core: left equal, the simulation's
// OpenMP and pane threads took that core from it and frames came late (docs/performance.md).
// Linux keeps a nice value per thread and new threads inherit it, so lowering this thread's
// priority before it starts any covers the threads it starts. The simulation still takes every
// core the window leaves idle.
void yield_to_the_window() {
  const id_t self = id_t(::gettid());
  errno = 0;
  const int nice_now = getpriority(PRIO_PROCESS, self);
  if (errno == 0) setpriority(PRIO_PROCESS, self, std::min(nice_now + kSimulationNice, 19));
}

}  // namespace

void History::push(const DiagnosticsRow& row) {
  tail_.push_back(row);
  if (tail_.size() == kChunk) {
    full_.push_back(std::make_shared<const std::vector<DiagnosticsRow>>(std::move(tail_)));
    tail_ = {};
    tail_.reserve(kChunk);
  }
}

SimWorker::SimWorker() : published_(std::make_shared<Published>()), thread_([this] { run(); }) {}

SimWorker::~SimWorker() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void SimWorker::enqueue(std::function<void()> command) {
  {
    std::lock_guard lock(mutex_);
    queue_.push_back(std::move(command));
    ++queued_;
  }
  wake_.notify_all();
}

void SimWorker::load(SceneDesc scene, std::vector<PaneConfig> panes, Precision precision) {
  enqueue([this, scene = std::move(scene), panes = std::move(panes), precision]() mutable {
    install(std::move(scene), std::move(panes), precision, nullptr);
  });
}

void SimWorker::load_restored(SceneDesc scene, PaneConfig pane, Precision precision,
                              std::function<Restored(Simulation&)> restore) {
  enqueue([this, scene = std::move(scene), pane = std::move(pane), precision,
           restore = std::move(restore)]() mutable {
    install(std::move(scene), {std::move(pane)}, precision, restore);
  });
}

void SimWorker::install(SceneDesc scene, std::vector<PaneConfig> panes, Precision precision,
                        const std::function<Restored(Simulation&)>& restore) {
  auto previous = std::move(panes_);
  auto previous_scene = scene_;
  const auto previous_precision = precision_;
  scene_ = std::make_shared<const SceneDesc>(std::move(scene));
  times_.emplace(*scene_);
  precision_ = precision;
  panes_.clear();
  for (auto& c : panes) panes_.push_back(Pane{c, nullptr, nullptr, {}, nullptr, 0, nullptr});
  try {
    restart_panes();
    if (restore) {
      Pane& p = panes_.front();
      Restored r = restore(*p.sim);
      p.history = {};
      p.history.push(r.last);
      if (r.drift) p.drift = std::make_shared<const DriftRule>(*r.drift);
      p.origin = std::move(r.origin);
      frame_ = std::min<long>(r.frame, times_->frames);
      target_ = times_->time_of(int(frame_));
    }
    error_.clear();
  } catch (const std::exception& e) {  // keep showing what ran before
    error_ = e.what();
    panes_ = std::move(previous);
    scene_ = previous_scene;
    precision_ = previous_precision;
    if (scene_) times_.emplace(*scene_);
    link_lockstep();
  }
}

void SimWorker::restart_panes() {
  // Every pane keeps two simulations (its initial state for resets), all built while the
  // previous panes still run: the whole set is checked before the first is built, as
  // `gui` checks its first scene (app/cmd_gui.cpp), not one simulation at a time.
  MemoryEstimate total;
  for (auto& p : panes_) {
    SceneDesc s = *scene_;
    if (!p.config.method.empty()) s.solver.method = p.config.method;
    const MemoryEstimate e = estimate_memory(s, precision_);
    total.grid_nodes += 2 * e.grid_nodes, total.particles += 2 * e.particles;
    total.bytes_per_node = std::max(total.bytes_per_node, e.bytes_per_node);
    total.bytes_per_particle = std::max(total.bytes_per_particle, e.bytes_per_particle);
  }
  check_memory(total, memory_cap_bytes(*scene_),
               scene_->source + " (" + std::to_string(2 * panes_.size()) + " simulations at once)");
  for (auto& p : panes_) {
    SceneDesc s = p.config.scene ? *p.config.scene : *scene_;  // as compare's panes
    if (!p.config.method.empty()) s.solver.method = p.config.method;
    s.solver.scheme = p.config.scheme;
    s.solver.flip_alpha = p.config.flip_alpha;
    if (p.config.kernel) s.solver.kernel = *p.config.kernel;
    if (p.config.integrator) s.solver.integrator = *p.config.integrator;
    if (const std::string why = scheme_conflict(s.solver); !why.empty() && s.solver.method == "mpm")
      throw SceneError(std::string(key_of(s.solver.scheme)) + " pane: " + why);
    p.initial = make_simulation(s, p.config.precision.value_or(precision_));  // SceneError
  }
  rewind_panes();
}

// Every pane back to its initial particles under its current scheme (PIC/FLIP drop C_p),
// paused at t = 0.
void SimWorker::rewind_panes() {
  for (auto& p : panes_) {
    p.sim = p.initial->clone();
    if (auto* t = p.sim->transfers()) t->set_scheme(p.config.scheme, p.config.flip_alpha);
    p.history = {};
    p.origin = nullptr;
    p.history.push(p.sim->measure());
    p.total_mass = p.sim->total_mass();
    p.drift = std::make_shared<const DriftRule>(DriftRule::of(*p.sim, p.history[0]));
  }
  link_lockstep();
  playing_ = false;
  pending_frames_ = 0;
  target_ = 0;
  frame_ = 0;
  notice_.clear();  // a checkpoint's line belongs to the run before
  // The throughput window restarts with the time: left running, it measured t = 0 against the
  // time before the reset (the GUI soak saw -0.169 sim s / wall s).
  rate_wall0_ = 0, rate_work_ = 0, sim_rate_ = 0, pstep_rate_ = 0;
  ++generation_;
}

void SimWorker::link_lockstep() {
  std::vector<Simulation*> sims;
  for (auto& p : panes_) sims.push_back(p.sim.get());
  lockstep_ = Lockstep(std::move(sims));
}

void SimWorker::play(bool on) {
  enqueue([this, on] {
    playing_ = on && !panes_.empty();
    rate_wall0_ = 0;  // the throughput window starts now, not before the pause
    rt_wall0_ = now_seconds();
    rt_sim0_ = target_;
  });
}

void SimWorker::step_frame() {
  enqueue([this] {
    playing_ = false;
    if (!panes_.empty()) ++pending_frames_;
  });
}

void SimWorker::reset() {
  enqueue([this] { rewind_panes(); });
}

void SimWorker::set_realtime(bool on) {
  enqueue([this, on] {
    realtime_ = on;
    rt_wall0_ = now_seconds();
    rt_sim0_ = target_;
  });
}

void SimWorker::set_scheme(std::size_t pane, Scheme scheme, double flip_alpha) {
  enqueue([this, pane, scheme, flip_alpha] {
    if (pane >= panes_.size()) return;
    SolverDesc wanted = panes_[pane].sim->scene().solver;
    wanted.scheme = scheme;
    if (const std::string why = scheme_conflict(wanted); !why.empty() && wanted.method == "mpm") {
      error_ = std::string(key_of(scheme)) + ": " + why;  // the pane keeps its scheme
      return;
    }
    panes_[pane].config.scheme = scheme;
    panes_[pane].config.flip_alpha = flip_alpha;
    if (auto* t = panes_[pane].sim->transfers()) t->set_scheme(scheme, flip_alpha);
  });
}

void SimWorker::with_pane(std::size_t pane, std::function<std::string(const PaneView&)> f) {
  enqueue([this, pane, f = std::move(f)] {
    if (pane >= panes_.size()) return;
    const Pane& p = panes_[pane];
    try {
      notice_ = f(PaneView{*p.sim, p.history, frame_, p.origin});
      error_.clear();
    } catch (const std::exception& e) {
      error_ = e.what();
      notice_.clear();
    }
  });
}

void SimWorker::set_noise(bool on) {
  enqueue([this, on] { noise_ = on; });
}

std::shared_ptr<const Published> SimWorker::latest() const {
  std::lock_guard lock(mutex_);
  return published_;
}

void SimWorker::sync(std::optional<long> frames_done) {
  std::unique_lock lock(mutex_);
  const std::uint64_t wanted = queued_;
  // A worker with nothing left to do (paused, end of scene, every pane failed) ends the wait.
  done_.wait(lock, [&] {
    return stop_ || (ran_ >= wanted &&
                     (!frames_done || published_->frame >= *frames_done || !published_->busy));
  });
}

bool SimWorker::run_commands() {
  std::deque<std::function<void()>> batch;
  {
    std::lock_guard lock(mutex_);
    batch.swap(queue_);
  }
  for (auto& c : batch) c();
  return !batch.empty();
}

void SimWorker::run() {
  yield_to_the_window();
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      const bool busy = playing_ || pending_frames_ > 0;
      if (!busy) wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
      if (stop_) return;
    }
    if (run_commands()) {
      publish();
      std::lock_guard lock(mutex_);
      ran_ = queued_ - queue_.size();
      done_.notify_all();
    }
    if (playing_ || pending_frames_ > 0) advance();
  }
}

void SimWorker::advance() {
  bool at_target = lockstep_.all_reached(target_);
  if (at_target) {  // start the next frame, or stop at the scene's end
    if (frame_ >= times_->frames) {
      playing_ = false;
      pending_frames_ = 0;
      publish();
      return;
    }
    const double next = times_->time_of(int(frame_) + 1);
    if (realtime_ && pending_frames_ == 0) {  // wait for the wall clock, waking on commands
      const double due = rt_wall0_ + (next - rt_sim0_);
      const double now = now_seconds();
      if (due > now + 1e-4) {
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, std::chrono::duration<double>(due - now),
                       [&] { return stop_ || !queue_.empty(); });
        return;
      }
      if (now - due > 0.25) {  // the solver cannot keep up: drop the debt instead of sprinting
        rt_wall0_ = now;
        rt_sim0_ = target_;
      }
    }
    target_ = next;
  }
  // Lockstep rounds, one step per pane, so every pane reaches the frame time together.
  const double t0 = now_seconds();
  double particle_steps = 0;
  const auto record = [&](std::size_t k, const DiagnosticsRow& row) {
    panes_[k].history.push(row);
  };
  for (double done = 1; done > 0;) {
    done = lockstep_.step_round(target_, record);
    particle_steps += done;
    std::lock_guard lock(mutex_);
    if (!queue_.empty() || stop_) break;  // commands first; the frame resumes afterwards
  }
  const double t1 = now_seconds();
  rate_work_ += particle_steps;
  at_target = lockstep_.all_reached(target_);
  if (at_target) {
    ++frame_;
    if (pending_frames_ > 0) --pending_frames_;
    if (lockstep_.all_failed()) playing_ = false, pending_frames_ = 0;
  }
  // Throughput over windows of wall time, so the readout is steady.
  if (rate_wall0_ == 0) rate_wall0_ = t0, rate_sim0_ = target_;
  if (t1 - rate_wall0_ >= kRateWindow) {
    double sim_now = 0;
    for (auto& p : panes_) sim_now = std::max(sim_now, p.sim->time());
    sim_rate_ = (sim_now - rate_sim0_) / (t1 - rate_wall0_);
    pstep_rate_ = rate_work_ / (t1 - rate_wall0_);
    rate_wall0_ = t1, rate_sim0_ = sim_now, rate_work_ = 0;
  }
  const bool busy = playing_ || pending_frames_ > 0;
  if (at_target && (!busy || t1 - last_publish_ >= kPublishInterval)) publish();
}

void SimWorker::publish() {
  auto out = std::make_shared<Published>();
  out->scene = scene_;
  for (auto& p : panes_) {
    PaneState s;
    s.config = p.config;
    if (s.config.method.empty() && scene_) s.config.method = scene_->solver.method;  // labels
    auto snapshot = p.sim->snapshot();
    if (noise_ && p.sim->transfers()) p.sim->transfers()->fill_velocity_noise(*snapshot);
    s.snapshot = snapshot;
    s.history = p.history;
    s.drift = p.drift;
    s.total_mass = p.total_mass;
    s.failure = p.sim->failure();
    out->panes.push_back(std::move(s));
  }
  out->playing = playing_;
  out->busy = playing_ || pending_frames_ > 0;
  out->realtime = realtime_;
  out->noise = noise_;
  out->sim_seconds_per_wall_second = sim_rate_;
  out->particle_steps_per_second = pstep_rate_;
  out->frame = frame_;
  out->generation = generation_;
  out->error = error_;
  out->notice = notice_;
  last_publish_ = now_seconds();
  std::lock_guard lock(mutex_);
  published_ = std::move(out);
  done_.notify_all();
}

}  // namespace apiclab::gui
