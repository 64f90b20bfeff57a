// The implicit solve's per-particle ∂P/∂F (sim/mpm/implicit/stress_hessian.hpp): against finite
// differences of P, and its projection: unchanged where positive definite (the Cholesky shortcut),
// the eigenvalues clamped at zero where not; both cases met, in 2D and 3D, for both models.
#include <gtest/gtest.h>

#include <random>

#include "sim/mpm/implicit/stress_hessian.hpp"

using namespace apiclab;

namespace {

template <int D>
Mat<double, D> random_deformation(std::mt19937_64& rng, double spread) {
  std::uniform_real_distribution<double> u(-spread, spread);
  Mat<double, D> F = Mat<double, D>::Identity();
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) F(a, b) += u(rng);
  return F;
}

template <int D>
void check_projection(MaterialModel model) {
  SCOPED_TRACE(::testing::Message() << "D = " << D << " model " << int(model));
  constexpr int N = D * D;
  using Matrix = Eigen::Matrix<double, N, N>;
  const Lame<double> l{38.0, 58.0};  // μ, λ: E = 100, ν ≈ 0.3
  std::mt19937_64 rng(5 + D);
  int definite = 0, projected = 0;
  for (int s = 0; s < 400; ++s) {
    // Mild to strong deformations, all with det F > 0 (both models' domain).
    const Mat<double, D> F = random_deformation<D>(rng, s % 2 ? 0.15 : 0.6);
    if (F.determinant() <= 0.1) continue;
    const Matrix H = stress_hessian<double, D>(model, F, l);
    // Column c of H is ∂P/∂F applied to the unit direction E_c: a central difference of P.
    const double h = 1e-6;
    for (int c = 0; c < N; ++c) {
      Mat<double, D> E = Mat<double, D>::Zero();
      E(c % D, c / D) = h;
      const Mat<double, D> dP =
          (first_piola<double, D>(model, F + E, l) - first_piola<double, D>(model, F - E, l)) /
          (2 * h);
      const Eigen::Map<const Eigen::Matrix<double, N, 1>> col(dP.data());
      // h² |P'''| and ε |P| / h: both far below 1e-4 of |∂P/∂F| ~ λ + 2μ ≈ 134.
      EXPECT_LE((H.col(c) - col).norm(), 1e-4 * H.norm()) << "column " << c;
    }
    const Matrix Hp = projected_stress_hessian<double, D>(model, F, l);
    // The oracle's eigensolver: dynamic size, one instantiation for both dimensions.
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
    const double scale = eig.eigenvalues().cwiseAbs().maxCoeff();
    if (eig.eigenvalues().minCoeff() > 1e-9 * scale) {
      ++definite;
      EXPECT_EQ(Hp, H) << "a positive definite ∂P/∂F is returned as it is";
    } else if (eig.eigenvalues().minCoeff() < -1e-9 * scale) {
      ++projected;
      const Eigen::MatrixXd expected = eig.eigenvectors() *
                                       eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
                                       eig.eigenvectors().transpose();
      EXPECT_LE((Hp - expected).norm(), 1e-12 * scale);
      EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Hp).eigenvalues().minCoeff(),
                -1e-12 * scale);
    }
  }
  // Both branches are taken by these deformations (so both are tested).
  EXPECT_GT(definite, 20);
  EXPECT_GT(projected, 20);
}

TEST(StressHessian, FixedCorotated2D) { check_projection<2>(MaterialModel::fixed_corotated); }
TEST(StressHessian, FixedCorotated3D) { check_projection<3>(MaterialModel::fixed_corotated); }
TEST(StressHessian, NeoHookean2D) { check_projection<2>(MaterialModel::neo_hookean); }
TEST(StressHessian, NeoHookean3D) { check_projection<3>(MaterialModel::neo_hookean); }

}  // namespace
