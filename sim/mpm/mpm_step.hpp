// One step: the phases in the paper's order, and step()'s failure checks (the skeleton is
// Simulation::step).
#pragma once
#include <cmath>
#include <sstream>

#include "sim/mpm/kernel_dispatch.hpp"
#include "sim/mpm/mpm.hpp"

namespace apiclab {

// Block sort for the coloured parallel P2G (sim/mpm/block_partition.hpp).
template <class T, int D>
void MpmSimulation<T, D>::sort_particles() {
  if (blocks_.sort(p_, scratch_, grid_, boundary_, scene_.solver.kernel, parallel_worthwhile())) {
    rebuild_index_of_id();
    if (stress_of_current_F_) {  // the stress follows its particles; the energy sum stands
      const double energy = particle_elastic_energy_;
      compute_stress();
      particle_elastic_energy_ = energy;
    }
  }
}

template <class T, int D>
void MpmSimulation<T, D>::step_fixed(double dt) {
  step_fixed_summing(dt, nullptr);
}

template <class T, int D>
DiagnosticsRow MpmSimulation<T, D>::step_fixed_measured(double dt) {
  ParticleSums sums;
  if (!step_fixed_summing(dt, &sums)) return measure();
  return scene_.solver.ledger ? with_ledger(row_of(sums)) : row_of(sums);
}

template <class T, int D>
bool MpmSimulation<T, D>::step_fixed_summing(double dt, ParticleSums* sums) {
  // A non-finite position would index the grid out of range: the state stays frozen, and
  // step() (or the caller of step_fixed, through measure()) reports it.
  if (non_finite_) return false;
  const bool ledger = sums && scene_.solver.ledger;       // sim/mpm/stage_ledger.hpp
  if (boundary_.moving()) boundary_.move_to(time_ + dt);  // moving planes where the step ends
  sort_particles();
  if (boundary_.moving()) blocks_.collect_constraints(grid_, boundary_);
  clear_grid();
  if (!uses_implicit_solve()) {
    particles_to_grid(true);  // forces at F^n, fused into the transfer
    if (!mesh_.empty())
      with_kernel(scene_.solver.kernel, [&](auto kernel) { add_mesh_forces<decltype(kernel)>(); });
    grid_velocity_update(T(dt));
    last_solve_ = NewtonCgReport{};
  } else {
    particles_to_grid(false);
    with_kernel(scene_.solver.kernel,
                [&](auto kernel) { implicit_velocity_update<decltype(kernel)>(T(dt)); });
  }
  if (ledger) ledger_grid();
  apply_boundary_conditions(ledger);
  grid_to_particles(T(dt), sums, ledger);
  if (!p_.fp_inv.empty()) plastic_flow();
  stress_of_current_F_ = false;
  // An explicit step computes the next step's stress now: its pass also sums the elastic energy
  // that measure() reports after this step, so the diagnostics need no decomposition of their own.
  if (!uses_implicit_solve() && !non_finite_) compute_stress();
  time_ += dt;
  ++steps_;
  return true;
}

// step()'s checks (Simulation::step): the implicit solve's convergence, a frozen state, the energy.
template <class T, int D>
std::optional<Failure> MpmSimulation<T, D>::check_step(const DiagnosticsRow& r) const {
  if (!last_solve_.converged && scene_.solver.stop_on_nonconvergence) {
    std::ostringstream d;
    d << "did not converge in " << last_solve_.newton_iterations << " Newton iterations (residual "
      << last_solve_.residual << ", tolerance " << last_solve_.tolerance << ")";
    return failure_at(steps_, time_, "implicit solve", d.str());
  }
  if (non_finite_)  // a frozen state whose energies may still read finite
    return failure_at(steps_, time_, "particle state", "became non-finite (NaN or Inf)");
  return energy_failure(r, steps_, time_, "particle state", scene_.solver.blowup_energy_factor,
                        energy_ref_);
}

}  // namespace apiclab
