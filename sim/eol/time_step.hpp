// The dynamic time step (Fan et al. 2013, Sec 3.6). First-order advection is stable for
//   Δt max_a |v*_a| / Δx ≤ α   (eq 30, α < 1).
// With the step's velocity v = v₀ + Δt v₁ (eq 31: v₀ the current velocity, v₁ = M⁻¹ f) and the
// split being linear (eq 32), v* = v₀* + Δt v₁*, and the bound becomes
//   γ₁ Δt² + γ₀ Δt − α = 0,   γ_j = max_i Σ_a |v*_{j,ia}| / Δx   (eq 33),
// whose positive root is the advection limit. It is capped by the explicit elastic limit
// ν Δx / (c + max|v*|) (c the fastest wave speed, v* the velocity through the object's own grid,
// so that a frame's constant velocity does not shorten the step; the paper treats elasticity
// explicitly too, Sec 5), by time.dt.value and by the frame time. Every step records which limit
// bound it.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "sim/math.hpp"

namespace apiclab::eol {

// Positive root of γ₁ Δt² + γ₀ Δt − α = 0 (written without cancellation); +inf when both γ
// vanish (nothing moves through the grid).
inline double advection_limit(double gamma0, double gamma1, double alpha) {
  const double disc = std::sqrt(gamma0 * gamma0 + 4.0 * gamma1 * alpha);
  const double denom = gamma0 + disc;
  return denom > 0 ? 2.0 * alpha / denom : std::numeric_limits<double>::infinity();
}

// The explicit elastic cap's ν under the rules whose time.dt.nu is MPM's particle Courant number
// (cfl, two-step): an MPM scene's ν = 1 blows rotating-disk up at t = 0.05 s under eol.
inline constexpr double kElasticNu = 0.3;

// Which bound set a step's Δt (the diagnostics' dt_limit column).
enum class DtLimit { advection, elastic, contact, max, frame, fixed };

inline const char* dt_limit_name(DtLimit l) {
  switch (l) {
    case DtLimit::advection:
      return "advection";
    case DtLimit::elastic:
      return "elastic";
    case DtLimit::contact:
      return "contact";
    case DtLimit::max:
      return "max";
    case DtLimit::frame:
      return "frame";
    case DtLimit::fixed:
      break;
  }
  return "fixed";
}

}  // namespace apiclab::eol
