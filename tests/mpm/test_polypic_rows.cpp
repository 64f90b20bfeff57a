// PolyPIC's transfers in row form (sim/mpm/schemes/polypic_modes.hpp: gather_modes_rows,
// scatter_modes_rows, what the step runs) against the plain per-mode sums (gather_modes,
// scatter_modes: one product per mode per node, the readable definition), for every number of
// kept modes in 2D and 3D, on random particles and a random grid velocity field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "sim/mpm/schemes/polypic_modes.hpp"
#include "sim/mpm/simd/lanes.hpp"
#include "sim/mpm/stencil.hpp"
#include "tests/mpm/test_helpers.hpp"

namespace apiclab {
namespace {

template <int D>
GridGeometry<double, D> small_grid(int n) {
  GridGeometry<double, D> g;
  g.dx = 0.1;
  g.inv_dx = 10;
  g.origin.setZero();
  std::size_t stride = 1;
  for (int a = 0; a < D; ++a) {
    g.lo[a] = 0;
    g.extent[a] = n;
    g.stride[a] = stride;
    stride *= std::size_t(n);
  }
  return g;
}

template <int D, int F>
void rows_match_plain(int extra, std::mt19937_64& rng, double& worst) {
  using St = Stencil<double, D, QuadraticKernel>;
  using L = Lanes<double, 1 + 2 * D>;
  constexpr int n = 12;
  const auto g = small_grid<D>(n);
  std::size_t nodes = 1;
  for (int a = 0; a < D; ++a) nodes *= std::size_t(n);
  std::vector<Vec<double, D>> velocity(nodes);
  for (auto& v : velocity) v = test::random_vector<double, D>(rng, -1.0, 1.0);
  constexpr int particles = 40;
  using Modes = std::vector<std::vector<Vec<double, D>>>;
  Modes plain(static_cast<std::size_t>(extra), std::vector<Vec<double, D>>(particles));
  Modes rows = plain;
  std::vector<Vec<double, D>> acc_plain(nodes, Vec<double, D>::Zero()), acc_rows = acc_plain;
  std::uniform_real_distribution<double> pos(0.3, 0.8), mass(0.5, 2);
  auto node = [&](std::size_t i) {  // ṽ in lanes 0..D−1 as G2P's packed nodes
    if constexpr (D == 2)
      return L::of(velocity[i][0], velocity[i][1]);
    else
      return L::of(velocity[i][0], velocity[i][1], velocity[i][2]);
  };
  for (std::size_t q = 0; q < particles; ++q) {
    Vec<double, D> x;
    for (int a = 0; a < D; ++a) x[a] = pos(rng);
    St st;
    st.compute(x, g);
    polypic::gather_modes<double, D>(st, g.inv_dx, velocity, extra, plain, q);
    polypic::gather_modes_rows<double, D, F, L>(st, g.inv_dx, node, extra, rows, q);
    const double m = mass(rng);
    polypic::scatter_modes<double, D>(
        st, g.inv_dx, plain, q,
        [&](std::size_t i, double w, const Vec<double, D>& v) { acc_plain[i] += (w * m) * v; });
    polypic::scatter_modes_rows<double, D, F, L>(st, g.inv_dx, plain, q, m,
                                                 [&](std::size_t i, const L& v) {
                                                   for (int a = 0; a < D; ++a)
                                                     acc_rows[i][a] += v[1 + a];
                                                 });
  }
  double scale = 0, d = 0;
  for (int j = 0; j < extra; ++j)
    for (std::size_t q = 0; q < particles; ++q) {
      scale = std::max(scale, plain[std::size_t(j)][q].norm());
      d = std::max(d, (plain[std::size_t(j)][q] - rows[std::size_t(j)][q]).norm());
    }
  double acc_scale = 0, acc_d = 0;
  for (std::size_t i = 0; i < nodes; ++i) {
    acc_scale = std::max(acc_scale, acc_plain[i].norm());
    acc_d = std::max(acc_d, (acc_plain[i] - acc_rows[i]).norm());
  }
  ASSERT_GT(scale, 0.1);
  ASSERT_GT(acc_scale, 0.1);
  EXPECT_LT(d, 1e-13 * scale) << D << "D, " << extra << " extra modes, F = " << F;
  EXPECT_LT(acc_d, 1e-13 * acc_scale) << D << "D, " << extra << " extra modes, F = " << F;
  worst = std::max({worst, d / scale, acc_d / acc_scale});
}

template <int D>
void all_counts() {
  std::mt19937_64 rng(77 + D);
  double worst = 0;
  for (int kept = D + 2; kept <= polypic::full_modes(D); ++kept) {
    const int extra = polypic::extra_modes(kept, D);
    if (!polypic::keeps_g_modes(kept, D)) rows_match_plain<D, 2>(extra, rng, worst);
    rows_match_plain<D, 3>(extra, rng, worst);  // the three functions also serve fewer modes
  }
  std::printf("[ polypic rows ] %dD: row form vs per-mode sums, worst relative %.2g\n", D, worst);
}

TEST(PolypicRows, MatchThePerModeSums2D) { all_counts<2>(); }
TEST(PolypicRows, MatchThePerModeSums3D) { all_counts<3>(); }

// The CFL rule's PolyPIC term (choose_dt, sim/time_step_rules.hpp): max over the stencil's nodes
// of |Σ_j c_j s_j|, unweighted, in row form (max_modes_speed_rows) against the per-mode scatter
// it replaced, for every kept mode count, on random particles and one whose axis weights
// vanish at a node (|x_p − x_i| = 1.5 Δx, where the G modes' norm is 0 but their values are not).
template <int D, int F>
void max_speed_matches_plain(int extra, std::mt19937_64& rng, double& worst) {
  using St = Stencil<double, D, QuadraticKernel>;
  const auto g = small_grid<D>(12);
  constexpr std::size_t particles = 40;
  std::vector<std::vector<Vec<double, D>>> modes(static_cast<std::size_t>(extra),
                                                 std::vector<Vec<double, D>>(particles));
  for (auto& m : modes)
    for (auto& c : m) c = test::random_vector<double, D>(rng, -1.0, 1.0);
  std::uniform_real_distribution<double> pos(0.3, 0.8);
  for (std::size_t q = 0; q < particles; ++q) {
    Vec<double, D> x;
    for (int a = 0; a < D; ++a) x[a] = q == 0 ? 0.45 : pos(rng);  // q = 0: 1.5 Δx from a node
    St st;
    st.compute(x, g);
    double plain = 0;
    polypic::scatter_modes<double, D>(
        st, g.inv_dx, modes, q,
        [&](std::size_t, double, const Vec<double, D>& u) { plain = std::max(plain, u.norm()); });
    const double rows = polypic::max_modes_speed_rows<double, D, F>(st, g.inv_dx, modes, q);
    ASSERT_GT(plain, 0.01);
    EXPECT_LT(std::abs(rows - plain), 1e-14 * plain)
        << D << "D, " << extra << " extra modes, F = " << F << ", particle " << q;
    worst = std::max(worst, std::abs(rows - plain) / plain);
  }
}

template <int D>
void max_speed_all_counts() {
  std::mt19937_64 rng(91 + D);
  double worst = 0;
  for (int kept = D + 2; kept <= polypic::full_modes(D); ++kept) {
    const int extra = polypic::extra_modes(kept, D);
    if (polypic::keeps_g_modes(kept, D))
      max_speed_matches_plain<D, 3>(extra, rng, worst);
    else
      max_speed_matches_plain<D, 2>(extra, rng, worst);  // as choose_dt picks F
  }
  std::printf("[ polypic rows ] %dD: CFL mode speed, row form vs per-mode, worst relative %.2g\n",
              D, worst);
}

TEST(PolypicRows, CflModeSpeedMatchesThePerModeScatter2D) { max_speed_all_counts<2>(); }
TEST(PolypicRows, CflModeSpeedMatchesThePerModeScatter3D) { max_speed_all_counts<3>(); }

}  // namespace
}  // namespace apiclab
