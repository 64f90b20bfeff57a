// The one fixture of the transfer-scheme tests (tests/mpm/schemes/): a scene of any scheme,
// random PolyPIC modes, the moments the checks compare, and the checks every scheme goes through
// (test_scheme_properties.cpp walks every registered scheme through them).
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "sim/mpm/probe.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"
#include "tests/mpm/test_helpers.hpp"

namespace apiclab::test {

// Sums of ~1e4 O(1) products in double: round-off ~1e-15 relative; 1e-12 leaves room and is
// orders below any transfer error (TPIC's G2P loss is ≥ 2e-5).
constexpr double kRoundOff = 1e-12;

inline SceneDesc scheme_scene(int dim, const std::string& scheme, const std::string& kernel,
                              int modes = 0) {
  SceneDesc s = make_scene(dim, scheme, kernel);
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
    for (auto& c : mode) c = random_vector<double, D>(rng, -1.0, 1.0);
  const int kept = polypic::kept_modes(sim.scene().solver.polypic_modes, D);
  if (sim.scene().solver.scheme == Scheme::polypic)
    for (auto& C : p.C) polypic::keep_linear_modes<double, D>(C, kept);
}

// Scales for relative tolerances: Σ m|v| for momentum and Σ m(|x||v| + |C|Δx² + Σ|c_j|Δx) for
// angular momentum, so that a cancelling total (random velocities sum to ~0) is still judged
// fairly.
template <int D>
double momentum_scale(const MpmSimulation<double, D>& sim) {
  const auto& p = MpmProbe(sim).particles();
  double s = 0;
  for (std::size_t q = 0; q < p.size(); ++q) s += p.mass[q] * p.v[q].norm();
  return s;
}
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

// A relative change of p and L over one transfer.
struct Change {
  double p = 0, L = 0;
};

// P2G of random particles (and modes): the particles' p and L (measure(), with the affine and
// mode terms) against the grid's; mass as eq 24 has it.
template <int D>
Change p2g_change(const SceneDesc& scene, std::uint64_t seed) {
  MpmSimulation<double, D> sim(scene);
  randomize_particles<D>(sim, D == 2 ? 600 : 300, seed, 0.3, 0.7,
                         scene.solver.scheme == Scheme::rpic);
  randomize_modes<D>(sim, 3);
  const DiagnosticsRow before = sim.measure();
  double msum = 0;
  for (double m : MpmProbe(sim).particles().mass) msum += m;
  const double sp = momentum_scale<D>(sim), sL = angular_scale<D>(sim);
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  double mgrid = 0;
  for (double m : MpmProbe(sim).grid().mass) mgrid += m;
  EXPECT_NEAR(mgrid, msum, kRoundOff * msum) << "mass (eq 24)";
  MpmProbe(sim).grid_velocity_update(0.0);  // v_i = (mv)_i / m_i (eq 26); Δt = 0 leaves ṽ = v
  const GridMoments moments = MpmProbe(sim).grid_moments(false);
  const Eigen::Vector3d p = moments.momentum, L = moments.angular_momentum;
  return {(p - to3(before.p)).norm() / sp, (L - to3(before.L)).norm() / sL};
}

// G2P of random particles after P2G and a random grid velocity: with `kick` 0, ṽ = vⁿ (λ = 0,
// eqs 37-39); otherwise ṽ = vⁿ + a random change of at most `kick` (as a force gives). The grid's
// Σ m ṽ and Σ x̃ × m ṽ (x̃ = x + Δt ṽ) against the particles'.
template <int D>
Change g2p_change(const SceneDesc& scene, std::uint64_t seed, double dt, double kick = 0) {
  MpmSimulation<double, D> sim(scene);
  randomize_particles<D>(sim, D == 2 ? 600 : 300, seed, 0.3, 0.7,
                         scene.solver.scheme == Scheme::rpic,
                         kick > 0 && !is_affine(scene.solver.scheme));
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  MpmProbe(sim).grid_velocity_update(0.0);
  auto& g = MpmProbe(sim).grid();
  std::mt19937_64 rng(kick > 0 ? 5 : 99);
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (g.mass[i] <= 0) continue;
    if (kick > 0)
      g.velocity_new[i] = g.velocity[i] + random_vector<double, D>(rng, -kick, kick);
    else
      g.velocity[i] = g.velocity_new[i] = random_vector<double, D>(rng, -1.0, 1.0);
  }
  const MovedGridMoments m = moved_grid_moments<D>(g, dt);
  MpmProbe(sim).grid_to_particles(dt);
  const DiagnosticsRow after = sim.measure();
  return {(to3(after.p) - m.p).norm() / m.p_scale, (to3(after.L) - m.L).norm() / m.L_scale};
}

// Sec 5.5 of Jiang et al. 2017: particles with v_p = v + C x_p, C_p = C (RPIC: C skew, the
// rigid fields it reproduces); P2G then G2P with Δt = 0 returns the same v_p and C_p, and the grid
// velocity in between is v + C x_i on every node with mass (eq 96).
template <int D>
void particle_affine_round_trip(const std::string& scheme, const std::string& kernel) {
  SCOPED_TRACE(::testing::Message() << scheme << " " << kernel << " " << D << "D");
  MpmSimulation<double, D> sim(scheme_scene(D, scheme, kernel));
  const std::size_t n = D == 2 ? 300 : 150;
  randomize_particles<D>(sim, n, 5 + D);
  std::mt19937_64 rng(123);
  const Vec<double, D> v = random_vector<double, D>(rng, -1.0, 1.0);
  Mat<double, D> C = random_matrix<double, D>(rng, 2.0);
  if (scheme == "rpic") C = (0.5 * (C - C.transpose())).eval();
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

// Sec 5.4 of Jiang et al. 2017: one force-free particle keeps v_p, C_p (and PolyPIC's modes) and
// moves with v_p for 1000 steps of the full explicit step (no gravity in make_scene). ASFLIP:
// vⁿ_i = v + C r_i, so Σ w vⁿ = v_p and the FLIP term is zero. XPIC(5): S⁺S vⁿ = vⁿ on its nodes,
// so every term of the series past the first is zero. Schemes without C start with C = 0.
template <int D>
void one_particle(const std::string& scheme, const std::string& kernel) {
  SCOPED_TRACE(::testing::Message() << scheme << " " << kernel << " " << D << "D");
  SceneDesc scene = scheme_scene(D, scheme, kernel);
  scene.solver.xpic_order = 5;
  MpmSimulation<double, D> sim(scene);
  randomize_particles<D>(sim, 1, 77 + D, 0.4, 0.45, scheme == "rpic",
                         !is_affine(scene.solver.scheme));
  randomize_modes<D>(sim, 4);
  auto& p = MpmProbe(sim).particles();
  p.v[0] *= 0.1;  // moves ≤ 0.17 in 1000 steps of 1e-3: stays clear of the walls
  for (auto& m : p.modes) m[0] *= 0.1;
  p.volume0[0] = 0;  // no elastic energy, so no force as F follows C (eq 34 scales by V_p)
  const Vec<double, D> v0 = p.v[0], x0 = p.x[0];
  const Mat<double, D> C0 = p.C[0];
  const auto modes0 = p.modes;
  const double dt = 1e-3;
  double verr = 0, cerr = 0, err = 0;
  for (int s = 0; s < 1000; ++s) {
    sim.step_fixed(dt);  // the solver's own phase order
    verr = std::max(verr, (p.v[0] - v0).norm());
    cerr = std::max(cerr, (p.C[0] - C0).norm());
    err = std::max(err, (p.v[0] - v0).norm() + (p.C[0] - C0).norm() * MpmProbe(sim).grid().dx);
    for (std::size_t j = 0; j < modes0.size(); ++j)
      err = std::max(err, (p.modes[j][0] - modes0[j][0]).norm());
  }
  // Each step rounds B = Σ w ṽ rᵀ (|ṽ| ≤ |v| + |C|·2Δx) and divides by k Δx²: ~1e-14 of
  // |v|/Δx + |C| per step; 1000 steps of drift stay below 1e-10 of that scale, and below 1e-10
  // of |v| + |C|Δx (+ the modes) absolutely.
  const double scale = v0.norm() / MpmProbe(sim).grid().dx + C0.norm();
  EXPECT_LE(verr, 1e-10 * scale);
  EXPECT_LE(cerr, 1e-10 * scale);
  EXPECT_LE(err, 1e-10);
  EXPECT_LE((p.x[0] - (x0 + 1000 * dt * v0)).norm(), 1e-12) << "x_p^{n+1} = x_p^n + Δt v_p (eq 80)";
  std::printf("[ one-particle %-7s %-9s %dD ] max |dv| = %.3g, max |dC| = %.3g, modes %.3g\n",
              scheme.c_str(), kernel.c_str(), D, verr, cerr, err);
}

}  // namespace apiclab::test
