// The velocity-impulse solve (Fan et al. 2013, eq 16) on the spatial velocities of the nodes,
// with walls and collider planes as constraints (eq 29 with node–plane rows, solver.contact
// nodes; the default, the paper's surface rows, is surface_contact.hpp; object–object contact
// is part 2). With the lumped (diagonal) mass and one row per node and plane, the QP
//   minimise ½ (u − u*)ᵀ M (u − u*)  subject to the plane's row
// is solved exactly by projecting the node's velocity: slip n·u = 0, separate n·u ≥ 0,
// sticky u = 0. Orthogonal planes (a domain corner) commute, so applying them in turn is exact.
// A moving collider (velocity v_b) constrains the velocity relative to it, u − v_b: the row's
// right-hand side is −jᵀv_b (eq 29), here the projection of u − v_b.
#pragma once
#include <vector>

#include "sim/math.hpp"
#include "sim/scene/registry.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab::eol {

template <class T, int D>
struct PlaneConstraint {
  Vec<T, D> point, normal;  // normal into the free side; point at the step's time
  BoundaryCondition condition;
  Vec<T, D> velocity = Vec<T, D>::Zero();  // the plane's (walls: zero)
  Vec<T, D> start = Vec<T, D>::Zero();     // point at time 0
};

// Places the moving planes at time t: point = start + t velocity.
template <class T, int D>
void move_planes(std::vector<PlaneConstraint<T, D>>& planes, double t) {
  for (auto& c : planes)
    if (!c.velocity.isZero(T(0))) c.point = c.start + T(t) * c.velocity;
}

// A collider that the plane rows take: a plane that does not turn (its velocity constant); the
// others are bodies (body_contact.hpp).
inline bool plane_row_collider(const ColliderDesc& c) {
  return c.type == ColliderType::plane && c.path.empty() && c.angular_velocity == Vec3d{0, 0, 0};
}

// The domain's walls (non-periodic faces) and the scene's plane colliders.
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
    if (!plane_row_collider(col)) continue;
    PlaneConstraint<T, D> c;
    for (int a = 0; a < D; ++a) {
      c.point[a] = T(col.point[a]);
      c.normal[a] = T(col.normal[a]);
      c.velocity[a] = T(col.velocity[a]);
    }
    c.start = c.point;
    c.condition = col.condition;
    planes.push_back(c);
  }
  return planes;
}

// The node–plane rows for one node with mass: on or behind a plane, the plane's projection.
template <class T, int D>
void apply_planes(Vec<T, D>& u, const Vec<T, D>& x,
                  const std::vector<PlaneConstraint<T, D>>& planes) {
  for (const auto& c : planes) {
    if ((x - c.point).dot(c.normal) > T(0)) continue;
    const T un = (u - c.velocity).dot(c.normal);  // relative to the plane
    switch (c.condition) {
      case BoundaryCondition::sticky:
        u = c.velocity;
        break;
      case BoundaryCondition::separate:
        if (un < T(0)) u -= un * c.normal;
        break;
      case BoundaryCondition::slip:
      case BoundaryCondition::periodic:
        u -= un * c.normal;
        break;
    }
  }
}

// Eq 16 then eq 29's node–plane rows for one node of mass m > 0: u ← u + Δt f / m
// (M q̇^{t+1} = Δt f + M q̇^t), then the planes' projections. Node by node, so the step runs it
// inside its pass over the nodes for the split's sums (EolSimulation::finish_step).
template <class T, int D>
void impulse_update(Vec<T, D>& u, const Vec<T, D>& force, T m, const Vec<T, D>& x,
                    const std::vector<PlaneConstraint<T, D>>& planes, T dt) {
  u += (dt / m) * force;
  apply_planes(u, x, planes);
}

}  // namespace apiclab::eol
