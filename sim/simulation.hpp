// The solver seen from outside: one Simulation per pane or run, made at run time from the
// scene's `solver.method` through the method registry (sim/method_registry.hpp). The core below
// is what every solver family has; a family with particle transfers (MPM) adds TransferControls.
#pragma once
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>

#include "sim/measure/diagnostics.hpp"
#include "sim/measure/particle_table.hpp"
#include "sim/scene/scene.hpp"
#include "sim/snapshot.hpp"

namespace apiclab {

class TransferControls;
class StateWriter;
class StateReader;

class Simulation {
 public:
  virtual ~Simulation() = default;
  virtual std::unique_ptr<Simulation> clone() const = 0;

  virtual int dim() const = 0;
  virtual Precision precision() const = 0;
  virtual const SceneDesc& scene() const = 0;
  double time() const { return time_; }
  long steps() const { return steps_; }
  // What a step works on, for progress lines and titles: "25344 particles", "4096 grid nodes".
  virtual std::string model_size() const = 0;

  // One step, the same for every family: choose Δt by the scene's rule (choose_dt), land it on
  // t_limit (land_on_frame), advance and measure (step_fixed_measured), then check the row
  // (check_step). Never past t_limit where the rule lands on frames. Returns the failure
  // (non-finite state, energy blow-up); after a failure the state stays frozen.
  std::optional<Failure> step(double t_limit, DiagnosticsRow* row = nullptr);
  // Steps until time() == t_target; on_step sees every row.
  std::optional<Failure> advance_to(double t_target,
                                    const std::function<void(const DiagnosticsRow&)>& on_step = {});
  // One step of exactly dt, without diagnostics or blow-up checks (benchmarks, tests).
  virtual void step_fixed(double dt) = 0;
  // step_fixed and the diagnostics row of the state it leaves, as step() computes it (MPM sums
  // the particles' share inside its G2P); `bench` times it against step_fixed.
  virtual DiagnosticsRow step_fixed_measured(double dt) {
    step_fixed(dt);
    return measure();
  }

  virtual DiagnosticsRow measure() const = 0;  // energies and momenta of the current state
  virtual double total_mass() const = 0;
  // The energy round-off of a body at rest, ε_T D Σ m c² (sim/mpm/implicit/round_off_floor.hpp):
  // an initial energy below it is no scale for a relative drift (sim/measure/run_summary.hpp).
  virtual double rest_energy_round_off() const { return 0; }
  const std::optional<Failure>& failure() const { return failure_; }

  // Sees every iteration of an iterative solve inside a step (implicit: the Newton iteration,
  // the CG iterations so far, the last Newton residual), so that a long step can show
  // progress. Families without one ignore it.
  using SolverIterationObserver =
      std::function<void(int newton_iteration, int cg_iterations, double residual)>;
  virtual void on_solver_iteration(SolverIterationObserver) {}

  // Whether one step spreads over several threads (OpenMP, above a size threshold). Panes
  // whose steps do not are stepped side by side, one per core (app/lockstep.cpp).
  virtual bool steps_in_parallel() const = 0;

  // Immutable copy of the state for drawing.
  virtual std::shared_ptr<Snapshot> snapshot() const = 0;

  // Checkpoints (app/checkpoint.hpp): whether the family saves its state, and the state itself:
  // time, steps and everything the next step reads, so that a solver made fresh from the same
  // scene and loaded continues bit for bit. load_state throws StateError (sim/state_io.hpp).
  virtual bool checkpoints() const { return false; }
  void save_state(StateWriter& w) const;
  void load_state(StateReader& r);

  // The particle-transfer controls, or nullptr for a family without particle transfers.
  virtual TransferControls* transfers() { return nullptr; }
  virtual const TransferControls* transfers() const { return nullptr; }

 protected:
  Simulation() = default;
  Simulation(const Simulation&) = default;
  Simulation& operator=(const Simulation&) = default;

  // step()'s hooks, in its order. Δt by the scene's time.dt rule, before the landing.
  virtual double choose_dt() = 0;
  // The landing shortened the step to meet a frame time (the dt_limit column's "frame").
  virtual void dt_set_by_frame() {}
  // The step reached t_limit, a frame time: what is drawn or recorded there (EoL's surfaces).
  virtual void reached_frame_time() {}
  // The family's checks of the row (failure_at, energy_failure): the failure, or none.
  virtual std::optional<Failure> check_step(const DiagnosticsRow& row) const = 0;

  // The family's part of save_state and load_state (after time and steps).
  virtual void save_family_state(StateWriter&) const {}
  virtual void load_family_state(StateReader&) {}

  // A snapshot holding what every family fills alike: dim, step, time, the scene's name,
  // domain, colliders and material names, and the failure.
  std::shared_ptr<Snapshot> scene_snapshot() const;

  double time_ = 0;
  long steps_ = 0;
  std::optional<Failure> failure_;
};

// Fixed steps of the reference step on its own particle state.
class ReferenceRun {
 public:
  virtual ~ReferenceRun() = default;
  virtual void step(double dt) = 0;
  virtual bool finite() const = 0;  // every position finite
  virtual std::size_t particle_count() const = 0;
};

// What a solver with particle-grid transfers (PIC/FLIP/APIC/RPIC) offers beyond the core.
class TransferControls {
 public:
  virtual ~TransferControls() = default;
  virtual std::size_t particle_count() const = 0;
  // Switches the transfer scheme live, from the current state (PIC/FLIP drop C_p).
  virtual void set_scheme(Scheme scheme, double flip_alpha) = 0;
  // Fills s.noise (by particle id) with |v_p − PIC-interpolated fresh P2G velocity|, a field
  // for drawing: velocity modes the grid cannot see.
  virtual void fill_velocity_noise(Snapshot& s) const = 0;
  // Particle state as CSV (docs/architecture.md, --dump), one row per particle ordered by id.
  virtual void write_particles_csv(std::ostream& out) const = 0;
  // The same state as named columns, for the other --dump formats (sim/measure/particle_table.hpp).
  virtual ParticleTable particle_table() const = 0;
  // Bytes the grid's node arrays hold (`bench`).
  virtual std::size_t grid_bytes() const = 0;
  // The readable reference step (sim/reference/reference_step.hpp) from a copy of the current
  // particles, in the solver's precision (`bench --reference`).
  virtual std::unique_ptr<ReferenceRun> reference_run() const = 0;
};

// Particles of a solver with particle transfers, 0 for one without (for reports and titles).
inline std::size_t particle_count(const Simulation& sim) {
  const TransferControls* t = sim.transfers();
  return t ? t->particle_count() : 0;
}

// The precision of a family's scalar type T.
template <class T>
constexpr Precision precision_of() {
  return sizeof(T) == 4 ? Precision::single : Precision::dbl;
}

// The Sec 6.7 landing rule for a step of dt with to_frame left to the frame time t_limit: the
// adaptive rules (and the fixed one with time.dt.land_on_frames) cap dt at the frame interval,
// take the whole rest when it is under 1.001 dt and split a rest under 2 dt into halves, so no
// sliver step follows; a fixed step is taken exactly and a frame is the step at or just past it.
struct FrameStep {
  double dt;
  bool by_frame;  // the frame, not the rule, set dt
};
FrameStep land_on_frame(const TimeDesc& time, double dt, double to_frame);

// The failure every solver family reports: "simulation blew up at step N, t = T: QUANTITY DETAIL".
Failure failure_at(long step, double t, const std::string& quantity, const std::string& detail);
// step()'s energy checks, shared by the families: a non-finite total or kinetic energy (named
// `state`, e.g. "particle state"), or kinetic + elastic above `factor` × the energy available.
std::optional<Failure> energy_failure(const DiagnosticsRow& r, long step, double t,
                                      const std::string& state, double factor,
                                      double energy_available);

// Builds the scene's solver (`solver.method`) with its initial state. Throws SceneError for
// scenes it cannot build.
std::unique_ptr<Simulation> make_simulation(const SceneDesc& scene,
                                            Precision precision = Precision::dbl);

}  // namespace apiclab
