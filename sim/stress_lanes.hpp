// The explicit stress pass of fixed-corotated particles, several particles at a time in SIMD
// lanes. 3D: Higham's scaled Newton polar iteration (polar_newton_3d) run on every lane together,
// each lane frozen once its own test passes, so each lane follows the scalar iteration. Scalar,
// the iteration's 3×3 inverses left half of a 3D step in the stress pass; across particles they
// become whole-vector multiply-adds.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "lanes.hpp"
#include "math.hpp"

namespace apiclab {

// Lanes per group: one register (simd_register_bytes, 256 bits also on AVX-512). In 2D a
// particle's arithmetic is too short to pay for moving its F into 512-bit lanes (2D double on
// AVX-512 ran at 0.87 of the scalar pass with 8 lanes, 1.2× faster with 4 on AVX2; bench, one
// run, interleaved); in 3D 512-bit lanes gained nothing once every other loop used 256 bits.
template <class T, int D>
inline constexpr int stress_lane_count = std::min(8, simd_register_bytes / int(sizeof(T)));

template <class T, int D>
struct StressLanes {
  static constexpr int count = stress_lane_count<T, D>;
  using V = typename SimdVector<T, count>::type;
  using Mask = typename SimdVector<T, count>::index;

  // Entries of a 3×3 matrix per lane, column-major as Eigen stores them: m[r + 3 c].
  struct M3 {
    V m[9];
  };

  static V det(const M3& a) {
    const V* m = a.m;
    return m[0] * (m[4] * m[8] - m[7] * m[5]) - m[3] * (m[1] * m[8] - m[7] * m[2]) +
           m[6] * (m[1] * m[5] - m[4] * m[2]);
  }
  // cof(A) = J A⁻ᵀ: its columns are the cross products of A's other two columns (math.hpp).
  static M3 cofactor(const M3& a) {
    M3 c;
    const V* m = a.m;
    auto cross = [&](int j, int k, int out) {
      c.m[out + 0] = m[1 + 3 * j] * m[2 + 3 * k] - m[2 + 3 * j] * m[1 + 3 * k];
      c.m[out + 1] = m[2 + 3 * j] * m[0 + 3 * k] - m[0 + 3 * j] * m[2 + 3 * k];
      c.m[out + 2] = m[0 + 3 * j] * m[1 + 3 * k] - m[1 + 3 * j] * m[0 + 3 * k];
    };
    cross(1, 2, 0);
    cross(2, 0, 3);
    cross(0, 1, 6);
    return c;
  }
  static bool any(Mask m) {
    for (int l = 0; l < count; ++l)
      if (m[l]) return true;
    return false;
  }
  static V splat(T s) { return V{} + s; }

  // For `count` particles starting at F: stress_out = −V P(F) Fᵀ and psi_out = Ψ(F) of the
  // fixed-corotated model, P = 2μ(F − R) + λ(J − 1) J F⁻ᵀ. Returns a bit per lane that the
  // Newton iteration could not do (inverted or nearly singular F, or no convergence in 30
  // steps, as polar_newton_3d): the caller computes those particles with the scalar path.
  static unsigned fixed_corotated(const Mat<T, 3>* F, const T* mu, const T* lambda, const T* volume,
                                  Mat<T, 3>* stress_out, T* psi_out) {
    static_assert(sizeof(Mat<T, 3>) == 9 * sizeof(T));  // `count` matrices, 9 scalars apart
    M3 f;
    load_matrices(F[0].data(), f.m);
    const V vmu = load_register<V>(mu), vlambda = load_register<V>(lambda);
    const V vvolume = load_register<V>(volume);
    V f_norm2 = V{};
    for (int k = 0; k < 9; ++k) f_norm2 += f.m[k] * f.m[k];
    const V J = det(f);
    // polar_newton_3d's test det > 1e-6 ‖F‖³, squared.
    const Mask ok = (J > T(0)) & (J * J > T(1e-12) * f_norm2 * f_norm2 * f_norm2);
    M3 x;
    for (int k = 0; k < 9; ++k) x.m[k] = ok ? f.m[k] : splat(k % 4 == 0 ? T(1) : T(0));
    V d = ok ? J : splat(T(1));
    Mask active = ok;
    const T tolerance2 =
        T(64) * std::numeric_limits<T>::epsilon() * std::numeric_limits<T>::epsilon();
    V step2 = splat(T(1));
    for (int it = 0; it < 30 && any(active); ++it) {
      const M3 c = cofactor(x);
      // γ = (‖X⁻¹‖ / ‖X‖)^½ = (‖cof X‖ / (det X ‖X‖))^½ while far from converged, as
      // polar_newton_3d (sim/math.hpp).
      V gamma = splat(T(1));
      const Mask scaled = active & (step2 > T(1e-4));
      if (any(scaled)) {  // the norms only for a step that scales
        V c_norm2 = V{}, x_norm2 = V{};
        for (int k = 0; k < 9; ++k) {
          c_norm2 += c.m[k] * c.m[k];
          x_norm2 += x.m[k] * x.m[k];
        }
        V ratio = c_norm2 / (d * d * x_norm2);
        ratio = scaled ? ratio : splat(T(1));
        V root = ratio;  // (initialised: GCC cannot see the loop write every lane)
        for (int l = 0; l < count; ++l) root[l] = std::sqrt(std::sqrt(ratio[l]));
        gamma = scaled ? root : gamma;
      }
      const V inverse = T(1) / (gamma * d);
      V s2 = V{};
      M3 next;
      for (int k = 0; k < 9; ++k) {
        next.m[k] = T(0.5) * (gamma * x.m[k] + c.m[k] * inverse);
        const V change = next.m[k] - x.m[k];
        s2 += change * change;
      }
      const V previous2 = step2;
      step2 = active ? s2 : step2;
      for (int k = 0; k < 9; ++k) x.m[k] = active ? next.m[k] : x.m[k];
      // Converged, or round-off stops the quadratic decrease just above the tolerance.
      const Mask done = (s2 <= tolerance2) | ((s2 < T(1e-6)) & (s2 >= previous2));
      active &= ~done;
      d = det(x);
    }
    const Mask failed = ~ok | active;
    const M3 cof = cofactor(f);
    const V two_mu = T(2) * vmu, volume_term = vlambda * (J - T(1));
    M3 p;
    V rotation_part = V{};
    for (int k = 0; k < 9; ++k) {
      const V fr = f.m[k] - x.m[k];
      rotation_part += fr * fr;
      p.m[k] = two_mu * fr + volume_term * cof.m[k];
    }
    const V psi = vmu * rotation_part + T(0.5) * vlambda * (J - T(1)) * (J - T(1));
    // −V P Fᵀ: entry (i, j) = −V Σ_k P(i, k) F(j, k).
    M3 s;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        s.m[i + 3 * j] =
            -vvolume * (p.m[i] * f.m[j] + p.m[i + 3] * f.m[j + 3] + p.m[i + 6] * f.m[j + 6]);
    store_matrices(s.m, stress_out[0].data());
    store_register(psi_out, psi);
    unsigned failed_bits = 0;
    for (int l = 0; l < count; ++l)
      if (failed[l]) failed_bits |= 1u << l;
    return failed_bits;
  }

  // The same in 2D, where R is closed-form (rotation_2d): c, s = (F00 + F11, F10 − F01) / n.
  static void fixed_corotated_2d(const Mat<T, 2>* F, const T* mu, const T* lambda, const T* volume,
                                 Mat<T, 2>* stress_out, T* psi_out) {
    static_assert(sizeof(Mat<T, 2>) == 4 * sizeof(T));  // `count` matrices, 4 scalars apart
    V f[4];
    load_matrices(F[0].data(), f);
    const V vmu = load_register<V>(mu), vlambda = load_register<V>(lambda);
    const V vvolume = load_register<V>(volume);
    const V a = f[0] + f[3], b = f[1] - f[2], n2 = a * a + b * b;
    V inverse_n;
    for (int l = 0; l < count; ++l) inverse_n[l] = T(1) / std::sqrt(n2[l]);  // vectorised
    const Mask rotated = n2 > T(0);
    const V c = rotated ? a * inverse_n : splat(T(1)), s = rotated ? b * inverse_n : V{};
    const V J = f[0] * f[3] - f[2] * f[1];
    const V fr[4] = {f[0] - c, f[1] - s, f[2] + s, f[3] - c};  // F − R, column-major
    const V cof[4] = {f[3], -f[2], -f[1], f[0]};
    const V two_mu = T(2) * vmu, volume_term = vlambda * (J - T(1));
    V p[4], rotation_part = V{};
    for (int k = 0; k < 4; ++k) {
      rotation_part += fr[k] * fr[k];
      p[k] = two_mu * fr[k] + volume_term * cof[k];
    }
    const V psi = vmu * rotation_part + T(0.5) * vlambda * (J - T(1)) * (J - T(1));
    V out[4];
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) out[i + 2 * j] = -vvolume * (p[i] * f[j] + p[i + 2] * f[j + 2]);
    store_matrices(out, stress_out[0].data());
    store_register(psi_out, psi);
  }

 private:
  // 128-bit halves of a register: `per_half` scalars each.
  static constexpr int per_half = 16 / int(sizeof(T));
  static constexpr int halves = count / per_half;
  using Half = typename SimdVector<T, per_half>::type;

  // The n entries of `count` consecutive matrices (n scalars apart: 2×2 or 3×3) as one register
  // per entry with matrix l in lane l, and back. Lane by lane these moves were a third of the 2D
  // and a quarter of the 3D stress pass. Entries e … e + per_half − 1 come as per_half registers,
  // register j holding in half g those entries of matrix j + g·per_half (one 128-bit load or
  // store each, no cross-half shuffle); a transpose within each half then gives one register per
  // entry. What is left of n (3D: entry 8) goes lane by lane.
  template <int n>
  static void load_matrices(const T* m, V (&out)[n]) {
    constexpr int whole = n / per_half * per_half;
    for (int e = 0; e < whole; e += per_half) {
      V r[per_half];
      for (int j = 0; j < per_half; ++j) {
        if constexpr (halves == 1)
          r[j] = load_register<V>(m + n * j + e);
        else
          r[j] = join_halves<V>(load_register<Half>(m + n * j + e),
                                load_register<Half>(m + n * (j + per_half) + e));
      }
      transpose_within_halves(r);
      for (int k = 0; k < per_half; ++k) out[e + k] = r[k];
    }
    for (int e = whole; e < n; ++e)
      out[e] = entry_of_each(m + e, n, std::make_index_sequence<count>{});
  }
  template <int n>
  static void store_matrices(const V (&in)[n], T* m) {
    constexpr int whole = n / per_half * per_half;
    for (int e = 0; e < whole; e += per_half) {
      V r[per_half];
      for (int k = 0; k < per_half; ++k) r[k] = in[e + k];
      transpose_within_halves(r);
      for (int j = 0; j < per_half; ++j) {
        if constexpr (halves == 1) {
          store_register(m + n * j + e, r[j]);
        } else {
          store_register(m + n * j + e, half_of<0, Half>(r[j]));
          store_register(m + n * (j + per_half) + e, half_of<1, Half>(r[j]));
        }
      }
    }
    for (int e = whole; e < n; ++e)
      for (int l = 0; l < count; ++l) m[n * l + e] = in[e][l];
  }
  template <std::size_t... l>
  static V entry_of_each(const T* m, int n, std::index_sequence<l...>) {
    return V{m[n * int(l)]...};
  }
  // Lane g·per_half + i of register k becomes lane g·per_half + k of register i: a per_half ×
  // per_half transpose within each 128-bit half (unpacks and half moves, one instruction each on
  // SSE, AVX2 and AVX-512); its own inverse.
  static void transpose_within_halves(V (&r)[per_half]) {
    if constexpr (count == 8) {
      const V t0 = shuffle_lanes<0, 8, 1, 9, 4, 12, 5, 13>(r[0], r[1]);  // unpack low
      const V t1 = shuffle_lanes<2, 10, 3, 11, 6, 14, 7, 15>(r[0], r[1]);
      const V t2 = shuffle_lanes<0, 8, 1, 9, 4, 12, 5, 13>(r[2], r[3]);
      const V t3 = shuffle_lanes<2, 10, 3, 11, 6, 14, 7, 15>(r[2], r[3]);
      r[0] = shuffle_lanes<0, 1, 8, 9, 4, 5, 12, 13>(t0, t2);  // low pairs of both
      r[1] = shuffle_lanes<2, 3, 10, 11, 6, 7, 14, 15>(t0, t2);
      r[2] = shuffle_lanes<0, 1, 8, 9, 4, 5, 12, 13>(t1, t3);
      r[3] = shuffle_lanes<2, 3, 10, 11, 6, 7, 14, 15>(t1, t3);
    } else if constexpr (count == 4 && per_half == 4) {  // 4 floats (SSE): one half
      const V t0 = shuffle_lanes<0, 4, 2, 6>(r[0], r[1]),
              t1 = shuffle_lanes<1, 5, 3, 7>(r[0], r[1]);
      const V t2 = shuffle_lanes<0, 4, 2, 6>(r[2], r[3]),
              t3 = shuffle_lanes<1, 5, 3, 7>(r[2], r[3]);
      r[0] = shuffle_lanes<0, 1, 4, 5>(t0, t2);
      r[1] = shuffle_lanes<0, 1, 4, 5>(t1, t3);
      r[2] = shuffle_lanes<2, 3, 6, 7>(t0, t2);
      r[3] = shuffle_lanes<2, 3, 6, 7>(t1, t3);
    } else if constexpr (count == 4) {  // 4 doubles (AVX): unpack low and high
      const V low = shuffle_lanes<0, 4, 2, 6>(r[0], r[1]);
      r[1] = shuffle_lanes<1, 5, 3, 7>(r[0], r[1]);
      r[0] = low;
    } else {  // 2 doubles (SSE)
      const V low = shuffle_lanes<0, 2>(r[0], r[1]);
      r[1] = shuffle_lanes<1, 3>(r[0], r[1]);
      r[0] = low;
    }
  }
};

}  // namespace apiclab
