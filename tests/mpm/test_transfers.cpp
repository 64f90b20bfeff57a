// Transfers in isolation (Jiang et al. 2017, Secs 5.1-5.5): P2G conserves mass, linear and
// angular momentum for every scheme; G2P conserves them for APIC and RPIC; APIC reproduces an
// affine velocity field exactly (round trip with Δt = 0); one particle keeps v_p and C_p.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "tests/mpm/test_helpers.hpp"

namespace apiclab {
namespace {

using test::make_scene;
using test::randomize_particles;

const char* kSchemes[] = {"pic", "flip", "apic", "rpic"};
const char* kKernels[] = {"linear", "quadratic", "cubic"};

// Scales for relative tolerances: Σ m|v| for momentum and Σ m(|x||v| + |C|Δx²) for angular
// momentum, so that a cancelling total (random velocities sum to ~0) is still judged fairly.
template <int D>
void scales(const MpmSimulation<double, D>& sim, double& sp, double& sL) {
  const auto& p = MpmProbe(sim).particles();
  sp = sL = 0;
  const double dx = MpmProbe(sim).grid().dx;
  for (std::size_t q = 0; q < p.size(); ++q) {
    sp += p.mass[q] * p.v[q].norm();
    sL += p.mass[q] * (p.x[q].norm() * p.v[q].norm() + p.C[q].norm() * dx * dx);
  }
}

// Largest relative errors seen, printed once per test for the record.
struct Worst {
  double p = 0, L = 0;
  void add(double ep, double eL) {
    p = std::max(p, ep);
    L = std::max(L, eL);
  }
  void print(const char* what) const {
    std::printf("[ %s ] max relative |dp| = %.3g, |dL| = %.3g\n", what, p, L);
  }
};

template <int D>
void p2g_conserves(const std::string& scheme, const std::string& kernel, Worst& worst) {
  SCOPED_TRACE(::testing::Message() << scheme << " " << kernel << " " << D << "D");
  MpmSimulation<double, D> sim(make_scene(D, scheme, kernel));
  randomize_particles<D>(sim, D == 2 ? 600 : 300, 42 + D, 0.3, 0.7, scheme == "rpic");
  const DiagnosticsRow before = sim.measure();
  double msum = 0;
  for (double m : MpmProbe(sim).particles().mass) msum += m;
  double sp, sL;
  scales<D>(sim, sp, sL);

  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  double mgrid = 0;
  for (double m : MpmProbe(sim).grid().mass) mgrid += m;
  MpmProbe(sim).grid_velocity_update(0.0);  // v_i = (mv)_i / m_i (eq 26); Δt = 0 leaves ṽ = v
  const GridMoments moments = MpmProbe(sim).grid_moments(false);
  const Eigen::Vector3d p = moments.momentum, L = moments.angular_momentum;

  // ≤ 600 particles × 64 nodes of O(1) terms in double: accumulated round-off ~1e-14
  // relative; 1e-12 leaves room and is still ~10 orders below any transfer error.
  worst.add((p - test::to3(before.p)).norm() / sp, (L - test::to3(before.L)).norm() / sL);
  EXPECT_NEAR(mgrid, msum, 1e-12 * msum) << "mass (eq 24)";
  EXPECT_LE((p - test::to3(before.p)).norm(), 1e-12 * sp) << "grid p " << p.transpose();
  EXPECT_LE((L - test::to3(before.L)).norm(), 1e-12 * sL)
      << "grid L " << L.transpose() << " particle L " << test::to3(before.L).transpose();
}

TEST(Transfers, P2GConservesMassMomentumAngularMomentum2D) {
  Worst w;
  for (const char* s : kSchemes)
    for (const char* k : kKernels) p2g_conserves<2>(s, k, w);
  w.print("P2G 2D, all schemes and kernels");
}
TEST(Transfers, P2GConservesMassMomentumAngularMomentum3D) {
  Worst w;
  for (const char* s : kSchemes)
    for (const char* k : kKernels) p2g_conserves<3>(s, k, w);
  w.print("P2G 3D, all schemes and kernels");
}

// G2P (eqs 37-39, λ = 0): set a random ṽ on every node with mass, transfer, and compare the
// grid's Σ m_i ṽ_i and Σ x̃_i × m_i ṽ_i (x̃_i = x_i + Δt ṽ_i) with the particle state.
template <int D>
void g2p_conserves(const std::string& scheme, const std::string& kernel, double dt, Worst& worst) {
  SCOPED_TRACE(::testing::Message() << scheme << " " << kernel << " " << D << "D dt " << dt);
  MpmSimulation<double, D> sim(make_scene(D, scheme, kernel));
  randomize_particles<D>(sim, D == 2 ? 600 : 300, 7 + D, 0.3, 0.7, scheme == "rpic");
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  MpmProbe(sim).grid_velocity_update(0.0);
  auto& g = MpmProbe(sim).grid();
  std::mt19937_64 rng(99);
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (g.mass[i] <= 0) continue;
    Vec<double, D> v = test::random_vector<double, D>(rng, -1.0, 1.0);
    g.velocity[i] = v;  // v_i^n = ṽ (only FLIP would read it with λ = 0)
    g.velocity_new[i] = v;
  }
  const test::GridMoments m = test::grid_moments<D>(g, dt);
  MpmProbe(sim).grid_to_particles(dt);
  const DiagnosticsRow after = sim.measure();
  worst.add((test::to3(after.p) - m.p).norm() / m.p_scale,
            scheme == "pic" ? 0.0 : (test::to3(after.L) - m.L).norm() / m.L_scale);
  // Same budget as P2G: sums of ~1e4 O(1) products, 1e-12 relative to the absolute scale.
  EXPECT_LE((test::to3(after.p) - m.p).norm(), 1e-12 * m.p_scale)
      << "particles p " << test::to3(after.p).transpose() << " grid p " << m.p.transpose();
  if (scheme != "pic") {
    EXPECT_LE((test::to3(after.L) - m.L).norm(), 1e-12 * m.L_scale)
        << "particles L " << test::to3(after.L).transpose() << " grid L " << m.L.transpose();
  }
}

TEST(Transfers, G2PConservesApicRpic2D) {
  Worst w;
  for (const char* s : {"apic", "rpic"}) {
    for (const char* k : {"quadratic", "cubic"})
      for (double dt : {0.0, 0.01}) g2p_conserves<2>(s, k, dt, w);
    // Multilinear uses the lagged C of Sec 5.9: B^{n+1} = C^{n+1} D_p^{n+1} with D_p^{n+1} ≠
    // D_p^n, so exact conservation across G2P holds only when the particle does not move.
    g2p_conserves<2>(s, "linear", 0.0, w);
  }
  g2p_conserves<2>("pic", "quadratic", 0.01, w);  // PIC: linear momentum only (eq 2)
  w.print("G2P 2D, APIC and RPIC");
}
TEST(Transfers, G2PConservesApicRpic3D) {
  Worst w;
  for (const char* s : {"apic", "rpic"}) {
    for (const char* k : {"quadratic", "cubic"})
      for (double dt : {0.0, 0.01}) g2p_conserves<3>(s, k, dt, w);
    g2p_conserves<3>(s, "linear", 0.0, w);
  }
  g2p_conserves<3>("pic", "quadratic", 0.01, w);
  w.print("G2P 3D, APIC and RPIC");
}

// Sec 5.5: v_p = v + C x_p, C_p = C; P2G then G2P with Δt = 0 returns the same v_p and C_p,
// and the grid velocity in between is v + C x_i on every node with mass (eq 96).
template <int D>
void affine_round_trip(const std::string& scheme, const std::string& kernel) {
  SCOPED_TRACE(::testing::Message() << scheme << " " << kernel << " " << D << "D");
  MpmSimulation<double, D> sim(make_scene(D, scheme, kernel));
  const std::size_t n = D == 2 ? 300 : 150;
  randomize_particles<D>(sim, n, 5 + D);
  std::mt19937_64 rng(123);
  const Vec<double, D> v = test::random_vector<double, D>(rng, -1.0, 1.0);
  Mat<double, D> C = test::random_matrix<double, D>(rng, 2.0);
  if (scheme == "rpic") C = (0.5 * (C - C.transpose())).eval();  // RPIC reproduces rigid fields
  auto& p = MpmProbe(sim).particles();
  for (std::size_t q = 0; q < n; ++q) {
    p.v[q] = v + C * p.x[q];
    p.C[q] = C;
  }
  const double scale = v.norm() + C.norm() * 1.0;  // |x| ≤ √D, the field is O(|v| + |C|)
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  MpmProbe(sim).grid_velocity_update(0.0);
  const auto& g = MpmProbe(sim).grid();
  double grid_err = 0;
  for (std::size_t i = 0; i < g.size(); ++i)
    if (g.mass[i] > 0)
      grid_err = std::max(grid_err, (g.velocity[i] - (v + C * g.node_position(i))).norm());
  MpmProbe(sim).grid_to_particles(0.0);
  double verr = 0, cerr = 0;
  for (std::size_t q = 0; q < n; ++q) {
    verr = std::max(verr, (p.v[q] - (v + C * p.x[q])).norm());
    cerr = std::max(cerr, (p.C[q] - C).norm());
  }
  // Exact in exact arithmetic (eqs 91-107); 1e-12 relative leaves ~100× room over the
  // measured round-off (≤ 4e-16 for v, ≤ 1.3e-14 for C, whose B D⁻¹ divides by kΔx²).
  EXPECT_LE(grid_err, 1e-12 * scale) << "grid velocity is not v + C x_i";
  EXPECT_LE(verr, 1e-12 * scale);
  EXPECT_LE(cerr, 1e-12 * C.norm());
  std::printf(
      "[ affine round trip %s %-9s %dD ] max |dv|/scale = %.3g, max |dC| = %.3g (|C| = %.3g)\n",
      scheme.c_str(), kernel.c_str(), D, verr / scale, cerr, C.norm());
}

TEST(Transfers, AffineRoundTripExact) {
  for (const char* k : {"quadratic", "cubic"}) {
    affine_round_trip<2>("apic", k);
    affine_round_trip<3>("apic", k);
    affine_round_trip<2>("rpic", k);
    affine_round_trip<3>("rpic", k);
  }
}

// PIC (no C) cannot carry an affine field through the round trip (random particles: the
// grid sees v_p at the particle centroid, not at x_i), which shows the test above is not vacuous.
TEST(Transfers, PicLosesAffineField) {
  MpmSimulation<double, 2> sim(make_scene(2, "pic", "quadratic"));
  randomize_particles<2>(sim, 300, 11, 0.3, 0.7, false, true);
  Mat<double, 2> C;
  C << 0.0, -1.0, 1.0, 0.0;  // rigid rotation
  auto& p = MpmProbe(sim).particles();
  for (std::size_t q = 0; q < p.size(); ++q) p.v[q] = C * p.x[q];
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  MpmProbe(sim).grid_velocity_update(0.0);
  MpmProbe(sim).grid_to_particles(0.0);
  double err = 0;
  for (std::size_t q = 0; q < p.size(); ++q) err = std::max(err, (p.v[q] - C * p.x[q]).norm());
  EXPECT_GT(err, 1e-3);  // random particles: the smoothing error is a sizeable fraction of Δx|C|
}

// Sec 5.4: one force-free particle keeps v_p and C_p (and moves with v_p) for 1000 steps of
// the full explicit step (no gravity in make_scene).
template <int D>
void one_particle(const std::string& kernel) {
  SCOPED_TRACE(::testing::Message() << kernel << " " << D << "D");
  MpmSimulation<double, D> sim(make_scene(D, "apic", kernel));
  randomize_particles<D>(sim, 1, 77 + D, 0.4, 0.45);
  auto& p = MpmProbe(sim).particles();
  p.v[0] *= 0.1;     // moves ≤ 0.17 in 1000 steps of 1e-3: stays clear of the walls
  p.volume0[0] = 0;  // no elastic energy, so no force as F follows C (eq 34 scales by V_p)
  const Vec<double, D> v0 = p.v[0], x0 = p.x[0];
  const Mat<double, D> C0 = p.C[0];
  const double dt = 1e-3;
  double verr = 0, cerr = 0;
  for (int s = 0; s < 1000; ++s) {
    sim.step_fixed(dt);  // the solver's own phase order
    verr = std::max(verr, (p.v[0] - v0).norm());
    cerr = std::max(cerr, (p.C[0] - C0).norm());
  }
  // Each step rounds B = Σ w ṽ rᵀ (|ṽ| ≤ |v| + |C|·2Δx) and divides by k Δx²: ~1e-14 of
  // |v|/Δx + |C| per step; 1000 steps of drift stay below 1e-10 of that scale.
  const double scale = v0.norm() / MpmProbe(sim).grid().dx + C0.norm();
  EXPECT_LE(verr, 1e-10 * scale);
  EXPECT_LE(cerr, 1e-10 * scale);
  EXPECT_LE((p.x[0] - (x0 + 1000 * dt * v0)).norm(), 1e-12) << "x_p^{n+1} = x_p^n + Δt v_p (eq 80)";
  ::testing::Test::RecordProperty(kernel + std::to_string(D) + "d_max_dv", std::to_string(verr));
  ::testing::Test::RecordProperty(kernel + std::to_string(D) + "d_max_dC", std::to_string(cerr));
  std::printf("[ one-particle %dD %-9s ] max |dv| = %.3g, max |dC| = %.3g over 1000 steps\n", D,
              kernel.c_str(), verr, cerr);
}

TEST(Transfers, OneParticleStable) {
  one_particle<2>("quadratic");
  one_particle<2>("cubic");
  one_particle<3>("quadratic");
  one_particle<3>("cubic");
}

}  // namespace
}  // namespace apiclab
