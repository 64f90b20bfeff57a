// Hyperelastic models (neo-Hookean, fixed corotated), 2D and 3D: P = ∂Ψ/∂F and the action of
// ∂P/∂F against central finite differences, rotation invariance, rest state, inversion.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "sim/materials.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {
namespace {

template <int D>
using M = Mat<double, D>;

Lame<double> lame() {
  MaterialDesc m;
  m.E = 1000;
  m.nu = 0.3;
  return {m.mu(), m.lambda()};
}

template <int D>
M<D> random_F(std::mt19937_64& rng, double spread) {
  std::uniform_real_distribution<double> u(-spread, spread);
  for (;;) {
    M<D> F = M<D>::Identity();
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) F(i, j) += u(rng);
    if (F.determinant() > 0.2) return F;
  }
}

template <int D>
M<D> random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  M<D> A;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) A(i, j) = n(rng);
  Eigen::HouseholderQR<M<D>> qr(A);
  M<D> Q = qr.householderQ();
  if (Q.determinant() < 0) Q.col(0) *= -1;
  return Q;
}

template <int D>
void check_model(MaterialModel model) {
  SCOPED_TRACE(::testing::Message() << key_of(model) << " " << D << "D");
  std::mt19937_64 rng(7 + D + 10 * int(model));
  const Lame<double> l = lame();
  const double h = 1e-6;
  for (int s = 0; s < 50; ++s) {
    M<D> F = random_F<D>(rng, 0.4);
    const double psi = energy_density<double, D>(model, F, l);
    const M<D> P = first_piola<double, D>(model, F, l);
    ASSERT_TRUE(std::isfinite(psi));
    // P = ∂Ψ/∂F, entry by entry. Central differences: truncation h²/6·|Ψ'''| (Ψ''' ~ λ, μ ~ 1e3,
    // so ~2e-10) plus rounding ε·|Ψ|/h (~1e-8 for |Ψ| ~ 1e2): 1e-6 relative to |P| + μ.
    M<D> Pfd;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) {
        M<D> Fp = F, Fm = F;
        Fp(i, j) += h;
        Fm(i, j) -= h;
        Pfd(i, j) =
            (energy_density<double, D>(model, Fp, l) - energy_density<double, D>(model, Fm, l)) /
            (2 * h);
      }
    EXPECT_LE((P - Pfd).norm(), 1e-6 * (P.norm() + l.mu)) << "F =\n"
                                                          << F << "\nP =\n"
                                                          << P << "\nFD =\n"
                                                          << Pfd;
    // ∂P/∂F : dF against central differences of P along dF (same error budget, one order up).
    for (int k = 0; k < 3; ++k) {
      M<D> dF = M<D>::Random();
      M<D> dP = first_piola_differential<double, D>(model, F, dF, l);
      M<D> dPfd = (first_piola<double, D>(model, F + h * dF, l) -
                   first_piola<double, D>(model, F - h * dF, l)) /
                  (2 * h);
      EXPECT_LE((dP - dPfd).norm(), 1e-6 * (dP.norm() + l.mu + l.lambda)) << "F =\n"
                                                                          << F << "\ndF =\n"
                                                                          << dF << "\ndP =\n"
                                                                          << dP << "\nFD =\n"
                                                                          << dPfd;
    }
    // Rotation invariance Ψ(QF) = Ψ(F), and P(QF) = Q P(F) (frame indifference). Round-off
    // of a determinant, a log and a polar decomposition: 1e-12 relative.
    M<D> Q = random_rotation<D>(rng);
    const double psiQ = energy_density<double, D>(model, Q * F, l);
    const M<D> PQ = first_piola<double, D>(model, Q * F, l);
    EXPECT_NEAR(psiQ, psi, 1e-12 * (std::abs(psi) + l.mu));
    EXPECT_LE((PQ - Q * P).norm(), 1e-11 * (P.norm() + l.mu));
    // Isotropy: Ψ(FQ) = Ψ(F).
    const double psiFQ = energy_density<double, D>(model, F * Q, l);
    EXPECT_NEAR(psiFQ, psi, 1e-12 * (std::abs(psi) + l.mu));
    // P Fᵀ symmetric (balance of angular momentum; the internal forces then conserve L).
    M<D> tau = P * F.transpose();
    EXPECT_LE((tau - tau.transpose()).norm(), 1e-12 * (tau.norm() + l.mu));
  }
  // Rest state: Ψ(I) = 0 and P(I) = 0 (10 ulp of μ, λ).
  const M<D> I = M<D>::Identity();
  const double psiI = energy_density<double, D>(model, I, l);
  const M<D> PI = first_piola<double, D>(model, I, l);
  EXPECT_NEAR(psiI, 0.0, 1e-12 * l.mu);
  EXPECT_LE(PI.norm(), 1e-12 * l.mu);
  // And rigid rotations are stress-free rest states too (rounding of R: 1e-11).
  const M<D> R = random_rotation<D>(rng);
  const double psiR = energy_density<double, D>(model, R, l);
  const M<D> PR = first_piola<double, D>(model, R, l);
  EXPECT_NEAR(psiR, 0.0, 1e-11 * l.mu);
  EXPECT_LE(PR.norm(), 1e-11 * l.mu);
}

TEST(Materials, NeoHookean2D) { check_model<2>(MaterialModel::neo_hookean); }
TEST(Materials, NeoHookean3D) { check_model<3>(MaterialModel::neo_hookean); }
TEST(Materials, FixedCorotated2D) { check_model<2>(MaterialModel::fixed_corotated); }
TEST(Materials, FixedCorotated3D) { check_model<3>(MaterialModel::fixed_corotated); }

template <int D>
void check_inverted() {
  SCOPED_TRACE(::testing::Message() << D << "D");
  const Lame<double> l = lame();
  std::mt19937_64 rng(31 + D);
  for (int s = 0; s < 20; ++s) {
    M<D> F = random_F<D>(rng, 0.3);
    F.col(0) *= -1;  // reflect: det F < 0
    ASSERT_LT(F.determinant(), 0.0);
    double nh = energy_density<double, D>(MaterialModel::neo_hookean, F, l);
    EXPECT_TRUE(std::isinf(nh) && nh > 0)
        << "neo-Hookean Ψ of an inverted F must be +inf, got " << nh;
    double fc = energy_density<double, D>(MaterialModel::fixed_corotated, F, l);
    EXPECT_TRUE(std::isfinite(fc)) << fc;
    EXPECT_GT(fc, 0.0);
    M<D> P = first_piola<double, D>(MaterialModel::fixed_corotated, F, l);
    EXPECT_TRUE(P.allFinite());
  }
  // Degenerate F (J = 0): neo-Hookean infinite, fixed corotated finite.
  M<D> Z = M<D>::Identity();
  Z(0, 0) = 0;
  const double nhZ = energy_density<double, D>(MaterialModel::neo_hookean, Z, l);
  const double fcZ = energy_density<double, D>(MaterialModel::fixed_corotated, Z, l);
  EXPECT_TRUE(std::isinf(nhZ));
  EXPECT_TRUE(std::isfinite(fcZ));
  // Fixed corotated: P = ∂Ψ/∂F holds for an inverted F away from the singular set too.
  M<D> F = M<D>::Identity();
  F(0, 0) = -0.7;
  F(1, 0) = 0.2;
  const double h = 1e-6;
  M<D> P = first_piola<double, D>(MaterialModel::fixed_corotated, F, l), Pfd;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) {
      M<D> Fp = F, Fm = F;
      Fp(i, j) += h;
      Fm(i, j) -= h;
      Pfd(i, j) = (energy_density<double, D>(MaterialModel::fixed_corotated, Fp, l) -
                   energy_density<double, D>(MaterialModel::fixed_corotated, Fm, l)) /
                  (2 * h);
    }
  EXPECT_LE((P - Pfd).norm(), 1e-6 * (P.norm() + l.mu));  // as above
}

TEST(Materials, Inverted2D) { check_inverted<2>(); }
TEST(Materials, Inverted3D) { check_inverted<3>(); }

// The 3D polar decomposition's Newton iteration against Eigen's JacobiSVD: R = U Vᵀ for F with
// det F > 0, from near-rigid to strongly stretched and sheared (condition numbers up to ~1e3),
// in double and float. R orthonormal with det +1 and S = RᵀF symmetric positive definite.
template <class T>
void polar_matches_svd(double tolerance) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1), logs(-3.5, 3.5);
  int newton = 0;
  for (int k = 0; k < 2000; ++k) {
    // F = Q1 diag(σ) Q2 with random rotations and singular values e^[-3.5, 3.5].
    auto rotation = [&] {
      Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
      return Mat<double, 3>(q.normalized().toRotationMatrix());
    };
    Vec<double, 3> sigma(std::exp(logs(rng)), std::exp(logs(rng)), std::exp(logs(rng)));
    if (k % 4 == 0)
      sigma = Vec<double, 3>::Constant(1) + 0.01 * Vec<double, 3>(u(rng), u(rng), u(rng));
    const Mat<double, 3> Fd = rotation() * sigma.asDiagonal() * rotation();
    const Mat<T, 3> F = Fd.cast<T>();
    Mat<T, 3> R, S;
    polar_decomposition<T, 3>(F, R, S);
    Eigen::JacobiSVD<Mat<double, 3>> svd(F.template cast<double>(),
                                         Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Mat<double, 3> Rsvd = svd.matrixU() * svd.matrixV().transpose();
    Mat<T, 3> Rn;
    newton += polar_newton_3d<T>(F, Rn);
    ASSERT_LT((R.template cast<double>() - Rsvd).norm(),
              tolerance * svd.singularValues()[0] / svd.singularValues()[2])
        << "sigma " << sigma.transpose();
    EXPECT_LT((R.transpose() * R - Mat<T, 3>::Identity()).norm(),
              T(10) * std::numeric_limits<T>::epsilon());
    EXPECT_NEAR(double(R.determinant()), 1.0, 10 * std::numeric_limits<T>::epsilon());
    EXPECT_LT((S - S.transpose()).norm(), T(4) * std::numeric_limits<T>::epsilon() * S.norm());
    EXPECT_GT(double(Eigen::SelfAdjointEigenSolver<Mat<T, 3>>(S).eigenvalues().minCoeff()), 0.0);
  }
  EXPECT_GT(newton, 1990) << "the Newton iteration should handle every F with det F > 0 here";
}

TEST(Materials, PolarDecomposition3DMatchesSvd) {
  polar_matches_svd<double>(1e-13);
  polar_matches_svd<float>(1e-5);
}

TEST(Materials, LameParameters) {
  MaterialDesc m;
  m.E = 1000;
  m.nu = 0.3;
  // μ = E / 2(1+ν), λ = Eν / (1+ν)(1−2ν): exact formulas, 1e-12 relative for the divisions.
  EXPECT_NEAR(m.mu(), 1000.0 / 2.6, 1e-12 * 400);
  EXPECT_NEAR(m.lambda(), 300.0 / (1.3 * 0.4), 1e-12 * 600);
}

}  // namespace
}  // namespace apiclab
