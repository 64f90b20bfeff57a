// The velocity-impulse solve (Fan et al. 2013, eq 16) on the spatial velocities of the nodes,
// with walls and collider planes as constraints (eq 29, the node–plane rows; object–object
// contact is part 2). With the lumped (diagonal) mass and one row per node and plane, the QP
//   minimise ½ (u − u*)ᵀ M (u − u*)  subject to the plane's row
// is solved exactly by projecting the node's velocity: slip n·u = 0, separate n·u ≥ 0,
// sticky u = 0. Orthogonal planes (a domain corner) commute, so applying them in turn is exact.
#pragma once
#include <vector>

#include "sim/math.hpp"
#include "sim/registry.hpp"
#include "sim/scene.hpp"

namespace apiclab::eol {

template <class T, int D>
struct PlaneConstraint {
  Vec<T, D> point, normal;  // normal into the free side
  BoundaryCondition condition;
};

// The domain's walls (non-periodic faces) and the scene's colliders.
template <class T, int D>
std::vector<PlaneConstraint<T, D>> scene_planes(const SceneDesc& s) {
  std::vector<PlaneConstraint<T, D>> planes;
  for (int a = 0; a < D; ++a) {
    if (s.domain.periodic(a)) continue;
    for (int side = 0; side < 2; ++side) {
      PlaneConstraint<T, D> c;
      c.point.setZero();
      c.normal.setZero();
      c.point[a] = T(side ? s.domain.max[a] : s.domain.min[a]);
      c.normal[a] = T(side ? -1 : 1);
      c.condition = s.domain.walls[std::size_t(2 * a + side)];
      planes.push_back(c);
    }
  }
  for (const ColliderDesc& col : s.colliders) {
    PlaneConstraint<T, D> c;
    for (int a = 0; a < D; ++a) {
      c.point[a] = T(col.point[a]);
      c.normal[a] = T(col.normal[a]);
    }
    c.condition = col.condition;
    planes.push_back(c);
  }
  return planes;
}

// u ← u + Δt f / m on the nodes with mass (eq 16: M q̇^{t+1} = Δt f + M q̇^t).
template <class T, int D>
void impulse_update(std::vector<Vec<T, D>>& u, const std::vector<Vec<T, D>>& force,
                    const std::vector<T>& mass, T dt) {
  for (std::size_t i = 0; i < u.size(); ++i)
    if (mass[i] > T(0)) u[i] += (dt / mass[i]) * force[i];
}

// The node–plane rows: a node with mass on or behind a plane gets the plane's projection.
template <class T, int D>
void apply_planes(std::vector<Vec<T, D>>& u, const std::vector<Vec<T, D>>& x,
                  const std::vector<T>& mass, const std::vector<PlaneConstraint<T, D>>& planes) {
  for (std::size_t i = 0; i < u.size(); ++i) {
    if (!(mass[i] > T(0))) continue;
    for (const auto& c : planes) {
      if ((x[i] - c.point).dot(c.normal) > T(0)) continue;
      const T un = u[i].dot(c.normal);
      switch (c.condition) {
        case BoundaryCondition::sticky:
          u[i].setZero();
          break;
        case BoundaryCondition::separate:
          if (un < T(0)) u[i] -= un * c.normal;
          break;
        case BoundaryCondition::slip:
        case BoundaryCondition::periodic:
          u[i] -= un * c.normal;
          break;
      }
    }
  }
}

}  // namespace apiclab::eol
