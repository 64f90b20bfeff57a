// What the implicit grid update (sim/mpm/implicit/implicit.hpp) keeps between its calls: the step's
// coefficients, the active nodes and constraints, Δv and ∇E, the per-particle F and ∂P/∂F at
// the force position, and Newton-CG's work vectors. Allocated once and reused every step.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/mpm/block_partition.hpp"
#include "sim/mpm/implicit/newton_cg.hpp"

namespace apiclab {

template <class T, int D>
struct ImplicitSolveState {
  // Forces at y_i = x_i + Δt (a v_i + b Δv_i) (see implicit.hpp).
  T dt = 0, a = 0, b = 0;
  Vec<T, D> gravity = Vec<T, D>::Zero();
  double mass_sum = 0, velocity_ref = 0;  // Σ m_i, and the mass-weighted RMS of v_i^n
  double energy_round_off = 0;  // of the last E evaluated (sim/mpm/implicit/round_off_floor.hpp)
  std::vector<std::uint32_t> active;               // nodes with mass
  std::vector<ConstrainedNode<T, D>> constraints;  // constraints acting this step
  std::vector<Vec<T, D>> dv, grad;                 // Δv = ṽ − v, ∇E(Δv)
  std::vector<Mat<T, D>> Fy;                       // F_p at the force position y
  // Per particle ∂P/∂F at y; in 2D folded with b Δt² V_p and Fⁿ into S_p (implicit.hpp).
  std::vector<Eigen::Matrix<T, D * D, D * D>> stiffness;
  std::vector<Mat<T, D>> block_inverse;  // block-Jacobi: each node's D×D block of H, inverted
  NewtonCgVectors<T, D> cg;
  std::vector<double> residuals;  // Newton residuals of the last step, in order
};

}  // namespace apiclab
