// Affine velocity fields through the transfers (Jiang et al. 2017, Sec 5.5): APIC and RPIC
// reproduce them particle → grid → particle; TPIC and PolyPIC grid → particle → grid; PolyPIC's
// kept modes return exactly; PIC, without C, cannot carry one (the checks are not vacuous).
#include "tests/mpm/schemes/scheme_fixture.hpp"

namespace apiclab {
namespace {

using test::randomize_modes;
using test::randomize_particles;
using test::scheme_scene;

TEST(AffineRoundTrip, ParticleFieldExact) {
  for (const char* k : {"quadratic", "cubic"}) {
    test::particle_affine_round_trip<2>("apic", k);
    test::particle_affine_round_trip<3>("apic", k);
    test::particle_affine_round_trip<2>("rpic", k);
    test::particle_affine_round_trip<3>("rpic", k);
  }
}

// PIC (no C) cannot carry an affine field through the round trip (random particles: the
// grid sees v_p at the particle centroid, not at x_i), which shows the test above is not vacuous.
TEST(AffineRoundTrip, PicLosesAffineField) {
  MpmSimulation<double, 2> sim(test::make_scene(2, "pic", "quadratic"));
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

// An affine grid field v + A x round-trips exactly (G2P then P2G at Δt = 0): v_p = v + A x_p,
// C_p = A (TPIC: Σ x_i ∇w_ipᵀ = I for B-splines), PolyPIC's higher modes 0, and the grid
// velocity after P2G again v + A x_i on every node with mass.
template <int D>
void grid_affine_round_trip(const std::string& scheme, const std::string& kernel) {
  SCOPED_TRACE(::testing::Message() << scheme << " " << kernel << " " << D << "D");
  MpmSimulation<double, D> sim(scheme_scene(D, scheme, kernel));
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

TEST(AffineRoundTrip, GridFieldExact) {
  for (const char* k : {"linear", "quadratic", "cubic"}) {
    grid_affine_round_trip<2>("tpic", k);
    grid_affine_round_trip<3>("tpic", k);
  }
  grid_affine_round_trip<2>("polypic", "quadratic");
  grid_affine_round_trip<3>("polypic", "quadratic");
}

// One particle with random coefficients in its kept modes: P2G gives the grid v_p(x_i) on the
// stencil, and G2P projects it back onto the same modes (orthogonal under the weights), so every
// kept coefficient returns exactly, for every mode count.
template <int D>
double kept_modes_round_trip(int modes) {
  MpmSimulation<double, D> sim(scheme_scene(D, "polypic", "quadratic", modes));
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

TEST(AffineRoundTrip, PolypicKeptModesExact) {
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

}  // namespace
}  // namespace apiclab
