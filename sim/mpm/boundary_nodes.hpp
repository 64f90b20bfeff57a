// The scene's boundary conditions on grid nodes: domain walls (nodes on or beyond a non-periodic
// face) and colliders (nodes behind a plane, inside a box or rod; sim/geometry/collider_body.hpp).
// Evaluated for the stored region only, each time the active box moves (and every step while a
// collider moves), so a large domain costs nothing for the nodes no particle reaches.
#pragma once
#include <algorithm>
#include <array>
#include <vector>

#include "sim/geometry/collider_body.hpp"
#include "sim/mpm/grid.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {

// A grid node with a boundary condition: a domain wall or a collider. The condition holds on the
// node's velocity relative to the body's velocity at the node, ν + ω × (x − c) (zero for walls
// and fixed colliders), along the body's outward normal there.
template <class T, int D>
struct ConstrainedNode {
  std::size_t node;  // index into the stored region
  Vec<T, D> normal;  // into the free side
  BoundaryCondition condition;
  bool collider = false;               // a collider's, not a domain wall's (the ledger splits them)
  Vec<T, D> body = Vec<T, D>::Zero();  // the wall's or body's velocity at the node
};

template <class T, int D>
class BoundaryNodes {
 public:
  void init(const SceneDesc& scene) {
    for (int a = 0; a < D; ++a) {
      periodic_[a] = scene.domain.periodic(a);
      min_[a] = T(scene.domain.min[a]);
      max_[a] = T(scene.domain.max[a]);
      walls_[2 * a] = scene.domain.walls[2 * a];
      walls_[2 * a + 1] = scene.domain.walls[2 * a + 1];
    }
    colliders_ = scene.colliders;
    moving_ = std::any_of(colliders_.begin(), colliders_.end(), collider_moves);
    move_to(0);
  }

  // Whether a collider moves: then its nodes change with time and are collected every step.
  bool moving() const { return moving_; }
  // Places the colliders at time t for collect().
  void move_to(double t) {
    poses_.clear();
    for (const ColliderDesc& c : colliders_) poses_.push_back(collider_pose(c, D, t));
  }

  // The constraints of every stored node of g, in node order; per node the walls axis by axis
  // (low face, high face), then the colliders in scene order.
  void collect(const GridGeometry<T, D>& g, std::vector<ConstrainedNode<T, D>>& out) const {
    out.clear();
    const std::size_t count = g.region_size();
    const T eps = T(1e-6) * g.dx;
    std::array<int, D> c{};  // the node's coordinates in the region, axis 0 fastest
    for (std::size_t i = 0; i < count; ++i) {
      Vec<T, D> x;  // as GridGeometry::node_position, without its divisions
      for (int a = 0; a < D; ++a) x[a] = g.origin[a] + T(g.lo[a] + c[a]) * g.dx;
      for (int a = 0; a < D && ++c[a] == g.extent[a]; ++a) c[a] = 0;
      for (int a = 0; a < D; ++a) {
        if (periodic_[a]) continue;
        if (x[a] <= min_[a] + eps) out.push_back({i, axis_normal(a, T(1)), walls_[2 * a]});
        if (x[a] >= max_[a] - eps) out.push_back({i, axis_normal(a, T(-1)), walls_[2 * a + 1]});
      }
      for (const ColliderPose& p : poses_) {
        Vec3d at{0, 0, 0};
        for (int a = 0; a < D; ++a) at[std::size_t(a)] = double(x[a]);
        const ColliderPose::Distance d = p.distance(at);
        if (d.phi > double(eps)) continue;
        ConstrainedNode<T, D> node{i, Vec<T, D>::Zero(), p.condition, true};
        const Vec3d v = p.velocity_at(at);
        for (int a = 0; a < D; ++a) {
          node.normal[a] = T(d.normal[std::size_t(a)]);
          node.body[a] = T(v[std::size_t(a)]);
        }
        out.push_back(node);
      }
    }
  }

 private:
  static Vec<T, D> axis_normal(int a, T sign) {
    Vec<T, D> n = Vec<T, D>::Zero();
    n[a] = sign;
    return n;
  }
  bool moving_ = false;
  std::vector<ColliderDesc> colliders_;
  std::vector<ColliderPose> poses_;  // at the time of move_to
  std::array<bool, D> periodic_{};
  Vec<T, D> min_ = Vec<T, D>::Zero(), max_ = Vec<T, D>::Zero();
  std::array<BoundaryCondition, 2 * D> walls_{};
};

}  // namespace apiclab
