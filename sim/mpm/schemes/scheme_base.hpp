// What every transfer scheme states, and the defaults its own file (pic.hpp, flip.hpp, ...)
// overrides. A scheme file is light: its update is a template over the solver's vector and
// matrix types, so sim/scene/scheme_registry.hpp includes it without Eigen.
#pragma once
#include <string_view>

namespace apiclab::schemes {

struct SchemeBase {
  static constexpr int colour = 9;  // its slot in render/palette.hpp's kPalette (9: grey)
  // Carries C_p: P2G transfers v_p + C_p (x_i − x_p) (eq 24), and the energy reads ½ m tr(C D Cᵀ).
  static constexpr bool affine = false;
  static constexpr bool reads_old = false;        // G2P reads Σ w vⁿ (FLIP's increment)
  static constexpr bool c_from_gradient = false;  // C = Σ ṽ ∇wᵀ with every kernel, not eq 38
  static constexpr bool force_in_affine = false;  // the stress rides P2G's affine term
  static constexpr bool moves_f_by_c = false;     // F ← (I + Δt C) F instead of ∇u
  static constexpr bool grid_field = false;       // grid passes before G2P, Σ w e_i gathered
  static constexpr bool higher_modes = false;     // velocity modes beyond the affine ones
  static constexpr bool corrects_move = false;    // x moves by more than Δt ū (correct_move)
};

}  // namespace apiclab::schemes
