// A collider placed at a time: its pose from the constant motion or the path's keys, the signed
// distance and outward normal of its analytic shape (plane, box, rod), and its velocity at a
// point, v_body = ν + ω × (x − c), which eq 29's right-hand side −jᵀv_body (Fan et al. 2013) and
// MPM's node condition hold the material to.
#pragma once
#include <array>
#include <limits>

#include "sim/scene/scene.hpp"

namespace apiclab {

struct ColliderPose {
  ColliderType type = ColliderType::plane;
  int dim = 2;
  BoundaryCondition condition = BoundaryCondition::slip;
  Vec3d center{};               // the body's point at t
  std::array<Vec3d, 3> axes{};  // the body's own axes in world at t (its rotation's columns)
  Vec3d normal{};               // plane: its normal at t
  Vec3d half{};                 // box: half its size; rod: (length / 2, radius, 0)
  Vec3d velocity{}, spin{};     // ν and ω at t (2D: ω along z)
  bool moving = false;          // the body moves at some time
  double reach = std::numeric_limits<double>::infinity();  // max |x − center| over the body

  struct Distance {
    double phi;    // < 0 inside the body
    Vec3d normal;  // the body's outward normal there (into the free side)
  };
  Distance distance(const Vec3d& x) const;
  Vec3d velocity_at(const Vec3d& x) const;  // ν + ω × (x − center)
};

// Whether the collider ever moves (a path, a velocity or a spin).
bool collider_moves(const ColliderDesc& c);

// The collider at time t in a scene of dimension dim.
ColliderPose collider_pose(const ColliderDesc& c, int dim, double t);

}  // namespace apiclab
