// Extrapolation of X and v from the nodes that hold material (mass > 0) into every empty node
// of the grid, front by front (breadth first), so the nodes the object reaches next step, and
// the departure points advection reads (Fan et al. 2013, eq 15), hold values continued from
// the material rather than stale ones. Within kLinearFronts fronts of the material (the reach of
// one step's departure points, α < 1 cell) X is continued linearly, 2 X_{i+s} − X_{i+2s} along
// each axis direction s with two known nodes in a row (exact for an affine X, so a rigid
// placement stays exact), averaged over the directions; farther out, and for v everywhere, by
// the mean of the known neighbours (constant: a linear continuation over many fronts would
// carry any curvature of X far out and could map distant empty nodes back into the rest shape).
#pragma once
#include <vector>

#include "sim/eol/grid/eulerian_grid.hpp"

namespace apiclab::eol {

template <class T, int D>
class Extrapolation {
 public:
  std::size_t bytes() const {
    return held_bytes(state_) + held_bytes(front_) + held_bytes(next_) + held_bytes(newX_) +
           held_bytes(newv_);
  }
  void apply(EulerianGrid<T, D>& g) {
    state_.assign(g.size(), kUnknown);
    front_.clear();
    for (std::size_t i = 0; i < g.size(); ++i)
      if (g.mass[i] > T(0)) state_[i] = kKnown;
    for (std::size_t i = 0; i < g.size(); ++i)
      if (state_[i] == kUnknown && has_known_neighbour(g, i)) {
        state_[i] = kQueued;
        front_.push_back(i);
      }
    for (int fronts = 0; !front_.empty(); ++fronts) {
      newX_.resize(front_.size());
      newv_.resize(front_.size());
      for (std::size_t k = 0; k < front_.size(); ++k)
        continue_into(g, front_[k], fronts < kLinearFronts, newX_[k], newv_[k]);
      next_.clear();
      for (std::size_t k = 0; k < front_.size(); ++k) {
        const std::size_t i = front_[k];
        g.X[i] = newX_[k];
        g.v[i] = newv_[k];
        state_[i] = kKnown;
      }
      for (std::size_t i : front_)
        for_each_neighbour(g, i, [&](std::size_t j, int, int) {
          if (state_[j] == kUnknown) {
            state_[j] = kQueued;
            next_.push_back(j);
          }
        });
      std::swap(front_, next_);
    }
  }

 private:
  enum : char { kUnknown, kQueued, kKnown };
  static constexpr int kLinearFronts = 3;

  // fn(neighbour, axis, direction) for the axis neighbours inside the grid.
  template <class Fn>
  static void for_each_neighbour(const EulerianGrid<T, D>& g, std::size_t i, Fn&& fn) {
    const auto c = g.coords(i);
    for (int a = 0; a < D; ++a) {
      const std::size_t s = g.stride(a);
      if (c[a] > 0) fn(i - s, a, -1);
      if (c[a] + 1 < g.n[a]) fn(i + s, a, 1);
    }
  }
  bool has_known_neighbour(const EulerianGrid<T, D>& g, std::size_t i) const {
    bool any = false;
    for_each_neighbour(g, i, [&](std::size_t j, int, int) { any = any || state_[j] == kKnown; });
    return any;
  }
  void continue_into(const EulerianGrid<T, D>& g, std::size_t i, bool linear, Vec<T, D>& X,
                     Vec<T, D>& v) {
    const auto c = g.coords(i);
    Vec<T, D> X_lin = Vec<T, D>::Zero(), X_near = Vec<T, D>::Zero(), v_near = Vec<T, D>::Zero();
    int lin = 0, near = 0;
    for_each_neighbour(g, i, [&](std::size_t j, int a, int dir) {
      if (state_[j] != kKnown) return;
      X_near += g.X[j];
      v_near += g.v[j];
      ++near;
      const int c2 = c[a] + 2 * dir;
      if (c2 < 0 || c2 >= g.n[a]) return;
      const std::size_t j2 = dir > 0 ? j + g.stride(a) : j - g.stride(a);
      if (state_[j2] != kKnown) return;
      X_lin += T(2) * g.X[j] - g.X[j2];
      ++lin;
    });
    X = linear && lin > 0 ? Vec<T, D>(X_lin / T(lin)) : Vec<T, D>(X_near / T(near));
    v = v_near / T(near);
  }

  std::vector<char> state_;
  std::vector<std::size_t> front_, next_;
  std::vector<Vec<T, D>> newX_, newv_;
};

}  // namespace apiclab::eol
