// FLIP (Jiang et al. 2017, eq 3): particles keep the grid's velocity increment, blended with PIC
// by α = solver.flip_alpha.
#pragma once
#include "sim/mpm/schemes/scheme_base.hpp"

namespace apiclab::schemes {

struct Flip : SchemeBase {
  static constexpr std::string_view key = "flip", name = "FLIP";
  static constexpr std::string_view help =
      "FLIP/PIC blend, eq 3: particles keep grid velocity increments";
  static constexpr std::string_view source = "Jiang et al. 2017, eq 3 (PIC/FLIP blend α)";
  static constexpr std::string_view conserves =
      "mass, linear momentum; not angular momentum; keeps energy as noise";
  static constexpr int colour = 1;
  static constexpr bool reads_old = true;

  template <class G, class T, class Inertia, class V, class M>
  static void update(const G& g, T alpha, bool /*lagged*/, Inertia&&, V& v, M& /*C*/) {
    v = alpha * (v + g.pic - g.old) + (T(1) - alpha) * g.pic;  // eq 3, PIC blend
  }
};

}  // namespace apiclab::schemes
