// The 3D fixed-corotated stress of several particles at a time (sim/mpm/simd/stress_lanes.hpp)
// against the scalar formula (first_piola_and_energy), lane by lane, with a different μ, λ and
// volume in every lane, on deformations from near-rest to singular values e^±3.5, inverted and
// near-singular ones among them: those lanes must be handed back to the scalar path.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "sim/materials.hpp"
#include "sim/mpm/simd/stress_lanes.hpp"

namespace apiclab {
namespace {

template <class T>
void lanes_match_scalar(double tolerance) {
  using Lanes = StressLanes<T, 3>;
  constexpr int L = Lanes::count;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), logs(-3.5, 3.5), unit(0.5, 2);
  auto rotation = [&] {
    Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
    return Mat<double, 3>(q.normalized().toRotationMatrix());
  };
  int lanes_done = 0, regular = 0, inverted = 0, handed_back_inverted = 0;
  double worst = 0;
  for (int batch = 0; batch < 600; ++batch) {
    Mat<T, 3> F[L], stress[L];
    T mu[L], lambda[L], volume[L], psi[L];
    bool newton_can[L];
    for (int l = 0; l < L; ++l) {
      Vec<double, 3> sigma(std::exp(logs(rng)), std::exp(logs(rng)), std::exp(logs(rng)));
      const int kind = (batch * L + l) % 7;
      regular += kind != 1 && kind != 2;
      if (kind == 0)
        sigma = Vec<double, 3>::Constant(1) + 0.01 * Vec<double, 3>(u(rng), u(rng), u(rng));
      if (kind == 1) sigma[2] = -sigma[2];  // inverted
      if (kind == 2) sigma[1] = 1e-9;       // nearly singular
      F[l] = (rotation() * sigma.asDiagonal() * rotation()).template cast<T>();
      mu[l] = T(300 * unit(rng));
      lambda[l] = T(500 * unit(rng));
      volume[l] = T(1e-3 * unit(rng));
      Mat<T, 3> R;
      newton_can[l] = polar_newton_3d<T>(F[l], R);
      inverted += F[l].determinant() <= T(0);
    }
    const unsigned scalar = Lanes::fixed_corotated(F, mu, lambda, volume, stress, psi);
    for (int l = 0; l < L; ++l) {
      const bool handed_back = scalar >> l & 1u;
      // The lanes take exactly the F that the scalar Newton iteration takes.
      ASSERT_EQ(handed_back, !newton_can[l]) << "lane " << l << " F\n" << F[l];
      if (F[l].determinant() <= T(0)) handed_back_inverted += handed_back;
      if (handed_back) continue;
      ++lanes_done;
      T psi_scalar;
      const Mat<T, 3> P = first_piola_and_energy<T, 3>(MaterialModel::fixed_corotated, F[l],
                                                       {mu[l], lambda[l]}, psi_scalar);
      const Mat<double, 3> expected = (-volume[l] * P * F[l].transpose()).template cast<double>();
      // Both sides run the same Newton iteration on the same F in a different arithmetic order;
      // R's error is then round-off times F's condition number (as PolarDecomposition3DMatchesSvd
      // bounds it), and the stress carries it through 2μ(F − R) Fᵀ, measured against the size of
      // the terms that make it up.
      Eigen::JacobiSVD<Mat<double, 3>> svd(F[l].template cast<double>());
      const double condition = svd.singularValues()[0] / svd.singularValues()[2];
      const double Fn = F[l].template cast<double>().norm(),
                   J = std::abs(svd.singularValues().prod());
      const double scale =
          volume[l] * Fn * (2 * mu[l] * (Fn + std::sqrt(3.0)) + lambda[l] * (J + 1) * Fn * Fn);
      const double error =
          (stress[l].template cast<double>() - expected).norm() / (scale * condition);
      worst = std::max(worst, error);
      ASSERT_LT(error, tolerance) << "lane " << l << " F\n" << F[l];
      const double psi_scale =
          mu[l] * (Fn + std::sqrt(3.0)) * (Fn + std::sqrt(3.0)) + lambda[l] * (J + 1) * (J + 1);
      ASSERT_LT(std::abs(double(psi[l]) - double(psi_scalar)), tolerance * condition * psi_scale);
    }
  }
  EXPECT_EQ(lanes_done, regular) << "every lane but the inverted and singular ones";
  EXPECT_GT(inverted, 0);
  EXPECT_EQ(handed_back_inverted, inverted) << "an inverted F is the scalar path's (SVD)";
  std::printf("%s: %d lanes, worst error %.2g (x round-off x condition), bound %.0g\n",
              sizeof(T) == 8 ? "double" : "float", lanes_done, worst, tolerance);
}

// 2D: R is closed-form on both sides, so the lanes differ from the scalar formula only by the
// order of the arithmetic; F includes inverted ones and F = 0 (R = I by convention).
template <class T>
void lanes_match_scalar_2d(double tolerance) {
  using Lanes = StressLanes<T, 2>;
  constexpr int L = Lanes::count;
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1, 1), unit(0.5, 2);
  double worst = 0;
  for (int batch = 0; batch < 600; ++batch) {
    Mat<T, 2> F[L], stress[L];
    T mu[L], lambda[L], volume[L], psi[L];
    for (int l = 0; l < L; ++l) {
      for (int k = 0; k < 4; ++k) F[l].data()[k] = T(2 * u(rng));
      if ((batch * L + l) % 50 == 0) F[l].setZero();
      mu[l] = T(300 * unit(rng));
      lambda[l] = T(500 * unit(rng));
      volume[l] = T(1e-3 * unit(rng));
    }
    Lanes::fixed_corotated_2d(F, mu, lambda, volume, stress, psi);
    for (int l = 0; l < L; ++l) {
      T psi_scalar;
      const Mat<T, 2> P = first_piola_and_energy<T, 2>(MaterialModel::fixed_corotated, F[l],
                                                       {mu[l], lambda[l]}, psi_scalar);
      const Mat<double, 2> expected = (-volume[l] * P * F[l].transpose()).template cast<double>();
      const double Fn = F[l].template cast<double>().norm(),
                   J = std::abs(double(F[l].determinant()));
      const double scale =
          volume[l] * Fn * (2 * mu[l] * (Fn + std::sqrt(2.0)) + lambda[l] * (J + 1) * Fn) + 1e-30;
      const double error = (stress[l].template cast<double>() - expected).norm() / scale;
      worst = std::max(worst, error);
      ASSERT_LT(error, tolerance) << "lane " << l << " F\n" << F[l];
      const double psi_scale =
          mu[l] * (Fn + std::sqrt(2.0)) * (Fn + std::sqrt(2.0)) + lambda[l] * (J + 1) * (J + 1);
      ASSERT_LT(std::abs(double(psi[l]) - double(psi_scalar)), tolerance * psi_scale);
    }
  }
  std::printf("2D %s: worst error %.2g (x round-off), bound %.0g\n",
              sizeof(T) == 8 ? "double" : "float", worst, tolerance);
}

TEST(StressLanes, FixedCorotated2DMatchesTheScalarFormulaLaneByLane) {
  lanes_match_scalar_2d<double>(1e-15);
  lanes_match_scalar_2d<float>(1e-6);
}

TEST(StressLanes, FixedCorotatedMatchesTheScalarFormulaLaneByLane) {
  lanes_match_scalar<double>(1e-15);
  lanes_match_scalar<float>(1e-6);
}

}  // namespace
}  // namespace apiclab
