// The explicit grid update (eqs 26 and 29 at λ = 0) and the boundary conditions on ṽ.
#pragma once
#include <cmath>

#include "sim/mpm/mpm.hpp"

namespace apiclab {

// The accumulator, free after P2G, is reused as G2P's packed [ṽ_i, v_i^n] per node (see
// Grid::node_lanes): one contiguous load per node in the gather.
template <class T, int D>
void MpmSimulation<T, D>::pack_velocities() {
  auto* acc = grid_.node_lanes.data();
  for_each_box_node([&](std::size_t i) {
    using NodeLanes = typename Grid<T, D>::NodeLanes;
    const Vec<T, D>& vt = grid_.velocity_new[i];
    const Vec<T, D>& vn = grid_.velocity[i];
    if constexpr (D == 2)
      acc[i] = NodeLanes::of(vt[0], vt[1], vn[0], vn[1]);
    else
      acc[i] = NodeLanes::of(vt[0], vt[1], vt[2], vn[0], vn[1], vn[2]);
  });
}

// Whether node i has mass: the nodes the grid update and the implicit solve move (the others'
// velocity is zero since P2G).
template <class T, int D>
inline bool MpmSimulation<T, D>::has_mass(std::size_t i) const {
  return grid_.mass[i] > T(0);
}

// ṽ_i = v_i + Δt (f_i / m_i + g) (eq 29 with λ = 0). Also measures the
// grid's kinetic energy and top speed, which the diagnostics and the two-step dt rule read.
template <class T, int D>
void MpmSimulation<T, D>::grid_velocity_update(T dt) {
  Vec<T, D> g;
  for (int a = 0; a < D; ++a) g[a] = T(scene_.gravity[a]);
  const auto& box_rows = blocks_.box_rows();
  const std::ptrdiff_t rows = std::ptrdiff_t(box_rows.size());
  double kinetic = 0, vmax2 = 0;
#pragma omp parallel for schedule(static) reduction(+ : kinetic) reduction(max : vmax2) if (parallel_worthwhile())
  for (std::ptrdiff_t r = 0; r < rows; ++r) {
    const auto [start, length] = box_rows[std::size_t(r)];
    for (std::size_t i = start; i < start + length; ++i) {
      if (has_mass(i)) {
        const T m = grid_.mass[i];
        const Vec<T, D> v = grid_.velocity[i];
        grid_.velocity_new[i] = v + dt * (grid_.force[i] / m + g);
        kinetic += 0.5 * double(m) * double(v.squaredNorm());
        vmax2 = std::max(vmax2, double(v.squaredNorm()));
      } else {
        grid_.velocity_new[i].setZero();
      }
    }
  }
  kinetic_grid_ = kinetic;
  max_grid_speed_ = std::sqrt(vmax2);
}

// A wall's or collider's condition on a node's ṽ, relative to the body's velocity.
template <class T, int D>
inline void apply_condition(const ConstrainedNode<T, D>& c, Vec<T, D>& v) {
  T vn = (v - c.body).dot(c.normal);  // relative to the wall or plane
  switch (c.condition) {
    case BoundaryCondition::sticky:
      v = c.body;
      break;
    case BoundaryCondition::slip:
      v -= vn * c.normal;
      break;
    case BoundaryCondition::separate:
      if (vn < T(0)) v -= vn * c.normal;
      break;
    case BoundaryCondition::periodic:
      break;
  }
}

// With the ledger, each condition's change is added to the walls' or the colliders' sums
// (sim/mpm/stage_ledger.hpp).
template <class T, int D>
void MpmSimulation<T, D>::apply_boundary_conditions(bool ledger) {
  if (ledger) {
    for (const auto& c : blocks_.box_constraints()) {
      Vec<T, D>& v = grid_.velocity_new[c.node];
      const Vec<T, D> before = v;
      apply_condition(c, v);
      if (v != before && has_mass(c.node))  // else no change to book
        add_node_change<T, D>(c.collider ? ledger_.colliders : ledger_.walls,
                              grid_.node_position(c.node), grid_.mass[c.node], before, v);
    }
    return;
  }
  // outside the box ṽ = 0 already satisfies them
  for (const auto& c : blocks_.box_constraints()) apply_condition(c, grid_.velocity_new[c.node]);
}

}  // namespace apiclab
