// Eulerian background grid: the node lattice of the scene's domain (plus a ghost layer two nodes
// wide on non-periodic axes, so kernel stencils of particles at a wall stay in range), of which
// only a region is stored: the active box the particles can reach (sim/mpm/block_partition.hpp). A
// scene whose domain is much larger than its objects pays memory and time for the box only.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/math.hpp"
#include "sim/mpm/simd/lanes.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {

// Where the nodes are: the domain's lattice (n, origin, dx, periodic axes) and the stored region
// [lo, lo + extent) of it in domain node coordinates, laid out with axis 0 fastest. Node
// indices everywhere (stencils, constraints, the implicit solve) are indices into the region.
template <class T, int D>
struct GridGeometry {
  static constexpr int ghost = 2;
  std::array<int, D> n{};  // nodes per axis over the whole domain
  std::array<bool, D> periodic{};
  Vec<T, D> origin;  // position of domain node 0
  T dx = 1, inv_dx = 1;
  std::array<int, D> lo{}, extent{};  // the stored region; periodic axes are stored whole
  std::array<std::size_t, D> stride{};

  void set_lattice(const SceneDesc& s) {
    dx = T(s.domain.dx);
    inv_dx = T(1) / dx;
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
    }
    set_region({}, {});
  }
  // Stores domain nodes [first, last) per axis (periodic axes always whole); returns the count.
  std::size_t set_region(const std::array<int, D>& first, const std::array<int, D>& last) {
    std::size_t total = 1;
    for (int a = 0; a < D; ++a) {
      lo[a] = periodic[a] ? 0 : first[a];
      extent[a] = periodic[a] ? n[a] : std::max(0, last[a] - first[a]);
      stride[a] = total;
      total *= std::size_t(extent[a]);
    }
    return total;
  }
  std::size_t region_size() const {
    std::size_t total = 1;
    for (int a = 0; a < D; ++a) total *= std::size_t(extent[a]);
    return total;
  }
  // Wrapped (periodic) or clamped domain node coordinate along one axis.
  int wrap(int i, int a) const {
    if (periodic[a]) {
      i %= n[a];
      return i < 0 ? i + n[a] : i;
    }
    return i < 0 ? 0 : (i >= n[a] ? n[a] - 1 : i);
  }
  // Domain node coordinate along axis a of a stored node.
  int node_coordinate(std::size_t index, int a) const {
    return lo[a] + int((index / stride[a]) % std::size_t(extent[a]));
  }
  Vec<T, D> node_position(std::size_t index) const {
    Vec<T, D> x;
    for (int a = 0; a < D; ++a) x[a] = origin[a] + T(node_coordinate(index, a)) * dx;
    return x;
  }
};

template <class T, int D>
struct Grid : GridGeometry<T, D> {
  // Per stored node. The phase contract of a step (MpmSimulation::step_fixed):
  std::vector<T> mass;                  // m_i^n (eq 24), from P2G on
  std::vector<Vec<T, D>> velocity;      // v_i^n (eq 26), from P2G on; zero without mass
  std::vector<Vec<T, D>> velocity_new;  // ṽ_i^{n+1} (eq 29), after the grid update
  std::vector<Vec<T, D>> force;         // f_i (eq 34), after P2G with forces
  // 1 + 2D lanes per node (sim/mpm/simd/lanes.hpp), two uses in one step (nodes of a stencil row
  // are one contiguous run the compiler can add or load as whole registers):
  //   clear_grid → particles_to_grid: the P2G accumulator [m, m v (D), f (D), padding];
  //   grid_to_particles: the packed G2P input [ṽ (D), vⁿ (D), padding] (pack_velocities),
  //   read as its first 2D lanes (GatherLanes).
  using NodeLanes = Lanes<T, 1 + 2 * D>;
  using GatherLanes = Lanes<T, 2 * D>;
  std::vector<NodeLanes, Eigen::aligned_allocator<NodeLanes>> node_lanes;

  // The lattice of the scene, nothing stored yet: the first block sort stores the active box.
  void init(const SceneDesc& s) {
    this->set_lattice(s);
    store({}, {});
  }
  // Stores domain nodes [first, last), all zero. The arrays keep their capacity, so a box that
  // moves without growing allocates nothing; memory follows the largest box so far.
  void store(const std::array<int, D>& first, const std::array<int, D>& last) {
    const std::size_t total = this->set_region(first, last);
    mass.assign(total, T(0));
    velocity.assign(total, Vec<T, D>::Zero());
    velocity_new.assign(total, Vec<T, D>::Zero());
    force.assign(total, Vec<T, D>::Zero());
    node_lanes.assign(total, NodeLanes{});
  }
  void store_whole_domain() {
    std::array<int, D> zero{};
    store(zero, this->n);
  }
  std::size_t size() const { return mass.size(); }
  // Bytes the node arrays hold (their capacity), for the memory tests and bench.
  std::size_t allocated_bytes() const {
    return mass.capacity() * sizeof(T) +
           (velocity.capacity() + velocity_new.capacity() + force.capacity()) * sizeof(Vec<T, D>) +
           node_lanes.capacity() * sizeof(NodeLanes);
  }
};

}  // namespace apiclab
