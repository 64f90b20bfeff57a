// The plastic model in MPM, the twin of the EoL solver's (sim/eol/eol_plasticity.hpp): the
// classic multiplicative update per particle (Stomakhin et al. 2013). F holds F_e; after G2P's
// F_e ← (I + Δt ∇v) F_e, eq 37 gives ΔF_p⁻¹ from it, and F_e ← F_e ΔF_p⁻¹, F_p⁻¹ ← F_p⁻¹ ΔF_p⁻¹
// (eq 35), so F_e F_p is the total F. Below yield neither changes.
#pragma once
#include <algorithm>
#include <cmath>

#include "sim/mpm/mpm.hpp"

namespace apiclab {

template <class T, int D>
void MpmSimulation<T, D>::plastic_flow() {
  const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
  std::size_t flowed = 0;
  double det_error = 0;
#pragma omp parallel for schedule(static) if (parallel_worthwhile()) reduction(+ : flowed) \
    reduction(max : det_error)
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const MaterialParams<T>& mat = materials_[std::size_t(p_.material[q])];
    if (mat.model != MaterialModel::plastic || p_.volume0[q] == T(0)) continue;
    Mat<T, D> dFp_inv;
    if (!plastic_flow_step<T, D>(p_.F[q], mat.lame, mat.plastic, dFp_inv)) continue;
    p_.F[q] = (p_.F[q] * dFp_inv).eval();
    p_.fp_inv[q] = (p_.fp_inv[q] * dFp_inv).eval();
    ++flowed;
    det_error = std::max(det_error, std::abs(double(dFp_inv.determinant()) - 1.0));
  }
  plastic_flowed_ = flowed;
  plastic_det_error_ = det_error;
}

}  // namespace apiclab
