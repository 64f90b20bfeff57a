// PIC (Jiang et al. 2017, eqs 1-2): the grid velocity interpolated back; dissipative.
#pragma once
#include "sim/mpm/schemes/scheme_base.hpp"

namespace apiclab::schemes {

struct Pic : SchemeBase {
  static constexpr std::string_view key = "pic", name = "PIC";
  static constexpr std::string_view help =
      "PIC, eqs 1-2: grid velocity interpolated back; dissipative";
  static constexpr std::string_view source = "Jiang et al. 2017, eqs 1-2";
  static constexpr std::string_view conserves =
      "mass, linear momentum; loses angular momentum and energy (dissipative)";
  static constexpr int colour = 0;

  // v_p and C_p from what G2P gathered (GatheredVelocity); `inertia()` gives D_p.
  template <class G, class T, class Inertia, class V, class M>
  static void update(const G& g, T /*alpha*/, bool /*lagged*/, Inertia&&, V& v, M& /*C*/) {
    v = g.pic;  // eq 2
  }
};

}  // namespace apiclab::schemes
