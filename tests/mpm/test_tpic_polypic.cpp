// TPIC (Nakamura et al. 2023) and PolyPIC (Fu et al. 2017), against the claims of their papers
// and of the APIC paper's tests (Jiang et al. 2017, Secs 5.1-5.5): conservation in P2G and G2P
// (exact where claimed, the measured loss where not), exact reproduction of affine fields and
// of PolyPIC's kept modes, PolyPIC's reductions to APIC and PIC, one-particle stability.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "sim/mpm/schemes/polypic.hpp"
#include "tests/mpm/test_helpers.hpp"

namespace apiclab {
namespace {

using test::randomize_particles;

SceneDesc scene(int dim, const std::string& scheme, const std::string& kernel, int modes = 0) {
  SceneDesc s = test::make_scene(dim, scheme, kernel);
  s.solver.polypic_modes = modes;
  return s;
}

// Random velocities in PolyPIC's higher modes (the size of v), and C with only the kept
// linear modes.
template <int D>
void randomize_modes(MpmSimulation<double, D>& sim, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto& p = MpmProbe(sim).particles();
  for (auto& mode : p.modes)
    for (auto& c : mode) c = test::random_vector<double, D>(rng, -1.0, 1.0);
  const int kept = polypic::kept_modes(sim.scene().solver.polypic_modes, D);
  if (sim.scene().solver.scheme == Scheme::polypic)
    for (auto& C : p.C) polypic::keep_linear_modes<double, D>(C, kept);
}

struct Change {
  double p = 0, L = 0;  // relative to Σ m|v| and Σ m(|x||v| + |C|Δx² + Σ|c_j|Δx)
};

template <int D>
double angular_scale(const MpmSimulation<double, D>& sim) {
  const auto& p = MpmProbe(sim).particles();
  const double dx = MpmProbe(sim).grid().dx;
  double s = 0;
  for (std::size_t q = 0; q < p.size(); ++q) {
    double modes = 0;
    for (const auto& m : p.modes) modes += m[q].norm();
    s += p.mass[q] * (p.x[q].norm() * p.v[q].norm() + p.C[q].norm() * dx * dx + modes * dx);
  }
  return s;
}

// P2G: particle p and L (measure(), with the affine and mode terms) against the grid's.
template <int D>
Change p2g_change(const std::string& scheme, const std::string& kernel, int modes) {
  MpmSimulation<double, D> sim(scene(D, scheme, kernel, modes));
  randomize_particles<D>(sim, D == 2 ? 600 : 300, 42 + D);
  randomize_modes<D>(sim, 3);
  const DiagnosticsRow before = sim.measure();
  double sp = 0;
  for (std::size_t q = 0; q < sim.particle_count(); ++q)
    sp += MpmProbe(sim).particles().mass[q] * MpmProbe(sim).particles().v[q].norm();
  const double sL = angular_scale<D>(sim);
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  MpmProbe(sim).grid_velocity_update(0.0);
  const GridMoments moments = MpmProbe(sim).grid_moments(false);
  const Eigen::Vector3d p = moments.momentum, L = moments.angular_momentum;
  return {(p - test::to3(before.p)).norm() / sp, (L - test::to3(before.L)).norm() / sL};
}

// G2P at Δt = 0 from a random grid velocity: the grid's p and L against the particles'.
template <int D>
Change g2p_change(const std::string& scheme, const std::string& kernel, int modes) {
  MpmSimulation<double, D> sim(scene(D, scheme, kernel, modes));
  randomize_particles<D>(sim, D == 2 ? 600 : 300, 7 + D);
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  MpmProbe(sim).grid_velocity_update(0.0);
  auto& g = MpmProbe(sim).grid();
  std::mt19937_64 rng(99);
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (g.mass[i] <= 0) continue;
    g.velocity[i] = g.velocity_new[i] = test::random_vector<double, D>(rng, -1.0, 1.0);
  }
  const test::GridMoments m = test::grid_moments<D>(g, 0.0);
  MpmProbe(sim).grid_to_particles(0.0);
  const DiagnosticsRow after = sim.measure();
  return {(test::to3(after.p) - m.p).norm() / m.p_scale,
          (test::to3(after.L) - m.L).norm() / m.L_scale};
}

// Sums of ~1e4 O(1) products in double: round-off ~1e-15 relative; 1e-12 leaves room and is
// orders below any transfer error (TPIC's G2P loss below is ≥ 2e-5).
constexpr double kRoundOff = 1e-12;

TEST(TpicPolypic, P2GConservesMomentumAndAngularMomentum) {
  double worst_p = 0, worst_L = 0;
  auto check = [&](Change c, const char* what) {
    SCOPED_TRACE(what);
    worst_p = std::max(worst_p, c.p), worst_L = std::max(worst_L, c.L);
    EXPECT_LE(c.p, kRoundOff);
    EXPECT_LE(c.L, kRoundOff);
  };
  for (const char* k : {"linear", "quadratic", "cubic"}) {
    check(p2g_change<2>("tpic", k, 0), k);
    check(p2g_change<3>("tpic", k, 0), k);
  }
  for (int m : {1, 3, 4, 6, 9}) check(p2g_change<2>("polypic", "quadratic", m), "polypic 2D");
  for (int m : {1, 4, 8, 11, 27}) check(p2g_change<3>("polypic", "quadratic", m), "polypic 3D");
  std::printf("[ P2G tpic, polypic ] max relative |dp| = %.3g, |dL| = %.3g\n", worst_p, worst_L);
}

// PolyPIC's G2P conserves both (Fu et al. 2017): the constant mode is PIC's, the linear modes
// APIC's B D⁻¹, and the higher modes carry no momentum or angular momentum.
TEST(TpicPolypic, PolypicG2PConservesMomentumAndAngularMomentum) {
  double worst_p = 0, worst_L = 0;
  for (int m : {3, 6, 9}) {
    const Change c = g2p_change<2>("polypic", "quadratic", m);
    worst_p = std::max(worst_p, c.p), worst_L = std::max(worst_L, c.L);
    EXPECT_LE(c.p, kRoundOff) << m << " modes";
    EXPECT_LE(c.L, kRoundOff) << m << " modes";
  }
  for (int m : {4, 10, 27}) {
    const Change c = g2p_change<3>("polypic", "quadratic", m);
    worst_p = std::max(worst_p, c.p), worst_L = std::max(worst_L, c.L);
    EXPECT_LE(c.p, kRoundOff) << m << " modes";
    EXPECT_LE(c.L, kRoundOff) << m << " modes";
  }
  std::printf("[ G2P polypic ] max relative |dp| = %.3g, |dL| = %.3g\n", worst_p, worst_L);
}

// TPIC's G2P keeps linear momentum (v_p is PIC's). Angular momentum: with the multilinear kernel
// TPIC's C = Σ ṽ ∇wᵀ is APIC's lagged C (Sec 5.9), exact at Δt = 0; with quadratic and cubic
// B-splines it is not APIC's B D⁻¹, since ∇w_ip ≠ D⁻¹ w_ip (x_i − x_p), and L is lost. Measured
// relative loss of one G2P from a random grid velocity: 2.8e-5 … 1.8e-4; the bound 1e-6 shows
// the loss is real (an APIC-like TPIC would give ~1e-16).
TEST(TpicPolypic, TpicG2PLosesAngularMomentumWithBSplines) {
  for (const char* k : {"linear", "quadratic", "cubic"}) {
    const Change c2 = g2p_change<2>("tpic", k, 0), c3 = g2p_change<3>("tpic", k, 0);
    std::printf("[ G2P tpic %-9s ] relative |dp| 2D %.3g 3D %.3g, |dL| 2D %.3g 3D %.3g\n", k, c2.p,
                c3.p, c2.L, c3.L);
    EXPECT_LE(c2.p, kRoundOff) << k;
    EXPECT_LE(c3.p, kRoundOff) << k;
    if (std::string(k) == "linear") {
      EXPECT_LE(c2.L, kRoundOff);
      EXPECT_LE(c3.L, kRoundOff);
    } else {
      EXPECT_GT(c2.L, 1e-6) << k;
      EXPECT_GT(c3.L, 1e-6) << k;
    }
  }
}

// An affine grid field v + A x round-trips exactly (G2P then P2G at Δt = 0): v_p = v + A x_p,
// C_p = A (TPIC: Σ x_i ∇w_ipᵀ = I for B-splines), PolyPIC's higher modes 0, and the grid
// velocity after P2G again v + A x_i on every node with mass.
template <int D>
void affine_round_trip(const std::string& scheme, const std::string& kernel) {
  SCOPED_TRACE(::testing::Message() << scheme << " " << kernel << " " << D << "D");
  MpmSimulation<double, D> sim(scene(D, scheme, kernel));
  randomize_particles<D>(sim, D == 2 ? 300 : 150, 5 + D);
  std::mt19937_64 rng(123);
  const Vec<double, D> v = test::random_vector<double, D>(rng, -1.0, 1.0);
  const Mat<double, D> A = test::random_matrix<double, D>(rng, 2.0);
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);  // only to mark the nodes the particles reach
  auto& g = MpmProbe(sim).grid();
  for (std::size_t i = 0; i < g.size(); ++i)
    g.velocity[i] = g.velocity_new[i] = v + A * g.node_position(i);
  MpmProbe(sim).grid_to_particles(0.0);
  const auto& p = MpmProbe(sim).particles();
  const double scale = v.norm() + A.norm();
  double verr = 0, cerr = 0, merr = 0;
  for (std::size_t q = 0; q < p.size(); ++q) {
    verr = std::max(verr, (p.v[q] - (v + A * p.x[q])).norm());
    cerr = std::max(cerr, (p.C[q] - A).norm());
    for (const auto& m : p.modes) merr = std::max(merr, m[q].norm());
  }
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  MpmProbe(sim).grid_velocity_update(0.0);
  double grid_err = 0;
  for (std::size_t i = 0; i < g.size(); ++i)
    if (g.mass[i] > 0)
      grid_err = std::max(grid_err, (g.velocity[i] - (v + A * g.node_position(i))).norm());
  // Exact in exact arithmetic; measured round-off ≤ 1e-14 relative (C divides by Δx).
  EXPECT_LE(verr, 1e-12 * scale);
  EXPECT_LE(cerr, 1e-12 * scale);
  EXPECT_LE(merr, 1e-12 * scale);
  EXPECT_LE(grid_err, 1e-12 * scale);
  std::printf("[ affine round trip %-7s %-9s %dD ] |dv| %.2g, |dC| %.2g, |modes| %.2g, grid %.2g\n",
              scheme.c_str(), kernel.c_str(), D, verr / scale, cerr / scale, merr / scale,
              grid_err / scale);
}

TEST(TpicPolypic, AffineFieldsRoundTripExactly) {
  for (const char* k : {"linear", "quadratic", "cubic"}) {
    affine_round_trip<2>("tpic", k);
    affine_round_trip<3>("tpic", k);
  }
  affine_round_trip<2>("polypic", "quadratic");
  affine_round_trip<3>("polypic", "quadratic");
}

// One particle with random coefficients in its kept modes: P2G gives the grid v_p(x_i) on the
// stencil, and G2P projects it back onto the same modes (orthogonal under the weights), so every
// kept coefficient returns exactly, for every mode count.
template <int D>
double kept_modes_round_trip(int modes) {
  MpmSimulation<double, D> sim(scene(D, "polypic", "quadratic", modes));
  randomize_particles<D>(sim, 1, 31 + std::uint64_t(modes), 0.4, 0.6);
  randomize_modes<D>(sim, 17);
  auto& p = MpmProbe(sim).particles();
  const Vec<double, D> v0 = p.v[0];
  const Mat<double, D> C0 = p.C[0];
  const std::vector<std::vector<Vec<double, D>>> modes0 = p.modes;
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  MpmProbe(sim).grid_velocity_update(0.0);
  MpmProbe(sim).grid_to_particles(0.0);
  double err = (p.v[0] - v0).norm() + (p.C[0] - C0).norm() * MpmProbe(sim).grid().dx;
  for (std::size_t j = 0; j < modes0.size(); ++j) err += (p.modes[j][0] - modes0[j][0]).norm();
  EXPECT_EQ(p.modes.size(), std::size_t(polypic::extra_modes(modes, D)));
  return err;
}

TEST(TpicPolypic, PolypicKeptModesRoundTripExactly) {
  double worst = 0;
  for (int m = 1; m <= 9; ++m) {
    const double e = kept_modes_round_trip<2>(m);
    worst = std::max(worst, e);
    EXPECT_LE(e, 1e-13) << m << " modes, 2D";  // O(1) coefficients: a few ulps each
  }
  for (int m : {1, 4, 5, 8, 9, 14, 20, 27}) {
    const double e = kept_modes_round_trip<3>(m);
    worst = std::max(worst, e);
    EXPECT_LE(e, 1e-13) << m << " modes, 3D";
  }
  std::printf("[ polypic kept modes ] worst round-trip error %.3g\n", worst);
}

// The modes are orthogonal under the weights at any particle position (the premise of the
// projection): Σ_i w s_r s_t = 0 for r ≠ t, for all 27 modes in 3D.
TEST(TpicPolypic, PolypicModesAreOrthogonal) {
  SceneDesc s = scene(3, "polypic", "quadratic");
  MpmSimulation<double, 3> sim(s);
  std::mt19937_64 rng(5);
  double worst = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Stencil<double, 3, QuadraticKernel> st;
    st.compute(test::random_vector<double, 3>(rng, 0.3, 0.7), MpmProbe(sim).grid());
    const auto b = polypic::axis_bases<double, 3>(st, MpmProbe(sim).grid().inv_dx);
    for (int r = 0; r < 27; ++r)
      for (int t = 0; t < 27; ++t) {
        double dot = 0;
        polypic::for_each_indexed_node<double, 3>(
            st, [&](std::size_t, double w, const std::array<int, 3>& k) {
              dot += w * polypic::mode_value<double, 3>(b, r, k) *
                     polypic::mode_value<double, 3>(b, t, k);
            });
        const double expected = r == t ? polypic::mode_norm<double, 3>(b, r) : 0.0;
        worst = std::max(worst, std::abs(dot - expected));
      }
  }
  EXPECT_LE(worst, 1e-15);
}

// PolyPIC with the affine modes only is APIC, with the constant mode only PIC: the same run to
// round-off (rotating disk, symplectic Euler, 40 steps; and a 3D block).
template <int D>
double max_difference(const SceneDesc& a, const SceneDesc& b, bool random_state) {
  MpmSimulation<double, D> sa(a), sb(b);
  if (random_state) {
    randomize_particles<D>(sa, 200, 9, 0.35, 0.65, false, a.solver.scheme == Scheme::pic);
    randomize_particles<D>(sb, 200, 9, 0.35, 0.65, false, b.solver.scheme == Scheme::pic);
    if (a.solver.scheme == Scheme::polypic) randomize_modes<D>(sa, 1);
    if (b.solver.scheme == Scheme::polypic) randomize_modes<D>(sb, 1);
  }
  for (int s = 0; s < 40; ++s) {
    sa.step_fixed(1e-4);
    sb.step_fixed(1e-4);
  }
  const auto &pa = MpmProbe(sa).particles(), &pb = MpmProbe(sb).particles();
  double d = 0;
  for (std::size_t q = 0; q < pa.size(); ++q) {
    EXPECT_EQ(pa.id[q], pb.id[q]);
    d = std::max({d, (pa.x[q] - pb.x[q]).norm(), (pa.v[q] - pb.v[q]).norm(),
                  (pa.C[q] - pb.C[q]).norm() * a.domain.dx});
  }
  return d;
}

TEST(TpicPolypic, PolypicReducesToApicAndPic) {
  const std::string disk = std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json";
  auto disk_scene = [&](const std::string& scheme, int modes) {
    return load_scene(disk, {"solver.integrator=symplectic", "solver.scheme=" + scheme,
                             "solver.polypic_modes=" + std::to_string(modes)});
  };
  const double apic2 = max_difference<2>(disk_scene("polypic", 3), disk_scene("apic", 0), false);
  const double pic2 = max_difference<2>(disk_scene("polypic", 1), disk_scene("pic", 0), false);
  const double apic3 =
      max_difference<3>(scene(3, "polypic", "quadratic", 4), scene(3, "apic", "quadratic"), true);
  const double pic3 =
      max_difference<3>(scene(3, "polypic", "quadratic", 1), scene(3, "pic", "quadratic"), true);
  std::printf(
      "[ polypic reductions ] 3 modes vs apic %.3g, 1 vs pic %.3g (2D); 4 vs apic %.3g, "
      "1 vs pic %.3g (3D)\n",
      apic2, pic2, apic3, pic3);
  EXPECT_LE(apic2, 1e-12);
  EXPECT_LE(pic2, 1e-12);
  EXPECT_LE(apic3, 1e-12);
  EXPECT_LE(pic3, 1e-12);
  // Not vacuous: the full basis differs from APIC on the same disk.
  EXPECT_GT(max_difference<2>(disk_scene("polypic", 9), disk_scene("apic", 0), false), 1e-9);
}

// Sec 5.4: one force-free particle keeps its velocity field and moves with v_p, 1000 steps.
template <int D>
void one_particle(const std::string& scheme, const std::string& kernel) {
  SCOPED_TRACE(::testing::Message() << scheme << " " << kernel << " " << D << "D");
  MpmSimulation<double, D> sim(scene(D, scheme, kernel));
  randomize_particles<D>(sim, 1, 77 + D, 0.4, 0.45);
  randomize_modes<D>(sim, 4);
  auto& p = MpmProbe(sim).particles();
  p.v[0] *= 0.1;  // moves ≤ 0.17 in 1000 steps of 1e-3: stays clear of the walls
  for (auto& m : p.modes) m[0] *= 0.1;
  p.volume0[0] = 0;  // no elastic force
  const Vec<double, D> v0 = p.v[0], x0 = p.x[0];
  const Mat<double, D> C0 = p.C[0];
  const auto modes0 = p.modes;
  const double dt = 1e-3;
  double err = 0;
  for (int s = 0; s < 1000; ++s) {
    sim.step_fixed(dt);
    err = std::max(err, (p.v[0] - v0).norm() + (p.C[0] - C0).norm() * MpmProbe(sim).grid().dx);
    for (std::size_t j = 0; j < modes0.size(); ++j)
      err = std::max(err, (p.modes[j][0] - modes0[j][0]).norm());
  }
  // As APIC's one-particle test: ~1e-14 per step of |v| + |C|Δx, below 1e-10 after 1000 steps.
  EXPECT_LE(err, 1e-10);
  EXPECT_LE((p.x[0] - (x0 + 1000 * dt * v0)).norm(), 1e-12);
  std::printf("[ one-particle %-7s %-9s %dD ] max drift of v, C, modes %.3g over 1000 steps\n",
              scheme.c_str(), kernel.c_str(), D, err);
}

TEST(TpicPolypic, OneParticleStable) {
  for (const char* k : {"linear", "quadratic", "cubic"}) {
    one_particle<2>("tpic", k);
    one_particle<3>("tpic", k);
  }
  one_particle<2>("polypic", "quadratic");
  one_particle<3>("polypic", "quadratic");
}

// Whole steps on the rotating disk (symplectic Euler, 500 steps): PolyPIC with all 9 modes
// conserves linear and angular momentum to round-off; TPIC conserves linear momentum and loses
// angular momentum, measured.
TEST(TpicPolypic, RotatingDiskConservation) {
  const std::string disk = std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json";
  for (const std::string scheme : {"polypic", "tpic"}) {
    MpmSimulation<double, 2> sim(
        load_scene(disk, {"solver.integrator=symplectic", R"(time.dt={"rule":"elastic","nu":0.3})",
                          "solver.scheme=" + scheme}));
    const DiagnosticsRow r0 = sim.measure();
    double sp = 0;
    for (std::size_t q = 0; q < sim.particle_count(); ++q)
      sp += MpmProbe(sim).particles().mass[q] * MpmProbe(sim).particles().v[q].norm();
    double dp = 0, dL = 0;
    for (int s = 0; s < 500; ++s) {
      DiagnosticsRow r;
      auto f = sim.step(100.0, &r);
      ASSERT_FALSE(f) << f->message;
      dp = std::max(dp, (test::to3(r.p) - test::to3(r0.p)).norm() / sp);
      dL = std::max(dL, std::abs(r.L[2] - r0.L[2]) / r0.L[2]);
    }
    std::printf("[ %s rotating disk ] 500 steps: max |dp|/Σm|v| = %.3g, max |dL|/L0 = %.3g\n",
                scheme.c_str(), dp, dL);
    EXPECT_LE(dp, 1e-12) << scheme;
    if (scheme == "polypic")
      EXPECT_LE(dL, 1e-12);
    else
      // measured 1.0e-6 after 500 steps (APIC and PolyPIC: ~1e-15)
      EXPECT_GT(dL, 1e-7) << "TPIC's G2P is not angular-momentum conserving (measured loss)";
  }
}

// PolyPIC needs the quadratic kernel and at most 3^dim modes; one clear line each.
TEST(TpicPolypic, PolypicRefusesOtherKernelsAndTooManyModes) {
  EXPECT_THROW(parse_scene_text(test::scene_json(2, "polypic", "cubic"), "t"), SceneError);
  EXPECT_THROW(parse_scene_text(test::scene_json(2, "polypic", "linear"), "t"), SceneError);
  auto with_modes = [](int dim, int m) {
    nlohmann::json j = nlohmann::json::parse(test::scene_json(dim, "polypic", "quadratic"));
    j["solver"]["polypic_modes"] = m;
    return parse_scene_text(j.dump(), "t");
  };
  EXPECT_THROW(with_modes(2, 10), SceneError);
  EXPECT_NO_THROW(with_modes(2, 9));
  EXPECT_NO_THROW(with_modes(3, 27));
  EXPECT_THROW(with_modes(3, 28), SceneError);
}

}  // namespace
}  // namespace apiclab
