// A particle's ∂P/∂F as a D²×D² matrix, projected to be positive semi-definite: what the
// implicit grid update's Hessian product and block-Jacobi preconditioner read
// (sim/mpm/implicit/implicit.hpp).
#pragma once
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <cmath>

#include "sim/materials.hpp"

namespace apiclab {

// ∂P/∂F at F (column-major vec), column c the differential along the unit direction c.
template <class T, int D>
Eigen::Matrix<T, D * D, D * D> stress_differential_matrix(MaterialModel model, const Mat<T, D>& F,
                                                          Lame<T> l) {
  constexpr int N = D * D;
  Eigen::Matrix<T, N, N> H;
  for (int c = 0; c < N; ++c) {
    Mat<T, D> E = Mat<T, D>::Zero();
    E(c % D, c / D) = T(1);  // column-major vec
    Mat<T, D> dP = first_piola_differential<T, D>(model, F, E, l);
    H.col(c) = Eigen::Map<const Eigen::Matrix<T, N, 1>>(dP.data());
  }
  return H;
}

// The same, symmetrised. Exactly symmetric for hyperelastic P; the symmetrisation removes
// round-off so that the eigensolver below sees a symmetric matrix.
template <class T, int D>
Eigen::Matrix<T, D * D, D * D> stress_hessian(MaterialModel model, const Mat<T, D>& F, Lame<T> l) {
  const Eigen::Matrix<T, D * D, D* D> H = stress_differential_matrix<T, D>(model, F, l);
  return T(0.5) * (H + H.transpose());
}

// Neo-Hookean's ∂P/∂F less its negative modes, from the analytic eigensystem of an isotropic
// energy Ψ(σ) (Teran et al. 2005, Sec 5; Smith et al. 2019): with F = U Σ Vᵀ, the D² modes are
// U Q Vᵀ for Q = (e_i e_jᵀ ∓ e_j e_iᵀ)/√2, i < j, with eigenvalues (Ψ_i ± Ψ_j)/(σ_i ± σ_j), and
// Q = diag(e) for the eigenvectors e of ∂²Ψ/∂σ². With Ψ_i = μ σ_i + (λ log J − μ)/σ_i these are
//   twist (−): μ + (λ log J − μ)/(σ_i σ_j),   the other (+): μ − (λ log J − μ)/(σ_i σ_j),
//   ∂²Ψ/∂σ² = diag(μ + (μ − λ log J)/σ_i²) + λ s sᵀ,  s_i = 1/σ_i,
// so a compressed particle's twists go negative while its ∂P/∂F at rest has D(D−1)/2 zero
// twists (why a Cholesky test alone sends most particles to the eigensolver). Returns false
// where it does not apply (J ≤ 0), leaving H as it was.
template <class T, int D>
bool remove_negative_modes_neo_hookean(const Mat<T, D>& F, Lame<T> l,
                                       Eigen::Matrix<T, D * D, D * D>& H) {
  const T J = F.determinant();
  if (!(J > T(0))) return false;
  Eigen::JacobiSVD<Mat<T, D>> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Mat<T, D>&U = svd.matrixU(), &V = svd.matrixV();  // det U det V = 1 since J > 0
  const Vec<T, D> sigma = svd.singularValues();
  const T c = l.lambda * std::log(J) - l.mu;
  const auto remove = [&](T eigenvalue, const Mat<T, D>& Q) {  // H −= λ q qᵀ, q = vec(U Q Vᵀ)
    const Mat<T, D> mode = U * Q * V.transpose();
    const Eigen::Map<const Eigen::Matrix<T, D * D, 1>> q(mode.data());
    H.noalias() -= eigenvalue * q * q.transpose();
  };
  for (int i = 0; i < D; ++i)
    for (int j = i + 1; j < D; ++j)
      for (const T sign : {T(-1), T(1)}) {  // twist (Q antisymmetric), then the other
        const T eigenvalue = l.mu - sign * (c / (sigma[i] * sigma[j]));
        if (!(eigenvalue < T(0))) continue;
        Mat<T, D> Q = Mat<T, D>::Zero();
        Q(i, j) = T(1) / std::sqrt(T(2));
        Q(j, i) = sign * Q(i, j);
        remove(eigenvalue, Q);
      }
  const Vec<T, D> s = sigma.cwiseInverse();
  Mat<T, D> stretch = l.lambda * s * s.transpose();
  for (int i = 0; i < D; ++i) stretch(i, i) += l.mu - c * s[i] * s[i];
  Eigen::SelfAdjointEigenSolver<Mat<T, D>> eig;
  eig.computeDirect(stretch);
  for (int k = 0; k < D; ++k)
    if (eig.eigenvalues()[k] < T(0))
      remove(eig.eigenvalues()[k], Mat<T, D>(eig.eigenvectors().col(k).asDiagonal()));
  return true;
}

// A symmetric matrix with its negative eigenvalues set to zero, in place (stress_hessian.cpp):
// one eigensolver, in double, for every precision and dimension, since it is the slowest
// template to compile and reached only where the closed forms above do not apply.
void clamp_negative_eigenvalues(Eigen::MatrixXd& symmetric);

// stress_hessian with negative eigenvalues clamped to zero, as Stomakhin et al. 2012 and Teran
// et al. 2005 do per particle, so CG always sees a positive definite M + bΔt²K.
template <class T, int D>
Eigen::Matrix<T, D * D, D * D> projected_stress_hessian(MaterialModel model, const Mat<T, D>& F,
                                                        Lame<T> l) {
  constexpr int N = D * D;
  Eigen::Matrix<T, N, N> H = stress_hessian<T, D>(model, F, l);
  // A particle whose ∂P/∂F is positive definite as it is: a Cholesky factorisation (N³/6
  // multiply-adds) says so. The others: neo-Hookean's modes in closed form, else the eigensolver.
  if (Eigen::LLT<Eigen::Matrix<T, N, N>>(H).info() == Eigen::Success) return H;
  if (model != MaterialModel::fixed_corotated && remove_negative_modes_neo_hookean<T, D>(F, l, H))
    return H;
  Eigen::MatrixXd clamped = H.template cast<double>();
  clamp_negative_eigenvalues(clamped);
  return clamped.template cast<T>();
}

// Compiled once per precision and dimension in stress_hessian.cpp, shared by the solver and its
// tests: ∂P/∂F's fixed-size Eigen code is among the slowest templates of the build.
#define APICLAB_STRESS_HESSIAN(EXTERN, T, D)                                                      \
  EXTERN template Eigen::Matrix<T, D * D, D * D> stress_differential_matrix<T, D>(                \
      MaterialModel, const Mat<T, D>&, Lame<T>);                                                  \
  EXTERN template Eigen::Matrix<T, D * D, D * D> stress_hessian<T, D>(MaterialModel,              \
                                                                      const Mat<T, D>&, Lame<T>); \
  EXTERN template Eigen::Matrix<T, D * D, D * D> projected_stress_hessian<T, D>(                  \
      MaterialModel, const Mat<T, D>&, Lame<T>);
APICLAB_STRESS_HESSIAN(extern, double, 2)
APICLAB_STRESS_HESSIAN(extern, double, 3)

// In float, ∂P/∂F is computed in double and rounded once: a second set of fixed-size SVD,
// Cholesky and differential templates would double the file's compile for a less exact matrix.
#define APICLAB_STRESS_HESSIAN_FLOAT(D)                                                            \
  template <>                                                                                      \
  Eigen::Matrix<float, D * D, D * D> stress_differential_matrix<float, D>(                         \
      MaterialModel, const Mat<float, D>&, Lame<float>);                                           \
  template <>                                                                                      \
  Eigen::Matrix<float, D * D, D * D> stress_hessian<float, D>(MaterialModel, const Mat<float, D>&, \
                                                              Lame<float>);                        \
  template <>                                                                                      \
  Eigen::Matrix<float, D * D, D * D> projected_stress_hessian<float, D>(                           \
      MaterialModel, const Mat<float, D>&, Lame<float>);
APICLAB_STRESS_HESSIAN_FLOAT(2)
APICLAB_STRESS_HESSIAN_FLOAT(3)
#undef APICLAB_STRESS_HESSIAN_FLOAT

}  // namespace apiclab
