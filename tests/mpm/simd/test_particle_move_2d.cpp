// 2D G2P's end across a batch of particles (sim/mpm/simd/particle_move_2d.hpp): the register path
// must give the same bits as the per-particle one (F by eq 40, x by eq 39 clamped to the walls),
// raise the largest move the same, and report a non-finite particle in any lane.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "sim/mpm/simd/particle_move_2d.hpp"

namespace apiclab {
namespace {

template <class T, int L>
void batch_equals_one_by_one(bool poison) {
  SCOPED_TRACE(std::string(sizeof(T) == 8 ? "double" : "float") + (poison ? ", a NaN" : ""));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  ParticleMoveBatch2d<T, L> tail;
  std::vector<Mat<T, 2>> F(L), F1;
  std::vector<Vec<T, 2>> x(L), v(L), x1;
  const Vec<T, 2> lo(T(0.1), T(0.2)), hi(T(0.9), T(0.8));
  for (int l = 0; l < L; ++l) {
    Mat<T, 2> g;
    g << T(0.01 * u(rng)), T(0.01 * u(rng)), T(0.01 * u(rng)), T(0.01 * u(rng));
    // Every third particle moves through a wall, so both sides of the clamp are taken.
    const Vec<T, 2> move(T(l % 3 == 0 ? (l % 2 ? -0.9 : 0.9) : 0.01 * u(rng)), T(0.01 * u(rng)));
    tail.set(l, g, move);
    F[l] << T(1 + 0.1 * u(rng)), T(0.1 * u(rng)), T(0.1 * u(rng)), T(1 + 0.1 * u(rng));
    x[l] = Vec<T, 2>(T(0.5 + 0.4 * u(rng)), T(0.5 + 0.3 * u(rng)));
    v[l] = Vec<T, 2>(T(u(rng)), T(u(rng)));
  }
  if (poison) v[L - 2][1] = std::numeric_limits<T>::quiet_NaN();
  F1 = F;
  x1 = x;
  T largest = 0, largest1 = 0;
  const bool finite = tail.apply(L, F.data(), x.data(), v.data(), lo, hi, largest);
  bool finite1 = true;
  for (int l = 0; l < L; ++l)
    finite1 = tail.apply_one(l, F1[l], x1[l], v[l], lo, hi, largest1) && finite1;
  EXPECT_EQ(finite, !poison);
  EXPECT_EQ(finite1, !poison);
  EXPECT_EQ(largest, largest1);
  EXPECT_GT(largest, T(0.1));  // a wall-crossing move was seen
  int clamped = 0;
  for (int l = 0; l < L; ++l) {
    for (int e = 0; e < 4; ++e) EXPECT_EQ(F[l](e), F1[l](e)) << "particle " << l << " F " << e;
    for (int a = 0; a < 2; ++a) {
      EXPECT_EQ(x[l][a], x1[l][a]) << "particle " << l << " x " << a;
      EXPECT_GE(x[l][a], lo[a]);
      EXPECT_LE(x[l][a], hi[a]);
      clamped += x[l][a] == lo[a] || x[l][a] == hi[a];
    }
  }
  EXPECT_GT(clamped, 0);
}

TEST(ParticleMoveBatch, BatchGivesTheBitsOfOneByOne) {
  batch_equals_one_by_one<float, 16>(false);
  batch_equals_one_by_one<float, 16>(true);
  batch_equals_one_by_one<double, 4>(false);
  batch_equals_one_by_one<double, 4>(true);
}

TEST(ParticleMoveBatch, FollowsEquation40) {
  ParticleMoveBatch2d<double, 4> tail;
  std::vector<Mat<double, 2>> F(4, Mat<double, 2>::Identity()), F0;
  std::vector<Vec<double, 2>> x(4, Vec<double, 2>(0.5, 0.5)), v(4, Vec<double, 2>::Zero());
  Mat<double, 2> g;
  g << 0.01, -0.02, 0.03, 0.005;
  for (int l = 0; l < 4; ++l) {
    F[l](0, 1) = 0.1 * l;
    tail.set(l, g, Vec<double, 2>(0.01 * l, -0.01));
  }
  F0 = F;
  const Vec<double, 2> lo(0, 0), hi(1, 1);
  double largest = 0;
  EXPECT_TRUE(tail.apply(4, F.data(), x.data(), v.data(), lo, hi, largest));
  EXPECT_DOUBLE_EQ(largest, 0.03);
  for (int l = 0; l < 4; ++l) {
    const Mat<double, 2> expected = (Mat<double, 2>::Identity() + g) * F0[l];
    EXPECT_LT((F[l] - expected).cwiseAbs().maxCoeff(), 1e-15) << l;
    EXPECT_DOUBLE_EQ(x[l][0], 0.5 + 0.01 * l);
    EXPECT_DOUBLE_EQ(x[l][1], 0.49);
  }
}

// set_scaled (G2P's call: ∇u, ū and Δt read whole) stores Δt ∇u and Δt ū, the bits of set's
// entry-by-entry products, in every lane.
template <class T, int L>
void scaled_equals_set() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  ParticleMoveBatch2d<T, L> a, b;
  const T dt = T(0.37 * (1 + u(rng)));
  for (int l = 0; l < L; ++l) {
    Mat<T, 2> g;
    g << T(u(rng)), T(u(rng)), T(u(rng)), T(u(rng));
    const Vec<T, 2> ubar(T(u(rng)), T(u(rng)));
    a.set(l, dt * g, dt * ubar);
    b.set_scaled(l, g, ubar, dt);
  }
  for (int l = 0; l < L; ++l) {
    for (int e = 0; e < 4; ++e) EXPECT_EQ(a.dt_gradu[e][l], b.dt_gradu[e][l]) << l << " " << e;
    for (int c = 0; c < 2; ++c) EXPECT_EQ(a.move[c][l], b.move[c][l]) << l << " " << c;
    EXPECT_NE(b.move[1][l], T(0));
  }
}

TEST(ParticleMoveBatch, SetScaledGivesTheBitsOfSet) {
  scaled_equals_set<float, 16>();
  scaled_equals_set<double, 4>();
}

}  // namespace
}  // namespace apiclab
