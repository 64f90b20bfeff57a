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

#include "sim/math.hpp"
#include "sim/mpm/simd/lanes.hpp"
#include "sim/mpm/simd/soa_transpose.hpp"

namespace apiclab {

// Lanes per group: one register (simd_register_bytes, 256 bits also on AVX-512). In 2D a
// particle's arithmetic is too short to pay for moving its F into 512-bit lanes (8 double lanes
// ran slower than the scalar pass, 4 faster); in 3D 512-bit lanes gained nothing once every
// other loop used 256 bits.
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

  // For `count` particles starting at F: stress_out = −V P(F) Fᵀ and psi_out = Ψ(F) of the
  // fixed-corotated model, P = 2μ(F − R) + λ(J − 1) J F⁻ᵀ. Returns a bit per lane that the
  // Newton iteration could not do (inverted or nearly singular F, or no convergence in 30
  // steps, as polar_newton_3d): the caller computes those particles with the scalar path.
  static unsigned fixed_corotated(const Mat<T, 3>* F, const T* mu, const T* lambda, const T* volume,
                                  Mat<T, 3>* stress_out, T* psi_out) {
    static_assert(sizeof(Mat<T, 3>) == 9 * sizeof(T));  // `count` matrices, 9 scalars apart
    M3 f;
    load_entries(F[0].data(), f.m);
    const V vmu = load_register<V>(mu), vlambda = load_register<V>(lambda);
    const V vvolume = load_register<V>(volume);
    V f_norm2 = V{};
    for (int k = 0; k < 9; ++k) f_norm2 += f.m[k] * f.m[k];
    const V J = det(f);
    // polar_newton_3d's test det > 1e-6 ‖F‖³, squared.
    const Mask ok = (J > T(0)) & (J * J > T(1e-12) * f_norm2 * f_norm2 * f_norm2);
    M3 x;
    for (int k = 0; k < 9; ++k) x.m[k] = ok ? f.m[k] : splat<V>(k % 4 == 0 ? T(1) : T(0));
    V d = ok ? J : splat<V>(T(1));
    Mask active = ok;
    const T tolerance2 =
        T(64) * std::numeric_limits<T>::epsilon() * std::numeric_limits<T>::epsilon();
    V step2 = splat<V>(T(1));
    for (int it = 0; it < 30 && any(active); ++it) {
      const M3 c = cofactor(x);
      // γ = (‖X⁻¹‖ / ‖X‖)^½ = (‖cof X‖ / (det X ‖X‖))^½ while far from converged, as
      // polar_newton_3d (sim/math.hpp).
      V gamma = splat<V>(T(1));
      const Mask scaled = active & (step2 > T(1e-4));
      if (any(scaled)) {  // the norms only for a step that scales
        V c_norm2 = V{}, x_norm2 = V{};
        for (int k = 0; k < 9; ++k) {
          c_norm2 += c.m[k] * c.m[k];
          x_norm2 += x.m[k] * x.m[k];
        }
        V ratio = c_norm2 / (d * d * x_norm2);
        ratio = scaled ? ratio : splat<V>(T(1));
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
    store_entries(s.m, stress_out[0].data());
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
    load_entries(F[0].data(), f);
    const V vmu = load_register<V>(mu), vlambda = load_register<V>(lambda);
    const V vvolume = load_register<V>(volume);
    const V a = f[0] + f[3], b = f[1] - f[2], n2 = a * a + b * b;
    V inverse_n;
    for (int l = 0; l < count; ++l) inverse_n[l] = T(1) / std::sqrt(n2[l]);  // vectorised
    const Mask rotated = n2 > T(0);
    const V c = rotated ? a * inverse_n : splat<V>(T(1)), s = rotated ? b * inverse_n : V{};
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
    store_entries(out, stress_out[0].data());
    store_register(psi_out, psi);
  }
};

}  // namespace apiclab
