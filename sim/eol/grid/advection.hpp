// Advection through the grid by the Eulerian velocity only (Fan et al. 2013, eq 15 and
// Algorithm 1 steps 2 and 4), semi-Lagrangian (Stam 1999): the new value at node y_i is the
// old field at the departure point y_i − Δt v_i, interpolated multilinearly. Multilinear
// interpolation (extended affinely past the grid's faces) reproduces affine fields, so an
// affine X (any rigid placement of the rest shape) stays exact to round-off for any velocity.
#pragma once
#include <vector>

#include "sim/eol/grid/eulerian_grid.hpp"

namespace apiclab::eol {

template <class T, int D>
void advect(const EulerianGrid<T, D>& g, const std::vector<Vec<T, D>>& velocity, T dt,
            const std::vector<Vec<T, D>>& in, std::vector<Vec<T, D>>& out, bool parallel) {
  const std::ptrdiff_t n = std::ptrdiff_t(g.size());
#pragma omp parallel for if (parallel)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const std::size_t k = std::size_t(i);
    out[k] = g.interpolate(in, Vec<T, D>(g.y(k) - dt * velocity[k]));
  }
}

// Two fields through the same departure points (X and v in one step), the cell and weights
// found once: the same arithmetic as two advect calls. out_a and out_b alias no input.
template <class T, int D>
void advect_pair(const EulerianGrid<T, D>& g, const std::vector<Vec<T, D>>& velocity, T dt,
                 const std::vector<Vec<T, D>>& in_a, std::vector<Vec<T, D>>& out_a,
                 const std::vector<Vec<T, D>>& in_b, std::vector<Vec<T, D>>& out_b, bool parallel) {
  const std::ptrdiff_t n = std::ptrdiff_t(g.size());
#pragma omp parallel for if (parallel)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const std::size_t k = std::size_t(i);
    const auto corners = g.cell_weights(Vec<T, D>(g.y(k) - dt * velocity[k]));
    Vec<T, D> a = in_a[0] * T(0), b = in_b[0] * T(0);
    for (int c = 0; c < (1 << D); ++c) {
      const std::size_t j = corners.index[std::size_t(c)];
      const T w = corners.weight[std::size_t(c)];
      a += w * in_a[j];
      b += w * in_b[j];
    }
    out_a[k] = a;
    out_b[k] = b;
  }
}

}  // namespace apiclab::eol
