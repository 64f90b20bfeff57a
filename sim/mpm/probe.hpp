// A hand on the MPM solver's phases, for the tests and the round-trip probe
// (sim/mpm/roundtrip.cpp): read and write the particle state and the grid, step one phase (sort,
// P2G, grid update, boundary conditions, G2P), transfer once from a given grid field, read the
// grid's moments, and tell the solver that its particles were written (the Python module,
// python/state.cpp). MpmSimulation keeps all of these private; the probe is its friend and adds no
// work to a step.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sim/mpm/mpm.hpp"

namespace apiclab {

// Σ m_i, Σ m_i v_i and Σ x_i × m_i v_i over the grid nodes.
struct GridMoments {
  double mass = 0;
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero(), angular_momentum = Eigen::Vector3d::Zero();
};

// Sim is MpmSimulation<T, D>, or const MpmSimulation<T, D> to read only: MpmProbe(sim).phase().
template <class Sim>
class MpmProbe {
 public:
  using T = typename Sim::Scalar;
  static constexpr int D = Sim::Dim;
  explicit MpmProbe(Sim& sim) : sim_(sim) {}

  // The state. Writable particles may change F: the solver drops its cached stress and energy.
  decltype(auto) particles() const { return sim_.particles(); }
  decltype(auto) grid() const { return sim_.grid(); }
  decltype(auto) solver() const { return sim_.solver(); }

  // After particles() was written from outside between steps (the Python module): positions
  // may have left their blocks, so the next step sorts them again; the blow-up check's energy
  // and the implicit solve's velocity scale are the written state's, as setup takes the first's.
  void particles_written(bool moved) const {
    if (moved) sim_.blocks_.must_sort();
    sim_.stress_of_current_F_ = false;
    sim_.energy_ref_ = sim_.energy_reference();
    const DiagnosticsRow now = sim_.measure();
    sim_.velocity_scale_ = std::sqrt(2 * std::max(now.kinetic + now.elastic, 0.0) /
                                     std::max(sim_.total_mass(), 1e-300));
  }

  // The phases, in step_fixed's order (sim/mpm/mpm_step.hpp).
  void sort_particles() const { sim_.sort_particles(); }
  void clear_grid() const { sim_.clear_grid(); }  // zeroes the P2G accumulator
  // Eqs 24-25: m_i and (m v)_i (+ eq 34 at F^n when with_forces).
  void particles_to_grid(bool with_forces) const { sim_.particles_to_grid(with_forces); }
  void grid_velocity_update(T dt) const { sim_.grid_velocity_update(dt); }  // eq 29
  void apply_boundary_conditions() const { sim_.apply_boundary_conditions(); }
  // Eqs 37-40, or the scheme's variant; with sums, also the row's sums over the new state.
  void grid_to_particles(T dt, ParticleSums* sums = nullptr) const {
    sim_.grid_to_particles(dt, sums);
  }

  // The Sec 6.8 round trip from `field` (one velocity per grid node): v_i^n = ṽ_i = field_i, G2P
  // at Δt = 0 (x_p and F_p stay), P2G, v_i = (mv)_i / m_i (eqs 24, 26). The nodes' masses must
  // be those of a P2G of these particles (XPIC's grid passes read them).
  void transfer_once(const std::vector<Vec<T, D>>& field) const {
    auto& g = sim_.grid();
    for (std::size_t i = 0; i < g.size(); ++i) g.velocity[i] = g.velocity_new[i] = field[i];
    sim_.grid_to_particles(T(0));
    sim_.clear_grid();
    sim_.particles_to_grid(false);
    sim_.grid_velocity_update(T(0));  // massless nodes get v_i = 0
  }

  // After the grid update: updated = false gives v^n, true gives ṽ.
  GridMoments grid_moments(bool updated) const {
    GridMoments m;
    for (const auto mi : sim_.grid().mass) m.mass += double(mi);
    sim_.grid_momentum(updated, m.momentum, m.angular_momentum);
    return m;
  }
  Eigen::Vector3d total_force() const { return sim_.total_force(); }  // Σ_i f_i (Sec 5.2)
  // The parallel P2G's invariant (BlockPartition::conflict): "" or what breaks it.
  std::string partition_conflict() const { return sim_.partition_conflict(); }
  // The row's particle sums by measure()'s own pass.
  ParticleSums particle_sums() const { return sim_.particle_sums(); }
  // Bytes held by the particles, the grid and the per-scheme arrays; XPIC(m)'s node arrays.
  std::size_t state_bytes() const { return sim_.state_bytes(); }
  std::size_t xpic_capacity() const { return sim_.xpic_capacity(); }

 private:
  Sim& sim_;
};

}  // namespace apiclab
