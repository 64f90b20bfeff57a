// TPIC (Nakamura et al. 2023, Taylor PIC): P2G transfers v_p + ∇v_p (x_i − x_p), a first-order
// Taylor expansion, and G2P's C is ∇v_p = Σ ṽ_i ∇w_ipᵀ with every kernel.
#pragma once
#include "sim/mpm/schemes/apic.hpp"

namespace apiclab::schemes {

struct Tpic : Apic {
  static constexpr std::string_view key = "tpic", name = "TPIC";
  static constexpr std::string_view help =
      "TPIC (Nakamura et al. 2023, as the first author's Tesserae.jl documents it; no equation "
      "numbers reachable): P2G m v_i = sum w m (v_p + grad v_p (x_i - x_p)), G2P grad v_p = "
      "sum v_i grad w_ip^T (a first-order Taylor expansion); every kernel";
  static constexpr std::string_view source = "Nakamura et al. 2023 (Taylor PIC)";
  static constexpr std::string_view conserves =
      "mass, linear momentum; angular momentum in P2G, not in G2P with B-splines";
  static constexpr int colour = 7;
  static constexpr bool c_from_gradient = true;
};

}  // namespace apiclab::schemes
