// What G2P hands each scheme's particle update (`update` in sim/mpm/schemes/pic.hpp, flip.hpp,
// ...).
#pragma once
#include "sim/math.hpp"

namespace apiclab {

// What G2P gathered at one particle: v^PIC = Σ w ṽ_i, Σ w v_i^n, and for the affine schemes
// C^APIC: B D⁻¹ (eq 38) or, for the multilinear kernel, Σ ṽ_i ∇w_ipᵀ (Sec 5.9). XPIC also
// gathers Σ w e_i of its grid field e (sim/mpm/schemes/xpic_passes.hpp); zero for the other
// schemes.
template <class T, int D>
struct GatheredVelocity {
  Vec<T, D> pic, old;
  Mat<T, D> apic_C;
  Vec<T, D> xpic_shift = Vec<T, D>::Zero();
};

}  // namespace apiclab
