// The scene's boundary conditions on grid nodes: domain walls (nodes on or beyond a non-periodic
// face) and collider planes (nodes behind the plane). Evaluated for the stored region only, each
// time the active box moves (and every step while a collider moves), so a large domain costs
// nothing for the nodes no particle reaches.
#pragma once
#include <array>
#include <vector>

#include "sim/mpm/grid.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {

// A grid node with a boundary condition: a domain wall or a collider plane. The condition holds
// on the node's velocity relative to the body's (zero for walls and fixed planes).
template <class T, int D>
struct ConstrainedNode {
  std::size_t node;  // index into the stored region
  Vec<T, D> normal;  // into the free side
  BoundaryCondition condition;
  Vec<T, D> body = Vec<T, D>::Zero();  // the wall's or plane's velocity
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
    planes_.clear();
    moving_ = false;
    for (const auto& c : scene.colliders) {
      Plane p;
      for (int a = 0; a < D; ++a) {
        p.normal[a] = T(c.normal[a]);
        p.point[a] = T(c.point[a]);
        p.velocity[a] = T(c.velocity[a]);
      }
      p.condition = c.condition;
      moving_ = moving_ || !p.velocity.isZero(T(0));
      planes_.push_back(p);
    }
  }

  // Whether a collider moves: then its nodes change with time and are collected every step.
  bool moving() const { return moving_; }
  // The time at which collect() places the moving planes (point + t velocity).
  void move_to(double t) { time_ = t; }

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
      for (const Plane& p : planes_) {
        const Vec<T, D> at = moving_ ? Vec<T, D>(p.point + T(time_) * p.velocity) : p.point;
        if ((x - at).dot(p.normal) <= eps) out.push_back({i, p.normal, p.condition, p.velocity});
      }
    }
  }

 private:
  static Vec<T, D> axis_normal(int a, T sign) {
    Vec<T, D> n = Vec<T, D>::Zero();
    n[a] = sign;
    return n;
  }
  struct Plane {
    Vec<T, D> normal, point, velocity;
    BoundaryCondition condition;
  };
  bool moving_ = false;
  double time_ = 0;
  std::array<bool, D> periodic_{};
  Vec<T, D> min_ = Vec<T, D>::Zero(), max_ = Vec<T, D>::Zero();
  std::array<BoundaryCondition, 2 * D> walls_{};
  std::vector<Plane> planes_;
};

}  // namespace apiclab
