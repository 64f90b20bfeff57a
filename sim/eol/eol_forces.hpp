// The step's forces (eq 12): elasticity in frame axes, rotated to world axes with gravity and the
// frame's f_qvv added, per object.
#pragma once
#include "sim/eol/eol_simulation.hpp"

namespace apiclab::eol {

template <class T, int D>
void EolSimulation<T, D>::compute_forces(EolObject<T, D>& o) {
  forces_ready_ = false;
  forces(o);
}

template <class T, int D>
void EolSimulation<T, D>::forces(EolObject<T, D>& o) {
  StageTimer timer{stages_.forces};
  const Mat<T, D> R = o.frame.rotation();
  Vec<T, D> g;
  for (int a = 0; a < D; ++a) g[a] = T(scene_.gravity[std::size_t(a)]);
  // Elasticity (and Kelvin–Voigt damping) in frame axes, then per node (in the same parallel
  // region) rotated to world axes with gravity and f_qvv added.
  const bool viscous = ViscousForces<T, D>::any(materials_);
  if (viscous) o.viscous.compute(o.grid, materials_, parallel_);
  o.elastic.compute(
      o.grid, materials_, o.force, parallel_,
      [&](std::size_t i) {
        const T m = o.grid.mass[i];
        if (viscous) o.force[i] += o.viscous.force[i];
        o.force[i] = R * o.force[i] + m * g;
        if (lagrangian_ && m > T(0))
          o.force[i] +=
              quadratic_velocity_force<T, D>(m, o.frame.omega, o.r[i], Vec<T, D>(R * o.grid.v[i]));
      },
      o.plastic.empty() ? nullptr : &o.plastic);
}

// The forces of the state now; their Ψ is the diagnostics' elastic energy (elastic_energy).
template <class T, int D>
void EolSimulation<T, D>::forces_ahead() {
  for (auto& o : objects_) forces(o);
  forces_ready_ = true;
}

// Backward Euler's forces for the step (implicit_elasticity.hpp), each object's solve from the
// forces of the state now, then held to the step's contact rows (implicit_contact.hpp); the
// tolerances are the MPM family's solver keys.
template <class T, int D>
void EolSimulation<T, D>::implicit_forces(double dt) {
  StageTimer timer{stages_.forces};
  const SolverDesc& sv = scene_.solver;
  const ImplicitSettings settings{sv.newton_tolerance,  sv.newton_max_iterations, sv.cg_tolerance,
                                  sv.cg_max_iterations, max_wave_speed_,          0.0};
  implicit_report_ = NewtonCgReport{};
  for (auto& o : objects_) {
    std::vector<Vec<T, D>>& rigid = o.implicit.frame_velocity();
    rigid.assign(o.grid.size(), Vec<T, D>::Zero());
    if (lagrangian_)
      for (std::size_t i = 0; i < o.grid.size(); ++i)
        rigid[i] = o.frame.nu + spin_cross<T, D>(o.frame.omega, o.r[i]);
    o.implicit.begin(o.grid, materials_, o.frame.rotation(), o.u, o.force, T(dt), settings);
    const NewtonCgReport r = o.implicit.minimise();
    implicit_report_.newton_iterations += r.newton_iterations;
    implicit_report_.cg_iterations += r.cg_iterations;
    implicit_report_.converged = implicit_report_.converged && r.converged;
    if (r.residual / r.tolerance >=
        implicit_report_.residual / std::max(implicit_report_.tolerance, 1e-300)) {
      implicit_report_.residual = r.residual;
      implicit_report_.tolerance = r.tolerance;
    }
  }
  implicit_contact();
  for (auto& o : objects_) o.implicit.finish(o.u, o.force);
}

}  // namespace apiclab::eol
