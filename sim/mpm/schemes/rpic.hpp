// RPIC (Jiang et al. 2017, Secs 2.1, 5.1, 5.6.3): only the rigid part of APIC's affine velocity,
// C_p = ω_p*, which damps non-rigid motion like PIC.
#pragma once
#include "sim/mpm/schemes/scheme_base.hpp"

namespace apiclab::schemes {

struct Rpic : SchemeBase {
  static constexpr std::string_view key = "rpic", name = "RPIC";
  static constexpr std::string_view help =
      "RPIC, Secs 2.1 and 5.1: rigid (skew) velocity per particle";
  static constexpr std::string_view source = "Jiang et al. 2017, Secs 2.1, 5.1";
  static constexpr std::string_view conserves =
      "mass, linear and angular momentum; damps non-rigid motion like PIC";
  static constexpr int colour = 3;
  static constexpr bool affine = true;

  // The skew part of C: ω = K⁻¹ l (Sec 5.6.3) with D_p = k Δx² I.
  template <class M>
  static M skew_part(const M& C) {
    using T = typename M::Scalar;
    return T(0.5) * (C - C.transpose());
  }

  // With the multilinear kernel, whose D_p is not a multiple of I (Sec 5.9): ω = K_p⁻¹ l_p with
  // K_p = tr(D_p) I − D_p and l_p the skew part of B = C D_p (Sec 2.1).
  template <class M>
  static M rigid_part(const M& C, const M& Dp) {
    using T = typename M::Scalar;
    const M B = C * Dp;
    const M skewB = T(0.5) * (B - B.transpose());
    M Cr = M::Zero();
    if constexpr (M::RowsAtCompileTime == 2) {
      T kk = Dp.trace();
      T w = kk > T(0) ? T(2) * skewB(1, 0) / kk : T(0);
      Cr << T(0), -w, w, T(0);
    } else {
      const T l[3] = {T(2) * skewB(2, 1), T(2) * skewB(0, 2), T(2) * skewB(1, 0)};
      T w[3];
      for (int a = 0; a < 3; ++a) {
        T kk = Dp.trace() - Dp(a, a);
        w[a] = kk > T(0) ? l[a] / kk : T(0);
      }
      Cr << T(0), -w[2], w[1], w[2], T(0), -w[0], -w[1], w[0], T(0);
    }
    return Cr;
  }

  // eq 44 and C's rigid part; `inertia()` gives D_p, read with the multilinear kernel (`lagged`).
  template <class G, class T, class Inertia, class V, class M>
  static void update(const G& g, T /*alpha*/, bool lagged, Inertia&& inertia, V& v, M& C) {
    v = g.pic;
    C = lagged ? rigid_part<M>(g.apic_C, inertia()) : skew_part<M>(g.apic_C);
  }
};

}  // namespace apiclab::schemes
