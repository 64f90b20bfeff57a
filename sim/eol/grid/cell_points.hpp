// The 2^d Gauss points of one cell of an object's multilinear grid, evaluated together: one SIMD
// lane per point (8 doubles in 3D: one AVX-512 register, two AVX2 ones). The shape-function
// values and gradients at the points depend only on the rest grid (a cell's unit coordinates
// ξ), so they are tabulated once, laid out for the two kinds of loop the forces run: over the
// points (lanes q, for A = ∂X/∂ξ) and over the corners (lanes k, for the corner forces).
#pragma once
#include <array>
#include <cmath>

#include "sim/math.hpp"

// glibc's vector log (libmvec, linked through libm) for the lane loops: GCC calls it for a
// `#pragma omp simd` loop over std::log once log is declared SIMD-callable (glibc declares it so
// only under -ffast-math). Its results are within 1 ulp of the scalar log's (glibc's ulps table).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(_OPENMP)
extern "C" double log(double) noexcept __attribute__((simd("notinbranch")));
#endif

namespace apiclab::eol {

// The 2^d Gauss points of the unit cell: ξ_a = ½ ± ½/√3, weight 2^-d.
template <class T, int D>
struct CellQuadrature {
  static constexpr int points = 1 << D, corners = 1 << D;
  std::array<std::array<T, corners>, points> N;           // N_k(ξ_q)
  std::array<std::array<Vec<T, D>, corners>, points> dN;  // ∇_ξ N_k(ξ_q)
  // The same tables with the points (lanes_q) or the corners (lanes_k) innermost.
  alignas(64) T N_lanes_q[corners][points];      // N_k(ξ_q)
  alignas(64) T dN_lanes_q[corners][D][points];  // ∂N_k/∂ξ_b (ξ_q)
  alignas(64) T dN_lanes_k[points][D][corners];  // the same, point-major
  alignas(64) T N_lanes_k[points][corners];      // N_k(ξ_q), point-major
  T weight = T(1) / T(points);
  CellQuadrature() {
    const T g = T(0.5) / std::sqrt(T(3));
    for (int q = 0; q < points; ++q)
      for (int k = 0; k < corners; ++k) {
        T value = T(1);
        Vec<T, D> grad = Vec<T, D>::Ones();
        for (int a = 0; a < D; ++a) {
          const T xi = q & (1 << a) ? T(0.5) + g : T(0.5) - g;
          const bool up = k & (1 << a);
          const T factor = up ? xi : T(1) - xi, slope = up ? T(1) : T(-1);
          value *= factor;
          for (int b = 0; b < D; ++b) grad[b] *= b == a ? slope : factor;
        }
        N[std::size_t(q)][std::size_t(k)] = value;
        dN[std::size_t(q)][std::size_t(k)] = grad;
        N_lanes_q[k][q] = N_lanes_k[q][k] = value;
        for (int b = 0; b < D; ++b) dN_lanes_q[k][b][q] = dN_lanes_k[q][b][k] = grad[b];
      }
  }
};

// A = ∂X/∂ξ, its determinant and the interpolated fill H at the Gauss points of one cell, lane
// q for point q (structure of arrays): V₀ = det A w H is the point's material volume.
template <class T, int D>
struct CellPoints {
  static constexpr int P = 1 << D;
  alignas(64) T A[D][D][P];
  alignas(64) T det[P];
  alignas(64) T fill[P];

  // From the cell's corner values X_k and H_k (corner k at bit a of k = +1 along axis a),
  // summed in corner order.
  void evaluate(const CellQuadrature<T, D>& quad, const T (&X)[D][P], const T (&H)[P]) {
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b) {
#pragma omp simd
        for (int q = 0; q < P; ++q) A[a][b][q] = T(0);
      }
#pragma omp simd
    for (int q = 0; q < P; ++q) fill[q] = T(0);
    for (int k = 0; k < P; ++k) {
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) {
          const T x = X[a][k];
#pragma omp simd
          for (int q = 0; q < P; ++q) A[a][b][q] += x * quad.dN_lanes_q[k][b][q];
        }
      const T h = H[k];
#pragma omp simd
      for (int q = 0; q < P; ++q) fill[q] += h * quad.N_lanes_q[k][q];
    }
#pragma omp simd
    for (int q = 0; q < P; ++q) {
      if constexpr (D == 2)
        det[q] = A[0][0][q] * A[1][1][q] - A[0][1][q] * A[1][0][q];
      else
        det[q] = A[0][0][q] * (A[1][1][q] * A[2][2][q] - A[1][2][q] * A[2][1][q]) -
                 A[0][1][q] * (A[1][0][q] * A[2][2][q] - A[1][2][q] * A[2][0][q]) +
                 A[0][2][q] * (A[1][0][q] * A[2][1][q] - A[1][1][q] * A[2][0][q]);
    }
  }
  Mat<T, D> matrix(int q) const {
    Mat<T, D> M;
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b) M(a, b) = A[a][b][q];
    return M;
  }
};

}  // namespace apiclab::eol
