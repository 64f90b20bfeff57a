// Eulerian background grid: node arrays over the scene's domain (plus a ghost layer two nodes
// wide on non-periodic axes, so kernel stencils of particles at a wall stay in range).
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "lanes.hpp"
#include "math.hpp"
#include "scene.hpp"

namespace apiclab {

template <class T, int D>
struct Grid {
  static constexpr int ghost = 2;
  std::array<int, D> n{};
  std::array<bool, D> periodic{};
  Vec<T, D> origin;  // position of node 0
  T dx = 1, inv_dx = 1;
  std::array<std::size_t, D> stride{};
  // Per node. The phase contract of a step (MpmSimulation::step_fixed):
  std::vector<T> mass;  // m_i^n (eq 24), from P2G on
  // Two quantities in one array, to keep P2G and the update one pass each:
  //   after particles_to_grid: the momentum (m v)_i (eq 25);
  //   after the grid update (velocity_from_momentum, eq 26): the velocity v_i^n.
  std::vector<Vec<T, D>> velocity;
  std::vector<Vec<T, D>> velocity_new;  // ṽ_i^{n+1} (eq 29), after the grid update
  std::vector<Vec<T, D>> force;         // f_i (eq 34), after P2G with forces
  // 1 + 2D lanes per node (sim/lanes.hpp), two uses in one step (nodes of a stencil row are one
  // contiguous run the compiler can add or load as whole registers):
  //   clear_grid → particles_to_grid: the P2G accumulator [m, m v (D), f (D), padding];
  //   grid_to_particles: the packed G2P input [ṽ (D), vⁿ (D), padding] (pack_velocities),
  //   read as its first 2D lanes (GatherLanes).
  using NodeLanes = Lanes<T, 1 + 2 * D>;
  using GatherLanes = Lanes<T, 2 * D>;
  std::vector<NodeLanes, Eigen::aligned_allocator<NodeLanes>> accumulator;

  void init(const SceneDesc& s) {
    dx = T(s.domain.dx);
    inv_dx = T(1) / dx;
    std::size_t total = 1;
    for (int a = 0; a < D; ++a) {
      periodic[a] = s.domain.periodic(a);
      double cells = (s.domain.max[a] - s.domain.min[a]) / s.domain.dx;
      if (periodic[a]) {
        n[a] = int(std::lround(cells));
        origin[a] = T(s.domain.min[a]);
      } else {
        n[a] = int(std::ceil(cells - 1e-9)) + 1 + 2 * ghost;
        origin[a] = T(s.domain.min[a] - ghost * s.domain.dx);
      }
      stride[a] = total;
      total *= std::size_t(n[a]);
    }
    mass.assign(total, T(0));
    velocity.assign(total, Vec<T, D>::Zero());
    velocity_new.assign(total, Vec<T, D>::Zero());
    force.assign(total, Vec<T, D>::Zero());
    accumulator.assign(total, NodeLanes{});
  }
  std::size_t size() const { return mass.size(); }
  // Wrapped (periodic) or clamped node index along one axis.
  int wrap(int i, int a) const {
    if (periodic[a]) {
      i %= n[a];
      return i < 0 ? i + n[a] : i;
    }
    return i < 0 ? 0 : (i >= n[a] ? n[a] - 1 : i);
  }
  // Index of a node along axis a.
  int node_coordinate(std::size_t index, int a) const {
    return int((index / stride[a]) % std::size_t(n[a]));
  }
  Vec<T, D> node_position(std::size_t index) const {
    Vec<T, D> x;
    for (int a = 0; a < D; ++a) x[a] = origin[a] + T(node_coordinate(index, a)) * dx;
    return x;
  }
};

}  // namespace apiclab
