// Algorithm 2 of Fan et al. 2013 (Sec 3.8): place each material-space surface vertex X_s in the
// intermediate domain. Starting from last step's position p (the paper's guess y^{t−1}(v)),
//   e = X_s − X(p),   p ← p + F e,   F = (∂X/∂y)⁻¹ at p,
// until ‖e‖ < ε, with X(p) and ∂X/∂y the grid's multilinear interpolant and its derivative
// (Newton's method on the piecewise-multilinear map, so an affine X converges in one step).
// A vertex whose iteration does not converge (a first guess far off) is searched for over the
// cells: every cell whose corners' X box holds X_s is inverted locally from its centre. The
// frame then maps p to space: x = R p + p₁.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "sim/eol/grid/eulerian_grid.hpp"

namespace apiclab::eol {

constexpr int kSurfaceNewtonIterations = 20;

// Newton on X(p) = target from p; true when ‖e‖∞ ≤ tol.
template <class T, int D>
bool invert_reference_map(const EulerianGrid<T, D>& g, const Vec<T, D>& target, T tol,
                          Vec<T, D>& p) {
  Vec<T, D> X;
  Mat<T, D> J;
  for (int it = 0; it <= kSurfaceNewtonIterations; ++it) {
    g.interpolate_with_jacobian(g.X, p, X, J);
    const Vec<T, D> e = target - X;  // Algorithm 2, line 4
    if (e.template lpNorm<Eigen::Infinity>() <= tol) return true;
    if (it == kSurfaceNewtonIterations) break;
    const T det = J.determinant();
    if (!(std::abs(det) > T(0)) || !std::isfinite(double(det))) return false;
    p += J.inverse() * e;  // line 5: p ← p + F e
    if (!p.allFinite()) return false;
  }
  return false;
}

// The fallback: the cells whose corner X bound `target` (inflated by tol), each inverted from
// its centre; the first that converges wins.
template <class T, int D>
bool search_cells(const EulerianGrid<T, D>& g, const Vec<T, D>& target, T tol, Vec<T, D>& p) {
  std::array<int, D> cells;
  std::size_t count = 1;
  for (int a = 0; a < D; ++a) {
    cells[std::size_t(a)] = std::max(g.n[std::size_t(a)] - 1, 1);
    count *= std::size_t(cells[std::size_t(a)]);
  }
  for (std::size_t c = 0; c < count; ++c) {
    std::array<int, D> base;
    std::size_t r = c;
    for (int a = 0; a < D; ++a) {
      base[std::size_t(a)] = int(r % std::size_t(cells[std::size_t(a)]));
      r /= std::size_t(cells[std::size_t(a)]);
    }
    Vec<T, D> lo = Vec<T, D>::Constant(std::numeric_limits<T>::max()), hi = -lo;
    for (int corner = 0; corner < (1 << D); ++corner) {
      std::array<int, D> k = base;
      for (int a = 0; a < D; ++a) k[std::size_t(a)] += (corner >> a) & 1;
      const Vec<T, D>& X = g.X[g.index(k)];
      lo = lo.cwiseMin(X);
      hi = hi.cwiseMax(X);
    }
    if (((target.array() < lo.array() - tol) || (target.array() > hi.array() + tol)).any())
      continue;
    Vec<T, D> q = g.origin;
    for (int a = 0; a < D; ++a) q[a] += g.dx * (T(base[std::size_t(a)]) + T(0.5));
    if (invert_reference_map(g, target, tol, q)) {
      p = q;
      return true;
    }
  }
  return false;
}

// The tolerance ε for a vertex: round-off of X at its size.
template <class T, int D>
T placement_tolerance(const Vec<double, D>& Xs) {
  return T(64) * std::numeric_limits<T>::epsilon() *
         T(std::max(1.0, Xs.template lpNorm<Eigen::Infinity>()));
}

// Algorithm 2 for every vertex: y holds last step's intermediate positions and receives the
// new ones. Returns how many vertices found no position (left where they were).
template <class T, int D>
int place_surface(const EulerianGrid<T, D>& g, const std::vector<Vec<double, D>>& Xs,
                  std::vector<Vec<T, D>>& y, bool parallel) {
  const std::ptrdiff_t n = std::ptrdiff_t(Xs.size());
  int misses = 0;
#pragma omp parallel for if (parallel) reduction(+ : misses)
  for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
    const std::size_t i = std::size_t(ii);
    const Vec<T, D> target = Xs[i].template cast<T>();
    const T tol = placement_tolerance<T, D>(Xs[i]);
    Vec<T, D> p = y[i];
    if (invert_reference_map(g, target, tol, p) || search_cells(g, target, tol, p))
      y[i] = p;
    else
      ++misses;
  }
  return misses;
}

}  // namespace apiclab::eol
