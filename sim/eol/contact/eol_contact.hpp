// The step's contact with walls and colliders (Sec 3.5): whether an object's grid reaches a
// plane, and the surface rows of eqs 27-28 with the QP of eq 29 on them.
#pragma once
#include "sim/eol/eol_simulation.hpp"

namespace apiclab::eol {

// Whether any corner of the object's grid box is on or behind a plane (the surface lies inside
// the box, so otherwise no row can exist). The eulerian grid spans the domain: always.
template <class T, int D>
bool EolSimulation<T, D>::may_touch_planes(const EolObject<T, D>& o) const {
  const Mat<T, D> R = o.frame.rotation();
  for (int corner = 0; corner < (1 << D); ++corner) {
    Vec<T, D> y = o.grid.origin;
    for (int a = 0; a < D; ++a)
      if (corner & (1 << a)) y[a] += o.grid.dx * T(o.grid.n[std::size_t(a)] - 1);
    const Vec<T, D> x = R * y + o.frame.p;
    for (const auto& c : planes_)
      if ((x - c.point).dot(c.normal) <= T(0)) return true;
  }
  return false;
}

// Eq 16 for every node with mass, then eqs 27-29: the surface placed now (Algorithm 2), its rows
// against the planes, and the QP on them. The impulse stage calls it only when may_touch_planes.
template <class T, int D>
void EolSimulation<T, D>::impulse_surface_contact(EolObject<T, D>& o, T dt) {
  const std::ptrdiff_t n = std::ptrdiff_t(o.grid.size());
#pragma omp parallel for if (parallel_)
  for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
    const std::size_t i = std::size_t(ii);
    const T m = o.grid.mass[i];
    if (m > T(0)) impulse_update(o.u[i], o.force[i], m, o.x[i], {}, dt);
  }
  place_surface(o);
  const T cell = scene_.solver.eol.contact_cell > 0 ? T(scene_.solver.eol.contact_cell) : o.grid.dx;
  contact_rows_.clear();
  assemble_surface_rows(o.grid, o.surface_y, o.surface.simplex, o.frame.rotation(), o.frame.p,
                        planes_, cell, contact_rows_);
  contact_stats_ = contact_solver_.solve(contact_rows_, o.grid.mass, o.u);
}

}  // namespace apiclab::eol
