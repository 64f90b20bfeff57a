// PolyPIC's G modes (Fu et al. 2017) on impacts: why polypic_modes >= 5 (2D) blows up where
// stressed material meets nearly empty grid nodes, measured against closed forms
// (README, Further transfer schemes). The rest of PolyPIC's tests: tests/mpm/schemes/.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sim/mpm/schemes/polypic_modes.hpp"
#include "tests/mpm/test_helpers.hpp"

namespace apiclab {
namespace {

using test::randomize_particles;

SceneDesc scene(int dim, const std::string& scheme, const std::string& kernel) {
  return test::make_scene(dim, scheme, kernel);
}

// Why PolyPIC with the G modes (polypic_modes >= 5 in 2D) blows up on impacts: a property of
// the method, not of this basis. G is exactly the paper's polynomial u² − a u − ¼ orthogonal to
// 1 and u under the axis weights (below: to 1e-15 of it at every position), so w_k G_k is
// proportional to (1, −2, 1) and the projection reads the grid with position-free weights:
//   c_G = Σ w ṽ G / Σ w G² = ½ (ṽ_0 − 2 ṽ_1 + ṽ_2),
// a node of kernel weight w → 0 still counts ½. APIC reads it with weight w. In explicit MPM a
// node reached only by a stencil's edge has mass m w and force ~ V τ |∇w|, so
// ṽ_i − v_i = −Δt V τ ∇w_i / (m w_i) grows like 1/δ for a particle δ cells from its stencil's
// edge: APIC's C is independent of δ, the G coefficient is C e_x · Δx · ĝ(f) / 4 with
// ĝ = Σ_k G_k ∂w_k/∂(x_p/Δx) / Σ_k w_k G_k², which grows like 1/δ. Its energy
// ½ m |c|² Σ w G² stays small while Σ w G² ≈ 2δ² is small, but it is the particle's: when the
// particle moves towards its stencil's centre (half a cell, a few steps on impact) Σ w G² grows
// to 3/16 and the kinetic energy with it, by N(centre)/N(edge) ~ 1/δ², from a bounded stress.
// Where stressed material meets nearly empty nodes (contact, impact) this feeds back.
namespace gmode {
// The quadratic B-spline in cells and its derivative (kernels.hpp, written out again here).
double w(double t) {
  t = std::abs(t);
  return t < 0.5 ? 0.75 - t * t : t < 1.5 ? 0.5 * (1.5 - t) * (1.5 - t) : 0.0;
}
double dw(double t) {
  const double a = std::abs(t), s = t < 0 ? -1.0 : 1.0;
  return a < 0.5 ? -2 * t : a < 1.5 ? -s * (1.5 - a) : 0.0;
}
// The three nodes of a particle at f = x_p/Δx − base ∈ [0.5, 1.5): t_k = f − k.
struct Axis {
  double wk[3], dwk[3], G[3], N = 0, g = 0;
  explicit Axis(double f) {
    double s1 = 0, su = 0, suu = 0, s3 = 0;
    for (int k = 0; k < 3; ++k) {
      wk[k] = w(f - k), dwk[k] = dw(f - k);
      const double u = k - f;
      s1 += wk[k], su += wk[k] * u, suu += wk[k] * u * u, s3 += wk[k] * u * u * u;
    }
    // G = u² − a u − b orthogonal to 1 and u: [s1 su; su suu] [b; a] = [suu; s3].
    const double det = s1 * suu - su * su, b = (suu * suu - su * s3) / det,
                 a = (s1 * s3 - su * suu) / det;
    for (int k = 0; k < 3; ++k) {
      const double u = k - f;
      G[k] = u * u - a * u - b;
      N += wk[k] * G[k] * G[k];
      g += G[k] * dwk[k];
    }
    g /= N;
  }
};
}  // namespace gmode

TEST(PolypicGModes, GIsThePapersPolynomialAndReadsEveryNodeAtHalfWeight) {
  SceneDesc s = scene(2, "polypic", "quadratic");
  MpmSimulation<double, 2> sim(s);
  const double dx = MpmProbe(sim).grid().dx;
  double worst_basis = 0, worst_weight = 0;
  for (double f = 0.505; f < 1.5; f += 0.01) {
    Stencil<double, 2, QuadraticKernel> st;
    st.compute(Vec<double, 2>((8 - 1 + f) * dx, 8 * dx), MpmProbe(sim).grid());
    const auto b = polypic::axis_bases<double, 2>(st, MpmProbe(sim).grid().inv_dx);
    const gmode::Axis ax(f);
    for (int k = 0; k < 3; ++k) {
      worst_basis = std::max(worst_basis, std::abs(b[0].value[2][k] - ax.G[k]));
      // the projection weight of node k: w_k G_k / Σ w G² = ½ (1, −2, 1)_k
      const double half = k == 1 ? -1.0 : 0.5;
      worst_weight = std::max(worst_weight, std::abs(ax.wk[k] * ax.G[k] / ax.N - half));
    }
  }
  std::printf("[ polypic G basis ] |G − (u² − a u − ¼)| ≤ %.2g, |w G / N − ½(1,−2,1)| ≤ %.2g\n",
              worst_basis, worst_weight);
  EXPECT_LE(worst_basis, 1e-14);  // the same function, two ways of writing it
  EXPECT_LE(worst_weight, 1e-9);  // next to w → 0 the closed form divides O(w²) by O(w²)
}

// One stressed particle alone (F = diag(1.2, 1), at rest, no gravity), δ cells from its x
// stencil's edge (f = 1.5 − δ), its y stencil centred: one symplectic Euler step.
struct EdgeKick {
  double c_gx = 0, theory = 0, apic_cxx = 0, kinetic_edge = 0, kinetic_centre = 0, elastic = 0;
};
EdgeKick edge_kick(const std::string& scheme, double delta) {
  SceneDesc s = scene(2, scheme, "quadratic");
  s.gravity = {0, 0, 0};
  MpmSimulation<double, 2> sim(s);
  randomize_particles<2>(sim, 1, 3);
  auto& p = MpmProbe(sim).particles();
  const double dx = MpmProbe(sim).grid().dx;
  p.x[0] = Vec<double, 2>((8 + 0.5 - delta) * dx, 8 * dx);
  p.v[0].setZero();
  p.C[0].setZero();
  p.F[0] = Vec<double, 2>(1.2, 1.0).asDiagonal();
  p.mass[0] = p.volume0[0] = dx * dx / 4;
  for (auto& m : p.modes) m[0].setZero();
  EdgeKick e;
  e.elastic = sim.measure().elastic;
  sim.step_fixed(1e-4);
  e.apic_cxx = p.C[0](0, 0);
  int gx = 0;  // the stored index of the mode G_x (degrees {2, 0})
  while (polypic::mode_degrees<2>()[std::size_t(gx + 3)] != std::array<int, 2>{2, 0}) ++gx;
  if (!p.modes.empty()) e.c_gx = p.modes[std::size_t(gx)][0][0];
  e.theory = p.C[0](0, 0) * dx * gmode::Axis(1.5 - delta).g / 4;
  e.kinetic_edge = sim.measure().kinetic;
  p.x[0][0] = (8 + 0.0) * dx;  // the same particle state, half a cell on: its stencil's centre
  e.kinetic_centre = sim.measure().kinetic;
  return e;
}

TEST(PolypicGModes, KickGrowsAsOneOverDistanceToTheStencilEdge) {
  std::vector<double> deltas{0.25, 0.1, 0.03, 0.01, 0.003};
  std::vector<EdgeKick> poly, apic;
  for (double d : deltas)
    poly.push_back(edge_kick("polypic", d)), apic.push_back(edge_kick("apic", d));
  for (std::size_t i = 0; i < deltas.size(); ++i) {
    std::printf(
        "[ polypic G kick ] δ = %-5g c_Gx = %-10.4g theory %-10.4g (APIC C_xx %.4g, PolyPIC "
        "%.4g); kinetic/elastic at the edge %.3g, half a cell on %.3g (APIC %.3g)\n",
        deltas[i], poly[i].c_gx, poly[i].theory, apic[i].apic_cxx, poly[i].apic_cxx,
        poly[i].kinetic_edge / poly[i].elastic, poly[i].kinetic_centre / poly[i].elastic,
        apic[i].kinetic_centre / apic[i].elastic);
    // the step's G coefficient is the closed form above
    EXPECT_NEAR(poly[i].c_gx, poly[i].theory, 1e-9 * std::abs(poly[i].theory)) << deltas[i];
    // C is APIC's, the same at every δ: −Δt τ D⁻¹ / ρ (quadratic B-splines)
    EXPECT_NEAR(poly[i].apic_cxx, apic[0].apic_cxx, 1e-9 * std::abs(apic[0].apic_cxx));
    EXPECT_NEAR(apic[i].apic_cxx, apic[0].apic_cxx, 1e-9 * std::abs(apic[0].apic_cxx));
  }
  // 1/δ: δ c_Gx tends to a constant, with a first-order correction O(δ) (measured: 2.1 %
  // between δ = 0.01 and 0.003), so c_Gx grows about 170× from a lattice particle's δ = 1/4 to
  // δ = 0.003 while APIC's C does not move.
  const double a = deltas[3] * poly[3].c_gx, b = deltas[4] * poly[4].c_gx;
  EXPECT_NEAR(a / b, 1.0, 0.04);
  EXPECT_GT(std::abs(poly[4].c_gx / poly[0].c_gx), 100.0);
  // Energy: at the edge the mode's share is bounded; half a cell on it is ~1/δ² larger.
  // Theory: kinetic_centre − kinetic_edge = ½ m c² (N(1) − N(1.5 − δ)), N(1) = 3/16.
  const double m = std::pow(1.0 / 16, 2) / 4;
  for (std::size_t i = 0; i < deltas.size(); ++i) {
    const double gained =
        0.5 * m * poly[i].c_gx * poly[i].c_gx * (3.0 / 16 - gmode::Axis(1.5 - deltas[i]).N);
    EXPECT_NEAR(poly[i].kinetic_centre - poly[i].kinetic_edge, gained, 1e-6 * gained);
    EXPECT_NEAR(apic[i].kinetic_centre, apic[i].kinetic_edge, 1e-12 * apic[i].kinetic_edge);
  }
  EXPECT_GT(poly[4].kinetic_centre / poly[0].kinetic_centre, 1000.0);
}

}  // namespace
}  // namespace apiclab
