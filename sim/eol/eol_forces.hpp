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
  // Elasticity in frame axes, then per node (in the same parallel region) rotated to world axes
  // with gravity and f_qvv added.
  o.elastic.compute(o.grid, materials_, o.force, parallel_, [&](std::size_t i) {
    const T m = o.grid.mass[i];
    o.force[i] = R * o.force[i] + m * g;
    if (lagrangian_ && m > T(0))
      o.force[i] +=
          quadratic_velocity_force<T, D>(m, o.frame.omega, o.r[i], Vec<T, D>(R * o.grid.v[i]));
  });
}

// The forces of the state now; their Ψ is the diagnostics' elastic energy (elastic_energy).
template <class T, int D>
void EolSimulation<T, D>::forces_ahead() {
  for (auto& o : objects_) forces(o);
  forces_ready_ = true;
}

}  // namespace apiclab::eol
