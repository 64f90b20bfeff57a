// APIC (Jiang et al. 2017, eqs 24-26, 37-40): an affine velocity v_p + C_p (x − x_p) per particle.
#pragma once
#include "sim/mpm/schemes/scheme_base.hpp"

namespace apiclab::schemes {

struct Apic : SchemeBase {
  static constexpr std::string_view key = "apic", name = "APIC";
  static constexpr std::string_view help =
      "APIC, eqs 24-26 and 37-40: affine velocity per particle";
  static constexpr std::string_view source = "Jiang et al. 2017, eqs 24-26, 37-40";
  static constexpr std::string_view conserves = "mass, linear and angular momentum (Sec 5.3)";
  static constexpr int colour = 2;
  static constexpr bool affine = true;

  // eq 37, with G2P's C^APIC: B D⁻¹ (eq 38) or, with the multilinear kernel, Σ ṽ ∇wᵀ (Sec 5.9).
  template <class G, class T, class Inertia, class V, class M>
  static void update(const G& g, T /*alpha*/, bool /*lagged*/, Inertia&&, V& v, M& C) {
    v = g.pic;
    C = g.apic_C;
  }
};

}  // namespace apiclab::schemes
