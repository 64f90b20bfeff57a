// The per-scheme particle velocity and affine matrix after G2P (Jiang et al. 2017, Secs 5.1-5.9):
// PIC (eq 2), FLIP (eq 3), APIC (eqs 37-38), RPIC (Sec 5.6.3), ASFLIP (Fei et al. 2021),
// XPIC(m) (Hammerquist and Nairn 2017, with sim/mpm/schemes/xpic.hpp), TPIC and PolyPIC. Also the
// C_p a live scheme switch keeps (set_scheme).
#pragma once
#include "sim/math.hpp"
#include "sim/scene/registry.hpp"

namespace apiclab {

// RPIC keeps only the rigid part of C: its skew part, ω = K⁻¹ l (Sec 5.6.3), with D_p = k Δx² I.
template <class T, int D>
Mat<T, D> rpic_skew_part(const Mat<T, D>& C) {
  return T(0.5) * (C - C.transpose());
}

// RPIC with the multilinear kernel, whose D_p is not a multiple of I (Sec 5.9): ω = K_p⁻¹ l_p
// with K_p = tr(D_p) I − D_p and l_p the skew part of B = C D_p (Sec 2.1).
template <class T, int D>
Mat<T, D> rpic_rigid_part(const Mat<T, D>& C, const Mat<T, D>& Dp) {
  const Mat<T, D> B = C * Dp;
  const Mat<T, D> skewB = T(0.5) * (B - B.transpose());
  Mat<T, D> Cr = Mat<T, D>::Zero();
  if constexpr (D == 2) {
    T kk = Dp.trace();
    T w = kk > T(0) ? T(2) * skewB(1, 0) / kk : T(0);
    Cr << T(0), -w, w, T(0);
  } else {
    Vec<T, 3> l(T(2) * skewB(2, 1), T(2) * skewB(0, 2), T(2) * skewB(1, 0));
    Vec<T, 3> w;
    for (int a = 0; a < 3; ++a) {
      T kk = Dp.trace() - Dp(a, a);
      w[a] = kk > T(0) ? l[a] / kk : T(0);
    }
    Cr << T(0), -w[2], w[1], w[2], T(0), -w[0], -w[1], w[0], T(0);
  }
  return Cr;
}

// What G2P gathered at one particle: v^PIC = Σ w ṽ_i, Σ w v_i^n, and for the affine schemes
// C^APIC: B D⁻¹ (eq 38) or, for the multilinear kernel, Σ ṽ_i ∇w_ipᵀ (Sec 5.9). XPIC also
// gathers Σ w e_i of its grid field e (sim/mpm/schemes/xpic.hpp); zero for the other schemes.
template <class T, int D>
struct GatheredVelocity {
  Vec<T, D> pic, old;
  Mat<T, D> apic_C;
  Vec<T, D> xpic_shift = Vec<T, D>::Zero();
};

// v_p and C_p of scheme S from the gathered velocities; `inertia()` gives D_p, read only by RPIC
// with the multilinear kernel (`lagged`).
template <Scheme S, class T, int D, class Inertia>
inline void update_particle_velocity(const GatheredVelocity<T, D>& g, T flip_alpha, bool lagged,
                                     Inertia&& inertia, Vec<T, D>& v, Mat<T, D>& C) {
  if constexpr (S == Scheme::pic) {
    v = g.pic;  // eq 2
  } else if constexpr (S == Scheme::flip) {
    v = flip_alpha * (v + g.pic - g.old) + (T(1) - flip_alpha) * g.pic;  // eq 3, PIC blend
  } else if constexpr (S == Scheme::apic || S == Scheme::mls || S == Scheme::tpic ||
                       S == Scheme::polypic) {
    // eq 37 (MLS-MPM keeps APIC's transfers; TPIC's C is ∇v_p; PolyPIC's linear modes are
    // APIC's C, its higher modes are gathered in sim/mpm/g2p.hpp)
    v = g.pic;
    C = g.apic_C;
  } else if constexpr (S == Scheme::asflip) {
    // Fei et al. 2021: APIC's v^PIC and C plus α times the particle's own FLIP difference
    // v_p^n − Σ w v_i^n (v_i^n from APIC's affine P2G); α = 0 is APIC.
    v = g.pic + flip_alpha * (v - g.old);
    C = g.apic_C;
  } else if constexpr (S == Scheme::xpic) {
    // Hammerquist and Nairn 2017: V^{n+1} = S (ṽ − vⁿ + v*) = v^PIC + Σ w e_i with
    // e = v* − vⁿ; e = 0 for m = 1 (PIC).
    v = g.pic + g.xpic_shift;
  } else {
    v = g.pic;
    C = lagged ? rpic_rigid_part<T, D>(g.apic_C, inertia()) : rpic_skew_part<T, D>(g.apic_C);
  }
}

}  // namespace apiclab
