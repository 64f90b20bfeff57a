// The end of 2D G2P's per-particle work, F^{n+1} = (I + Δt ∇u) F^n (eq 40) and
// x^{n+1} = x^n + Δt ū (eq 39) with the walls' clamp and the finiteness check, for a batch of
// particles at once, particle l in lane l. One particle at a time these were scalar products,
// lane extractions and compares at the end of a long chain from the gather; across the batch
// they are a few whole-register operations, and the gathers of the batch's particles no longer
// wait on one another's ends. Same operations in the same order as the per-particle code, so
// the results are the same bits (tests/mpm/simd/test_particle_move_2d.cpp).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstring>

#include "sim/math.hpp"
#include "sim/mpm/simd/lanes.hpp"
#include "sim/mpm/simd/soa_transpose.hpp"

namespace apiclab {

template <class T, int L>
struct ParticleMoveBatch2d {
  alignas(64) T dt_gradu[4][L];  // Δt ∇u of each particle, column-major as Eigen stores it
  alignas(64) T move[2][L];      // Δt ū

  void set(int l, const Mat<T, 2>& dt_grad, const Vec<T, 2>& dt_ubar) {
    for (int e = 0; e < 4; ++e) dt_gradu[e][l] = dt_grad(e % 2, e / 2);
    for (int a = 0; a < 2; ++a) move[a][l] = dt_ubar[a];
  }
  // The same from ∇u, ū and Δt, each read whole and scaled in a register. G2P keeps ∇u and ū on
  // the stack, and set()'s entry-by-entry reads of them were loads inside a wider store, which
  // some cores do not forward: then 2D float G2P's hottest spot.
  void set_scaled(int l, const Mat<T, 2>& gradu, const Vec<T, 2>& ubar, T dt) {
    using V4 = typename SimdVector<T, 4>::type;
    const V4 g = dt * load_register<V4>(gradu.data());
    for (int e = 0; e < 4; ++e) dt_gradu[e][l] = g[e];
    if constexpr (sizeof(T) == 4) {
      double both;  // the two floats as one 8-byte load
      std::memcpy(&both, ubar.data(), sizeof both);
      using V2d = SimdVector<double, 2>::type;
      const V4 u = dt * reinterpret_cast<V4>(V2d{both, 0.0});
      for (int a = 0; a < 2; ++a) move[a][l] = u[a];
    } else {
      const auto u = dt * load_register<typename SimdVector<T, 2>::type>(ubar.data());
      for (int a = 0; a < 2; ++a) move[a][l] = u[a];
    }
  }

  // One particle, as g2p_impl did it: F (in place), x clamped to [lo, hi] (no periodic axis).
  // Returns whether x and v are finite; raises largest_move to its largest |move| entry.
  bool apply_one(int l, Mat<T, 2>& F, Vec<T, 2>& x, const Vec<T, 2>& v, const Vec<T, 2>& lo,
                 const Vec<T, 2>& hi, T& largest_move) const {
    const Mat<T, 2> F0 = F;
    for (int b = 0; b < 2; ++b)
      for (int a = 0; a < 2; ++a) {
        T s = F0(a, b);
        for (int k = 0; k < 2; ++k) s += dt_gradu[a + 2 * k][l] * F0(k, b);
        F(a, b) = s;
      }
    largest_move = std::max(largest_move, std::max(std::abs(move[0][l]), std::abs(move[1][l])));
    for (int a = 0; a < 2; ++a) x[a] = std::min(std::max(x[a] + move[a][l], lo[a]), hi[a]);
    return std::isfinite(x.sum() + v.sum());
  }

  // Particles 0 … count − 1 of F, x and v; a full batch a register at a time.
  bool apply(int count, Mat<T, 2>* F, Vec<T, 2>* x, const Vec<T, 2>* v, const Vec<T, 2>& lo,
             const Vec<T, 2>& hi, T& largest_move) const {
    constexpr int P = std::min(L, simd_register_bytes / int(sizeof(T)));
    static_assert(
        L % P == 0 && sizeof(Mat<T, 2>) == 4 * sizeof(T) && sizeof(Vec<T, 2>) == 2 * sizeof(T),
        "whole registers of particles, each particle's entries packed");
    if (count < L) {
      bool finite = true;
      for (int l = 0; l < count; ++l)
        finite = apply_one(l, F[l], x[l], v[l], lo, hi, largest_move) && finite;
      return finite;
    }
    using V = typename SimdVector<T, P>::type;
    bool finite = true;
    V widest{};
    for (int l0 = 0; l0 < L; l0 += P) {
      T* f = reinterpret_cast<T*>(F + l0);
      T* xs = reinterpret_cast<T*>(x + l0);
      const T* vs = reinterpret_cast<const T*>(v + l0);
      V f0[4], g[4], pos[2], vel[2];
      load_entries<4>(f, f0);
      load_entries<2>(xs, pos);
      load_entries<2>(vs, vel);
      for (int e = 0; e < 4; ++e) g[e] = load_register<V>(&dt_gradu[e][l0]);
      V f1[4];
      for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
          V s = f0[a + 2 * b];
          for (int k = 0; k < 2; ++k) s += g[a + 2 * k] * f0[k + 2 * b];
          f1[a + 2 * b] = s;
        }
      store_entries<4>(f1, f);
      V abs_move[2];
      for (int a = 0; a < 2; ++a) {
        const V m = load_register<V>(&move[a][l0]);
        abs_move[a] = m < V{} ? -m : m;
        const V moved = pos[a] + m;
        const V low = V{} + lo[a], high = V{} + hi[a];
        const V above = moved < low ? low : moved;  // std::max(moved, lo)
        pos[a] = high < above ? high : above;       // std::min(…, hi)
      }
      const V m = abs_move[0] < abs_move[1] ? abs_move[1] : abs_move[0];
      widest = widest < m ? m : widest;
      store_entries<2>(pos, xs);
      const V sum = (pos[0] + pos[1]) + (vel[0] + vel[1]);
      // x − x is 0 for a finite x, NaN for ±∞ and NaN.
      const auto ok = (sum - sum) == V{};
      for (int l = 0; l < P; ++l) finite = finite && ok[l] != 0;
    }
    for (int l = 0; l < P; ++l) largest_move = std::max(largest_move, widest[l]);
    return finite;
  }
};

}  // namespace apiclab
