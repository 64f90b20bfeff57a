// The particle order and grid region that make the parallel P2G race-free and the grid passes
// short: a counting sort of particles into blocks of B cells, a colouring of the blocks so that
// same-coloured blocks never touch a common node, and the active box of nodes the sorted
// particles can reach until the next sort, which is all the grid stores (sim/mpm/grid.hpp). The
// blocks are counted over the particles' bounding box only, so nothing here grows with the domain.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "sim/mpm/boundary_nodes.hpp"
#include "sim/mpm/grid.hpp"
#include "sim/mpm/kernel_dispatch.hpp"
#include "sim/mpm/particles.hpp"
#include "sim/mpm/stencil.hpp"

namespace apiclab {

template <class T, int D>
class BlockPartition {
 public:
  // Width in cells of the sorting blocks (see sort).
  static int block_cells(KernelType kernel) { return kernel == KernelType::cubic ? 5 : 4; }

  // Sorts p by block (using scratch as the second buffer) unless no particle has drifted half a
  // cell since the last sort; recolours the blocks and moves the active box: the grid then
  // stores that box (all zero) and its wall and collider nodes. Returns whether p was permuted.
  bool sort(Particles<T, D>& p, Particles<T, D>& scratch, Grid<T, D>& grid,
            const BoundaryNodes<T, D>& boundary, KernelType kernel, bool parallel);
  // Cells the fastest particle moved this step (G2P reports it).
  void add_drift(double cells) { drift_since_sort_ += cells; }
  // The particles were moved from outside the step (written between steps): sort them next.
  void must_sort() { drift_since_sort_ = 1e30; }

  // fn(q) for every particle, colour by colour: calls of one colour may run in parallel and
  // never touch a common node.
  template <class Fn>
  void for_each_particle_coloured(Fn&& fn, bool parallel) const {
    for_each_block_coloured(
        [&](std::uint32_t begin, std::uint32_t end) {
          for (std::uint32_t q = begin; q < end; ++q) fn(q);
        },
        parallel);
  }
  // The same per block: fn(begin, end) with the block's particles [begin, end). For loops whose
  // body the compiler will not inline into a per-particle call (P2G).
  template <class Fn>
  void for_each_block_coloured(Fn&& fn, bool parallel) const;
  // fn(i) for every node of the active box.
  template <class Fn>
  void for_each_box_node(Fn&& fn, bool parallel) const;
  // The active box as runs (first node, length) along axis 0.
  const std::vector<std::pair<std::size_t, std::size_t>>& box_rows() const { return box_rows_; }
  // The wall and collider nodes inside the active box.
  const std::vector<ConstrainedNode<T, D>>& box_constraints() const { return box_constraints_; }
  // Collects them again where a collider moves (BoundaryNodes::move_to sets the time).
  void collect_constraints(const Grid<T, D>& grid, const BoundaryNodes<T, D>& boundary) {
    boundary.collect(grid, box_constraints_);
  }

  // The sort's state for a checkpoint (sim/state_io.hpp): the drift since the last sort, the
  // blocks, their colours and the active box, so the next step sorts (or not) and sums in the
  // same order as a run never stopped. load stores the box on the grid again (all zero).
  template <class Writer>
  void save(Writer& w) const;
  template <class Reader>
  void load(Reader& r, Grid<T, D>& grid, const BoundaryNodes<T, D>& boundary);

  // The invariant above, checked against the current positions (which may have drifted since
  // the sort): blocks of one colour touch disjoint nodes, and every touched node lies in the
  // active box. Returns "" or what breaks it.
  std::string conflict(const Particles<T, D>& p, const Grid<T, D>& grid, KernelType kernel) const;

 private:
  void set_active_box(Grid<T, D>& grid, const BoundaryNodes<T, D>& boundary, int block_cells,
                      const std::array<int, D>& first_block, const std::array<int, D>& last_block);
  // Stores [box_lo_, box_hi_) on the grid, all zero, with its rows and constraints.
  void store_box(Grid<T, D>& grid, const BoundaryNodes<T, D>& boundary);

  // Particles of block b are [block_start_[b], block_start_[b+1]). Blocks are numbered over the
  // particles' bounding box: block coordinate first_block_[a] + (b's digit on axis a) of the
  // domain's blocks, which start at domain node 0 (periodic axes: all blocks).
  std::vector<std::uint32_t> keys_, order_, block_start_;
  std::vector<std::vector<std::uint32_t>> color_blocks_;
  std::array<int, D> blocks_per_axis_{}, first_block_{};
  // Nodes the particles can reach until the next sort: [box_lo_, box_hi_) per axis in domain
  // node coordinates (the grid's stored region), as runs of consecutive stored nodes (start,
  // length) along axis 0, and the wall/collider nodes inside it.
  std::array<int, D> box_lo_{}, box_hi_{};
  std::vector<std::pair<std::size_t, std::size_t>> box_rows_;
  std::vector<ConstrainedNode<T, D>> box_constraints_;
  double drift_since_sort_ = 1e30;  // cells moved since the last block sort
};

template <class T, int D>
bool BlockPartition<T, D>::sort(Particles<T, D>& p, Particles<T, D>& scratch, Grid<T, D>& grid,
                                const BoundaryNodes<T, D>& boundary, KernelType kernel,
                                bool parallel) {
  // The colouring stays race-free while no particle has moved a cell away from the block it
  // was sorted into (same-coloured stencils are a block apart); re-sort at half a cell.
  if (drift_since_sort_ < 0.5) return false;
  drift_since_sort_ = 0;
  const std::size_t n = p.size();
  // Block width B: a particle within half a cell of block b reaches nodes [B b − 2, B b + B + 2]
  // (cubic; quadratic and linear one less on the right), so blocks two apart never share a node
  // when B ≥ 4 (quadratic, linear) or B ≥ 5 (cubic). A periodic axis folds its remainder into
  // the last block, so every block is at least B cells wide, also across the wrap.
  const int B = block_cells(kernel);
  std::array<int, D> domain_blocks;
  for (int a = 0; a < D; ++a)
    domain_blocks[a] = grid.periodic[a] ? std::max(1, grid.n[a] / B) : (grid.n[a] + B - 1) / B;
  // The block of a coordinate is monotone in it, so the blocks of the extreme coordinates bound
  // every particle's block: keys run over that box only (same order as over the domain's blocks).
  auto block_of = [&](T x, int a) {
    int cell = int(std::floor((x - grid.origin[a]) * grid.inv_dx));
    cell = grid.wrap(cell, a);
    return std::min(cell / B, domain_blocks[a] - 1);
  };
  // The passes over all particles run on every thread: serial, the sort was about 3 % of a
  // two-thread step (perf, 3D), one thread idle.
  T lo[D], hi[D];
  for (int a = 0; a < D; ++a) {
    lo[a] = std::numeric_limits<T>::max();
    hi[a] = -lo[a];
  }
  const std::ptrdiff_t count = std::ptrdiff_t(n);
#pragma omp parallel for schedule(static) reduction(min                     \
                                                    : lo[:D]) reduction(max \
                                                                        : hi[:D]) if (parallel)
  for (std::ptrdiff_t q = 0; q < count; ++q)
    for (int a = 0; a < D; ++a) {
      lo[a] = std::min(lo[a], p.x[std::size_t(q)][a]);
      hi[a] = std::max(hi[a], p.x[std::size_t(q)][a]);
    }
  const Vec<T, D> xmin = Eigen::Map<const Vec<T, D>>(lo), xmax = Eigen::Map<const Vec<T, D>>(hi);
  std::size_t nblocks = 1;
  for (int a = 0; a < D; ++a) {
    first_block_[a] = grid.periodic[a] || n == 0 ? 0 : block_of(xmin[a], a);
    blocks_per_axis_[a] = grid.periodic[a]
                              ? domain_blocks[a]
                              : (n == 0 ? 1 : block_of(xmax[a], a) - first_block_[a] + 1);
    nblocks *= std::size_t(blocks_per_axis_[a]);
  }
  keys_.resize(n);
#pragma omp parallel for schedule(static) if (parallel)
  for (std::ptrdiff_t q = 0; q < count; ++q) {
    std::size_t key = 0, s = 1;
    for (int a = 0; a < D; ++a) {
      key += std::size_t(block_of(p.x[std::size_t(q)][a], a) - first_block_[a]) * s;
      s *= std::size_t(blocks_per_axis_[a]);
    }
    keys_[std::size_t(q)] = std::uint32_t(key);
  }
  // Counting sort by block (stable, so an already sorted order stays identical).
  block_start_.assign(nblocks + 1, 0);
  for (std::size_t q = 0; q < n; ++q) ++block_start_[keys_[q] + 1];
  for (std::size_t b = 0; b < nblocks; ++b) block_start_[b + 1] += block_start_[b];
  bool sorted = true;
  for (std::size_t q = 1; q < n && sorted; ++q) sorted = keys_[q - 1] <= keys_[q];
  if (!sorted) {
    order_.resize(n);
    std::vector<std::uint32_t>& cursor = keys_;  // reuse: keys are consumed below
    std::vector<std::uint32_t> next(block_start_.begin(), block_start_.end() - 1);
    for (std::size_t q = 0; q < n; ++q) order_[next[cursor[q]]++] = std::uint32_t(q);
    p.gather_into(order_, scratch, parallel);
    std::swap(p, scratch);
  }
  // Colours: blocks of one colour are at least one block apart, so their stencils never share
  // a node; the last block of a periodic axis gets its own colour (it touches block 0).
  int colors = 1;
  for (int a = 0; a < D; ++a) colors *= 3;
  color_blocks_.resize(std::size_t(colors));
  for (auto& c : color_blocks_) c.clear();
  std::array<int, D> first, last;
  first.fill(std::numeric_limits<int>::max());
  last.fill(-1);
  for (std::size_t b = 0; b < nblocks; ++b) {
    if (block_start_[b] == block_start_[b + 1]) continue;
    std::size_t rest = b;
    int color = 0, scale = 1;
    for (int a = 0; a < D; ++a) {
      int ba = first_block_[a] + int(rest % std::size_t(blocks_per_axis_[a]));
      rest /= std::size_t(blocks_per_axis_[a]);
      first[a] = std::min(first[a], ba);
      last[a] = std::max(last[a], ba);
      int c = (grid.periodic[a] && ba == domain_blocks[a] - 1 && ba > 0) ? 2 : ba % 2;
      color += c * scale;
      scale *= 3;
    }
    color_blocks_[std::size_t(color)].push_back(std::uint32_t(b));
  }
  set_active_box(grid, boundary, B, first, last);
  return !sorted;
}

// The grid passes (clear, unpack, update, pack, walls) run only over the nodes the sorted
// particles can reach until the next sort, and the grid stores only those: scenes whose objects
// fill a small part of the domain stop paying for the empty rest. A new box is stored all zero.
template <class T, int D>
void BlockPartition<T, D>::set_active_box(Grid<T, D>& grid, const BoundaryNodes<T, D>& boundary,
                                          int block_cells, const std::array<int, D>& first_block,
                                          const std::array<int, D>& last_block) {
  std::array<int, D> lo, hi;
  for (int a = 0; a < D; ++a) {
    if (grid.periodic[a] || last_block[a] < 0) {
      lo[a] = 0;
      hi[a] = last_block[a] < 0 ? 0 : grid.n[a];
    } else {
      lo[a] = std::max(0, block_cells * first_block[a] - 2);
      hi[a] = std::min(grid.n[a], block_cells * (last_block[a] + 1) + 3);
    }
  }
  if (lo == box_lo_ && hi == box_hi_ && !box_rows_.empty()) return;
  box_lo_ = lo;
  box_hi_ = hi;
  store_box(grid, boundary);
}

template <class T, int D>
void BlockPartition<T, D>::store_box(Grid<T, D>& grid, const BoundaryNodes<T, D>& boundary) {
  grid.store(box_lo_, box_hi_);
  box_rows_.clear();
  const std::size_t rows = grid.size() / std::size_t(std::max(1, grid.extent[0]));
  if (grid.size() > 0)
    for (std::size_t r = 0; r < rows; ++r)
      box_rows_.push_back({r * grid.stride[1], std::size_t(grid.extent[0])});
  boundary.collect(grid, box_constraints_);
}

template <class T, int D>
template <class Writer>
void BlockPartition<T, D>::save(Writer& w) const {
  w.tag("blocks");
  w.value(drift_since_sort_);
  w.value(blocks_per_axis_);
  w.value(first_block_);
  w.value(box_lo_);
  w.value(box_hi_);
  w.value(std::uint8_t(!box_rows_.empty()));
  w.array(block_start_);
  w.value(std::uint64_t(color_blocks_.size()));
  for (const auto& c : color_blocks_) w.array(c);
}

template <class T, int D>
template <class Reader>
void BlockPartition<T, D>::load(Reader& r, Grid<T, D>& grid, const BoundaryNodes<T, D>& boundary) {
  r.tag("blocks");
  r.value(drift_since_sort_);
  r.value(blocks_per_axis_);
  r.value(first_block_);
  r.value(box_lo_);
  r.value(box_hi_);
  const bool stored = r.template value<std::uint8_t>() != 0;
  r.array(block_start_);
  color_blocks_.resize(std::size_t(std::min<std::uint64_t>(r.template value<std::uint64_t>(), 27)));
  for (auto& c : color_blocks_) r.array(c);
  box_rows_.clear();
  if (stored) store_box(grid, boundary);
}

template <class T, int D>
std::string BlockPartition<T, D>::conflict(const Particles<T, D>& p, const Grid<T, D>& grid,
                                           KernelType kernel) const {
  std::vector<std::int64_t> owner(grid.size(), -1);
  std::ostringstream why;
  with_kernel(kernel, [&](auto k) {
    using K = decltype(k);
    for (std::size_t color = 0; color < color_blocks_.size(); ++color) {
      std::fill(owner.begin(), owner.end(), -1);
      for (std::uint32_t b : color_blocks_[color])
        for (std::uint32_t q = block_start_[b]; q < block_start_[b + 1]; ++q) {
          // The stencil's domain node coordinates first: a node outside the box has no index.
          bool inside = true;
          for (int a = 0; a < D; ++a) {
            T w[K::width], dw[K::width];
            const int base = K::weights((p.x[q][a] - grid.origin[a]) * grid.inv_dx, w, dw);
            for (int i = 0; i < K::width; ++i) {
              const int c = grid.periodic[a] ? grid.wrap(base + i, a) : base + i;
              inside = inside && c >= box_lo_[a] && c < box_hi_[a];
            }
          }
          if (!inside) {
            if (why.tellp() == 0)
              why << "particle " << q << " reaches a node outside the active box";
            continue;
          }
          Stencil<T, D, K> st;
          st.compute(p.x[q], grid);
          st.for_each([&](std::size_t node, T, const Vec<T, D>&, const Vec<T, D>&) {
            if (owner[node] >= 0 && owner[node] != std::int64_t(b) && why.tellp() == 0)
              why << "blocks " << owner[node] << " and " << b << " of colour " << color
                  << " share node " << node;
            owner[node] = b;
          });
        }
    }
  });
  return why.str();
}

template <class T, int D>
template <class Fn>
void BlockPartition<T, D>::for_each_block_coloured(Fn&& fn, bool parallel) const {
  for (const auto& blocks : color_blocks_) {
    if (blocks.empty()) continue;  // no parallel region to open and join (most colours in 3D)
    const std::ptrdiff_t nb = std::ptrdiff_t(blocks.size());
// Contiguous chunks: neighbouring same-coloured blocks share cache lines, so they go to one thread.
#pragma omp parallel for schedule(static) if (parallel)
    for (std::ptrdiff_t bi = 0; bi < nb; ++bi) {
      const std::uint32_t b = blocks[std::size_t(bi)];
      fn(block_start_[b], block_start_[b + 1]);
    }
  }
}

template <class T, int D>
template <class Fn>
void BlockPartition<T, D>::for_each_box_node(Fn&& fn, bool parallel) const {
  const std::ptrdiff_t rows = std::ptrdiff_t(box_rows_.size());
#pragma omp parallel for schedule(static) if (parallel)
  for (std::ptrdiff_t r = 0; r < rows; ++r) {
    const auto [start, length] = box_rows_[std::size_t(r)];
    for (std::size_t i = start; i < start + length; ++i) fn(i);
  }
}

}  // namespace apiclab
