// PolyPIC (Fu et al. 2017; MLS on velocities, Hu et al. 2018 Sec 3.2): per-particle polynomial
// velocity modes. Its linear modes are APIC's C; the higher modes' basis, gather, scatter and
// energy are sim/mpm/schemes/polypic_modes.hpp.
#pragma once
#include "sim/mpm/schemes/apic.hpp"

namespace apiclab::schemes {

struct PolyPic : Apic {
  static constexpr std::string_view key = "polypic", name = "PolyPIC";
  static constexpr std::string_view help =
      "PolyPIC (Fu, Guo, Gast, Jiang and Teran 2017; MLS on velocities with B-spline weights, "
      "Hu et al. 2018 Sec 3.2; no equation numbers reachable): per-particle polynomial velocity "
      "modes orthogonal under the weights, solver.polypic_modes of them (1 = PIC, 3 in 2D / 4 in "
      "3D = APIC's affine, 9 / 27 = all); quadratic kernel";
  static constexpr std::string_view source =
      "Fu et al. 2017 (MLS velocity modes, Hu et al. 2018 Sec 3.2)";
  static constexpr std::string_view conserves = "mass, linear and angular momentum";
  static constexpr int colour = 8;
  static constexpr bool higher_modes = true;
};

}  // namespace apiclab::schemes
