// A hand on the implicit solve (sim/mpm/implicit/implicit.hpp) for the tests that check its
// energy E, gradient ∇E and Hessian H against finite differences and its preconditioner:
// implicit_begin after a P2G without forces (MpmProbe), then E, ∇E and H at a given Δv.
// MpmSimulation keeps these private; the probe is its friend.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/mpm/mpm.hpp"

namespace apiclab {

// Sim is MpmSimulation<T, D>: ImplicitProbe(sim).template implicit_begin<K>(dt).
template <class Sim>
class ImplicitProbe {
 public:
  using T = typename Sim::Scalar;
  static constexpr int D = Sim::Dim;
  using Field = std::vector<Vec<T, D>>;  // one vector per grid node
  explicit ImplicitProbe(Sim& sim) : sim_(sim) {}

  template <class K>
  void implicit_begin(T dt) const {
    sim_.template implicit_begin<K>(dt);
  }
  template <class K>
  double implicit_energy(const Field& dv, bool gradient) const {
    return sim_.template implicit_energy<K>(dv, gradient);
  }
  void implicit_update_hessian(bool project_definite) const {
    sim_.implicit_update_hessian(project_definite);
  }
  template <class K>
  void implicit_hessian_apply(const Field& in, Field& out) const {
    sim_.template implicit_hessian_apply<K>(in, out);
  }
  template <class K>
  void implicit_block_jacobi() const {  // after implicit_update_hessian
    sim_.template implicit_block_jacobi<K>();
  }
  const std::vector<Mat<T, D>>& block_jacobi_inverse() const { return sim_.imp_.block_inverse; }
  const std::vector<std::uint32_t>& active_nodes() const { return sim_.imp_.active; }
  const Field& implicit_gradient() const { return sim_.imp_.grad; }
  // Newton residuals (mass-weighted RMS of M⁻¹g) of the last implicit step, in order.
  const std::vector<double>& newton_residuals() const { return sim_.imp_.residuals; }

 private:
  Sim& sim_;
};

}  // namespace apiclab
