// The smallest Newton and CG tolerances the implicit grid update (sim/mpm/implicit/implicit.hpp)
// can meet in the scalar type T: a tolerance below them is raised to them, so that float does not
// spend its Newton and CG caps chasing round-off (torus-drop in float spent its 20 Newton
// iterations and thousands of CG ones on a free-fall step that double solves in one).
//
// Newton's residual is r = M⁻¹ P ∇E, a velocity (sim/mpm/implicit/newton_cg.hpp), with
//   M⁻¹∇E_i = Δv_i − Δt g − (Δt / m_i) f_i(y),   f_i = −Σ_p V_p P(F_y) F_pᵀ ∇w_ip.
// Each term is computed in T. The velocity terms carry round-off ε_T v (v: the step's velocity
// scale, max of the grid's RMS speed and |g| Δt). The force term carries more: F_y = (I +
// Δt Σ_i u_i ∇w_ipᵀ) F_p sums gradients of size 1/Δx that cancel (Σ_i ∇w_ip = 0), so F_y is
// off by δF ≈ ε_T Δt v / Δx; the stress by (λ + 2μ) δF; and the force term, with V_p / m_i ≈
// 1/ρ and one more ∇w of size 1/Δx, by
//   (Δt / ρ) (λ + 2μ) δF / Δx = ε_T v (c Δt / Δx)²,   c = √((λ + 2μ)/ρ), the P-wave speed.
// The stress itself carries ε_T (λ + 2μ)|F|²: its terms (μF, (λ log J − μ)F⁻ᵀ, ...) are each of
// that size and cancel to P ≈ 0 near rest, so the force term is off by (Δt / ρ)(λ + 2μ) ε_T / Δx
// = ε_T c (c Δt / Δx) whatever the velocity: a body at rest, or one whose motion has decayed
// (PIC), holds its residual there.
// So the residual cannot be resolved below  ε_T (v (1 + (c Δt / Δx)²) + c (c Δt / Δx)).  The
// same factor bounds
// the condition number of CG's operator M⁻¹H = I + b Δt² M⁻¹K (eigenvalues in [1, 1 + b (c Δt /
// Δx)² k], k an O(1) stencil constant), and a relative CG residual below ε_T κ is round-off;
// CG's floor is therefore  ε_T (1 + b (c Δt / Δx)²).  These are worst-case bounds (every
// rounding error of the same sign): on torus-drop in float (v = g Δt = 0.196 m/s, c Δt / Δx =
// 22.3) a solve without the floor stalled at a residual of 2.2e-7, 0.02 of the velocity term
// 1.2e-5, so the bound needs no further safety factor. In double the floors sit near 1e-11 v,
// far below any tolerance in use; in float they decide.
//
// Energies carry the same round-off: Σ V Ψ(F) sums terms of size V (λ + 2μ)|F|² that cancel near
// rest, so it is known to ε_T Σ V (λ + 2μ)|F|² = ε_T D Σ m c² at F = I (energy_round_off). The
// line search's energy comparisons and the blow-up checks' energy available are held to it.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

namespace apiclab {

struct RoundOffFloor {
  double newton;  // on Newton's residual, a velocity (same units as v)
  double cg;      // on CG's residual relative to its first
};

// v: the step's velocity scale; c: the largest P-wave speed of the materials; b: the force
// position's weight on Δv (sim/mpm/implicit/implicit.hpp: ½·½ for midpoint, 1 for backward Euler).
template <class T>
RoundOffFloor implicit_round_off_floor(double v, double dt, double dx, double c, double b) {
  const double eps = double(std::numeric_limits<T>::epsilon());
  const double courant2 = (c * dt / dx) * (c * dt / dx);  // (c Δt / Δx)²
  return {eps * (v * (1 + courant2) + c * std::sqrt(courant2)), eps * (1 + b * courant2)};
}

// The energy a scene's round-off can show with nothing moving: ε_T D Σ m c² (above), for
// `mass_c2` = Σ m c² (a bound: the total mass times the largest c²). An energy below it is a
// body at rest, not a blow-up.
template <class T>
double energy_round_off(double mass_c2, int dim) {
  return double(std::numeric_limits<T>::epsilon()) * dim * mass_c2;
}

}  // namespace apiclab
