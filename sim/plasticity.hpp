// Multiplicative plasticity (Fan et al. 2013, Sec 3.7, after Bargteil et al. 2007): F = F_e F_p
// (eq 34), (F_p⁻¹)^{t+1} = (F_p⁻¹)^t ΔF_p⁻¹ (eq 35), with F_e = U Σ Vᵀ (eq 36) and
//   ΔF_p⁻¹ = V (Σ / (det Σ)^{1/d})^{−γ} Vᵀ,  γ = ν (‖σ‖ − σ_y) / ‖σ‖ clamped to [0, 1]   (eq 37),
// σ the deviatoric Cauchy stress of the plastic model's neo-Hookean F_e (Bargteil's von Mises
// measure: eq 37 only moves the deviatoric stretch, so a pressure alone never yields). The
// EoL solver keeps F_p⁻¹ at material samples, MPM per particle; both update it here.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/materials.hpp"
#include "sim/math.hpp"

namespace apiclab {

template <class T>
struct PlasticParams {
  T yield_stress = std::numeric_limits<T>::infinity();  // ‖σ_y‖
  T flow_rate = T(0);                                   // ν
};

// ‖σ_dev‖ of F_e without a decomposition: σ = τ/J, τ_dev = μ (b − tr b/d I), b = F_e F_eᵀ.
template <class T, int D>
T deviatoric_stress_norm(const Mat<T, D>& Fe, Lame<T> l) {
  const T J = Fe.determinant();
  if (!(J > T(0))) return T(0);
  Mat<T, D> b = Fe * Fe.transpose();
  b.diagonal().array() -= b.trace() / T(D);
  return l.mu / J * b.norm();
}

// Eq 37 for one point: ΔF_p⁻¹ into dFp_inv, false below yield (dFp_inv untouched, the caller
// keeps F_p bit for bit) or for an inverted F_e.
template <class T, int D>
bool plastic_flow_step(const Mat<T, D>& Fe, Lame<T> l, PlasticParams<T> p, Mat<T, D>& dFp_inv) {
  const T norm = deviatoric_stress_norm<T, D>(Fe, l);
  if (!(norm > p.yield_stress)) return false;
  const T gamma = std::clamp(p.flow_rate * (norm - p.yield_stress) / norm, T(0), T(1));
  const Eigen::JacobiSVD<Mat<T, D>> svd(Fe, Eigen::ComputeFullV);
  const Vec<T, D> s = svd.singularValues();
  if (!(s.minCoeff() > T(0))) return false;
  // (σ_i / (Π σ)^{1/d})^{−γ} = exp(−γ (log σ_i − mean log σ)): the factors' product is 1.
  const Vec<T, D> logs = s.array().log().matrix();
  const Vec<T, D> scale = (-gamma * (logs.array() - logs.mean())).exp().matrix();
  const Mat<T, D>& V = svd.matrixV();
  dFp_inv = V * scale.asDiagonal() * V.transpose();
  return true;
}

}  // namespace apiclab
