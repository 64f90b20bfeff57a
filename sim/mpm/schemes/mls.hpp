// MLS-MPM (Hu et al. 2018, Sec 4): APIC's transfers, C as the velocity gradient that moves F
// (eq 17), and the force of eq 18 fused into P2G's affine term (Q_p, Sec 6).
#pragma once
#include "sim/mpm/schemes/apic.hpp"

namespace apiclab::schemes {

struct Mls : Apic {
  static constexpr std::string_view key = "mls", name = "MLS";
  static constexpr std::string_view help =
      "MLS-MPM (Hu et al. 2018, Sec 4): APIC's transfers, C as the velocity gradient, F <- (I + "
      "dt C) F (eq 17); the force of eq 18, -V0 dPsi/dF F^T M_p^-1 w (x_i - x_p), fused into "
      "P2G's affine term (Q_p, Sec 6); quadratic or cubic, symplectic Euler";
  static constexpr std::string_view source = "Hu et al. 2018, Sec 4, eqs 17-18";
  static constexpr std::string_view conserves =
      "mass, linear and angular momentum (APIC's transfers)";
  static constexpr int colour = 4;
  static constexpr bool force_in_affine = true;  // f_i = −Σ V P Fᵀ D⁻¹ w (x_i − x_p)
  static constexpr bool moves_f_by_c = true;     // eq 17
};

}  // namespace apiclab::schemes
