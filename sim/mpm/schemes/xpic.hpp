// XPIC(m) (Hammerquist and Nairn 2017): PIC plus the m-term series of the particle-grid-particle
// operator. Its m − 1 grid passes, which make the grid field e = v* − vⁿ, are
// sim/mpm/schemes/xpic_passes.hpp.
#pragma once
#include "sim/mpm/schemes/scheme_base.hpp"

namespace apiclab::schemes {

struct Xpic : SchemeBase {
  static constexpr std::string_view key = "xpic", name = "XPIC";
  static constexpr std::string_view help =
      "XPIC(m) (Hammerquist and Nairn 2017; their v* = sum_r (-1)^r v*_r, v*_r = (m-r+1)/r "
      "S+S v*_{r-1}, as Tesserae.jl documents it): PIC plus the m-term series of the "
      "particle-grid-particle operator, v <- (I - (I - S S+)^m) v_p + S a dt; m = "
      "solver.xpic_order, XPIC(1) = PIC";
  static constexpr std::string_view source = "Hammerquist and Nairn 2017, XPIC(m)";
  static constexpr std::string_view conserves =
      "mass, linear momentum; not angular momentum (as PIC)";
  static constexpr int colour = 6;
  static constexpr bool grid_field = true;

  // V^{n+1} = S (ṽ − vⁿ + v*) = v^PIC + Σ w e_i; e = 0 for m = 1 (PIC).
  template <class G, class T, class Inertia, class V, class M>
  static void update(const G& g, T /*alpha*/, bool /*lagged*/, Inertia&&, V& v, M& /*C*/) {
    v = g.pic + g.xpic_shift;
  }
};

}  // namespace apiclab::schemes
