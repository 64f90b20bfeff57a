// Advection through the grid by the Eulerian velocity only (Fan et al. 2013, eq 15 and
// Algorithm 1 steps 2 and 4), semi-Lagrangian (Stam 1999): the new value at node y_i is the
// old field at the departure point y_i − Δt v_i, interpolated multilinearly. Multilinear
// interpolation (extended affinely past the grid's faces) reproduces affine fields, so an
// affine X (any rigid placement of the rest shape) stays exact to round-off for any velocity.
#pragma once
#include <vector>

#include "sim/eol/eulerian_grid.hpp"

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

}  // namespace apiclab::eol
