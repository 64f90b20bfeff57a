// The solver seen from outside: one Simulation per pane or run, chosen at run time by
// dimension and precision (the implementation, MpmSimulation<T, D>, is a template).
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "diagnostics.hpp"
#include "scene.hpp"
#include "snapshot.hpp"

namespace apiclab {

class Simulation {
 public:
  virtual ~Simulation() = default;
  virtual std::unique_ptr<Simulation> clone() const = 0;

  virtual int dim() const = 0;
  virtual Precision precision() const = 0;
  virtual const SceneDesc& scene() const = 0;
  virtual std::size_t particle_count() const = 0;
  virtual double time() const = 0;
  virtual long steps() const = 0;

  // Takes one step with the scene's time-step rule, never past t_limit (steps land exactly on
  // frame times with the Sec 6.7 sliver rule). Returns the step's diagnostics row, or the
  // failure (non-finite state, energy blow-up); after a failure the state stays frozen.
  virtual std::optional<Failure> step(double t_limit, DiagnosticsRow* row = nullptr) = 0;
  // Steps until time() == t_target; on_step sees every row.
  std::optional<Failure> advance_to(double t_target,
                                    const std::function<void(const DiagnosticsRow&)>& on_step = {});
  // One step of exactly dt, without diagnostics or blow-up checks (benchmarks, tests).
  virtual void step_fixed(double dt) = 0;

  virtual DiagnosticsRow measure() const = 0;
  virtual double total_mass() const = 0;  // energies and momenta of the current state
  virtual const std::optional<Failure>& failure() const = 0;

  // Switches the transfer scheme live, from the current state (PIC/FLIP drop C_p).
  virtual void set_scheme(Scheme scheme, double flip_alpha) = 0;

  // Immutable copy for drawing; with_noise adds |v_p − PIC-interpolated fresh P2G velocity|.
  virtual std::shared_ptr<Snapshot> snapshot(bool with_noise = false) const = 0;
  // Particle state as CSV (DESIGN.md, --dump), one row per particle ordered by id.
  virtual void write_particles_csv(std::ostream& out) const = 0;
};

// Scenes with fewer particles than this run their loops on one thread (an OpenMP region
// costs more than it saves there). Tests set it to 0 to exercise the parallel paths.
inline std::size_t& parallel_min_particles() {
  static std::size_t n = 20000;
  return n;
}

// Builds the initial particles from the scene. Throws SceneError for scenes it cannot build.
std::unique_ptr<Simulation> make_simulation(const SceneDesc& scene,
                                            Precision precision = Precision::dbl);

}  // namespace apiclab
