// A particle's ∂P/∂F as a D²×D² matrix, projected to be positive semi-definite: what the
// implicit grid update's Hessian product and block-Jacobi preconditioner read (sim/implicit.hpp).
#pragma once
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "materials.hpp"

namespace apiclab {

// ∂P/∂F at F (column-major vec), symmetrised. Exactly symmetric for hyperelastic P; the
// symmetrisation removes round-off so that the eigensolver below sees a symmetric matrix.
template <class T, int D>
Eigen::Matrix<T, D * D, D * D> stress_hessian(MaterialModel model, const Mat<T, D>& F, Lame<T> l) {
  constexpr int N = D * D;
  Eigen::Matrix<T, N, N> H;
  for (int c = 0; c < N; ++c) {
    Mat<T, D> E = Mat<T, D>::Zero();
    E(c % D, c / D) = T(1);  // column-major vec
    Mat<T, D> dP = first_piola_differential<T, D>(model, F, E, l);
    H.col(c) = Eigen::Map<const Eigen::Matrix<T, N, 1>>(dP.data());
  }
  return T(0.5) * (H + H.transpose());
}

// stress_hessian with negative eigenvalues clamped to zero, as Stomakhin et al. 2012 and Teran
// et al. 2005 do per particle, so CG always sees a positive definite M + bΔt²K.
template <class T, int D>
Eigen::Matrix<T, D * D, D * D> projected_stress_hessian(MaterialModel model, const Mat<T, D>& F,
                                                        Lame<T> l) {
  constexpr int N = D * D;
  const Eigen::Matrix<T, N, N> H = stress_hessian<T, D>(model, F, l);
  // Most particles' ∂P/∂F is positive definite as it is: a Cholesky factorisation (N³/6
  // multiply-adds) says so, and only the others pay for the eigensolver.
  if (Eigen::LLT<Eigen::Matrix<T, N, N>>(H).info() == Eigen::Success) return H;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<T, N, N>> eig(H);
  Eigen::Matrix<T, N, 1> ev = eig.eigenvalues();
  if (ev.minCoeff() >= T(0)) return H;
  ev = ev.cwiseMax(T(0));
  return eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace apiclab
