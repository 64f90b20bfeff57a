// ASFLIP (Fei et al. 2021) and XPIC(m) (Hammerquist and Nairn 2017) against what their papers
// state: ASFLIP at α = 0 is APIC, XPIC(1) is PIC (both to the bit, whole runs); XPIC(m) is the
// operator series (I − (I − P)^m) on the particle velocities, P the PIC round trip, and never
// carries P's null modes; what each conserves over one G2P (linear momentum exactly, angular
// momentum not: the loss is measured); one force-free particle stays put (Sec 5.4 of Jiang et
// al. 2017); the diagnostics count ASFLIP's affine term as APIC's.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>

#include "sim/scene/parameters.hpp"
#include "tests/mpm/test_helpers.hpp"

namespace apiclab {
namespace {

using test::make_scene;
using test::randomize_particles;

// The disk with symplectic Euler at the explicit elastic limit (tests/mpm/test_implicit.cpp covers
// the scene's own midpoint rule).
SceneDesc disk(const std::string& scheme, std::vector<std::string> extra = {}) {
  return test::disk_symplectic(scheme, std::move(extra));
}

// Largest |a − b| over x, v, C and F after `steps` whole steps, particles matched by id.
double run_difference(const SceneDesc& a, const SceneDesc& b, int steps) {
  MpmSimulation<double, 2> sa(a), sb(b);
  for (int s = 0; s < steps; ++s) {
    EXPECT_FALSE(sa.step(100.0, nullptr));
    EXPECT_FALSE(sb.step(100.0, nullptr));
  }
  const auto &pa = MpmProbe(sa).particles(), &pb = MpmProbe(sb).particles();
  std::vector<std::size_t> at(pb.size());
  for (std::size_t q = 0; q < pb.size(); ++q) at[std::size_t(pb.id[q])] = q;
  double d = 0;
  for (std::size_t q = 0; q < pa.size(); ++q) {
    const std::size_t r = at[std::size_t(pa.id[q])];
    d = std::max({d, (pa.x[q] - pb.x[r]).norm(), (pa.v[q] - pb.v[r]).norm(),
                  (pa.C[q] - pb.C[r]).norm(), (pa.F[q] - pb.F[r]).norm()});
  }
  return d;
}

// Fei et al. 2021: v ← v^PIC + α (v_p − v_old), x ← x + Δt (v^PIC + β α (v_p − v_old)); with α = 0
// both terms vanish and the step is APIC's, operation for operation.
TEST(AsflipXpic, AsflipWithoutBlendIsApic) {
  const double d = run_difference(
      disk("apic"), disk("asflip", {"solver.flip_alpha=0", "solver.asflip_beta=0"}), 300);
  EXPECT_EQ(d, 0.0) << "ASFLIP(α = 0, β = 0) left APIC by " << d;
  // The blend itself changes the run (so the comparison above is not vacuous).
  const double blended = run_difference(
      disk("apic"), disk("asflip", {"solver.flip_alpha=1", "solver.asflip_beta=1"}), 300);
  std::printf("[ asflip ] 300 disk steps: |ASFLIP(0,0) - APIC| = %g, |ASFLIP(1,1) - APIC| = %.3g\n",
              d, blended);
  EXPECT_GT(blended, 1e-9);
}

// Hammerquist and Nairn 2017: XPIC(1) is PIC. m = 1 runs no grid pass and adds no term.
TEST(AsflipXpic, XpicOrderOneIsPic) {
  const double d = run_difference(disk("pic"), disk("xpic", {"solver.xpic_order=1"}), 300);
  EXPECT_EQ(d, 0.0) << "XPIC(1) left PIC by " << d;
  const double m2 = run_difference(disk("pic"), disk("xpic", {"solver.xpic_order=2"}), 300);
  std::printf("[ xpic ] 300 disk steps: |XPIC(1) - PIC| = %g, |XPIC(2) - PIC| = %.3g\n", d, m2);
  EXPECT_GT(m2, 1e-6);
}

// Without forces ṽ = vⁿ, and XPIC(m)'s update is V^{n+1} = (I − (I − P)^m) Vⁿ with P the PIC round
// trip P_pq = Σ_i w_ip m_q w_iq / m_i. P is built here from the kernel weights alone, its powers
// and spectrum by Eigen; the solver's m − 1 grid passes must give the same velocities. As m → ∞
// the update tends to Vⁿ − Π Vⁿ, Π the projection on ker P (the velocity modes the grid cannot
// see): FLIP without its null-space noise, the limit the paper states.
TEST(AsflipXpic, XpicIsTheOperatorSeriesAndDropsTheNullSpace) {
  constexpr std::size_t n = 400;  // more particles than the ~100 nodes they touch: ker P ≠ {0}
  SceneDesc scene = make_scene(2, "xpic", "quadratic");
  MpmSimulation<double, 2> base(scene);
  randomize_particles<2>(base, n, 2024, 0.35, 0.65, false, true);
  auto& bp = MpmProbe(base).particles();
  for (std::size_t q = 0; q < n; ++q)
    bp.mass[q] = 1, bp.volume0[q] = 1;  // P symmetric; F = I: no stress
  // P from the weights at xⁿ (the state's own order: the solver sorts a copy).
  // The whole domain's nodes (the solver's own grid stores only the box it needs, from a sort).
  Grid<double, 2> whole = MpmProbe(base).grid();
  whole.store_whole_domain();
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(Eigen::Index(whole.size()), Eigen::Index(n));
  for (std::size_t q = 0; q < n; ++q) {
    Stencil<double, 2, QuadraticKernel> st;
    st.compute(bp.x[q], whole);
    st.for_each([&](std::size_t i, double w, const Vec<double, 2>&, const Vec<double, 2>&) {
      W(Eigen::Index(i), Eigen::Index(q)) += w;
    });
  }
  const Eigen::VectorXd mi = W.rowwise().sum();  // unit masses
  Eigen::VectorXd inv_mi = Eigen::VectorXd::Zero(mi.size());
  for (Eigen::Index i = 0; i < mi.size(); ++i)
    if (mi[i] > 0) inv_mi[i] = 1 / mi[i];
  const Eigen::MatrixXd P = W.transpose() * inv_mi.asDiagonal() * W;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(P);
  const Eigen::VectorXd lambda = eig.eigenvalues();
  Eigen::MatrixXd null_basis(Eigen::Index(n), 0);
  int nulls = 0;
  for (Eigen::Index k = 0; k < lambda.size(); ++k)
    if (lambda[k] < 1e-10) ++nulls;
  null_basis = eig.eigenvectors().leftCols(nulls);  // ascending eigenvalues
  ASSERT_GT(nulls, 0);
  EXPECT_GT(lambda.minCoeff(), -1e-12);
  EXPECT_LT(lambda.maxCoeff(), 1 + 1e-12);  // 0 ≤ P ≤ I: the series' terms never grow

  Eigen::MatrixXd V0(Eigen::Index(n), 2);
  for (std::size_t q = 0; q < n; ++q) V0.row(Eigen::Index(q)) = bp.v[q].transpose();
  const Eigen::MatrixXd limit = V0 - null_basis * (null_basis.transpose() * V0);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(Eigen::Index(n), Eigen::Index(n));
  double last_distance = 1e300, worst_series = 0, worst_null = 0;
  for (int m : {1, 2, 3, 5, 10, 40, 200, 1000}) {
    MpmSimulation<double, 2> sim = base;
    MpmProbe(sim).solver().xpic_order = m;
    sim.step_fixed(1e-4);
    Eigen::MatrixXd V(Eigen::Index(n), 2);
    for (std::size_t q = 0; q < n; ++q)
      V.row(Eigen::Index(MpmProbe(sim).particles().id[q])) =
          MpmProbe(sim).particles().v[q].transpose();
    Eigen::MatrixXd expected = V0;
    if (m <= 40) {  // dense powers: (I − P)^m by repeated products
      Eigen::MatrixXd Q = I;
      for (int k = 0; k < m; ++k) Q = (Q * (I - P)).eval();
      expected = V0 - Q * V0;
    } else {  // spectrally: 1 − (1 − λ)^m on each eigenvector
      Eigen::VectorXd f(lambda.size());
      for (Eigen::Index k = 0; k < f.size(); ++k) f[k] = 1 - std::pow(1 - lambda[k], m);
      expected = eig.eigenvectors() * f.asDiagonal() * eig.eigenvectors().transpose() * V0;
    }
    const double series = (V - expected).norm() / V0.norm();
    const double null_part = (null_basis.transpose() * V).norm() / V0.norm();
    const double distance = (V - limit).norm() / V0.norm();
    worst_series = std::max(worst_series, series);
    worst_null = std::max(worst_null, null_part);
    std::printf(
        "[ xpic(%4d) ] |V - series|/|V0| = %.2g, |null part| = %.2g, |V - limit|/|V0| = %.4f\n", m,
        series, null_part, distance);
    EXPECT_LT(distance, last_distance) << "XPIC(m) does not approach the limit at m = " << m;
    last_distance = distance;
  }
  // Sums of ~10⁴ O(1) products per term and up to 999 passes: measured ≤ 2e-13 relative; a
  // wrong sign or a lost term of the series is O(1e-2) or more.
  EXPECT_LT(worst_series, 1e-11);
  EXPECT_LT(worst_null, 1e-11) << "XPIC must not carry velocity modes the grid cannot see";
  std::printf("[ xpic ] %d null modes of %zu; distance to the limit at m = 1000: %.4f\n", nulls, n,
              last_distance);
}

// One G2P after a random grid update (ṽ ≠ vⁿ, as a force gives): the particles' p and L against
// the grid's Σ m ṽ and Σ x̃ × m ṽ. APIC is exact in both (Jiang et al. 2017, Sec 5.3). ASFLIP keeps
// p exactly (Σ m (v_p − Σ w vⁿ) = 0 after APIC's P2G) but not L; XPIC keeps p (S⁺S keeps the
// mass-weighted sum, so Σ m_i e_i = 0) but not L, like PIC.
struct Moments {
  double dp, dL;
};
template <int D>
Moments g2p_moments(const std::string& scheme, const std::vector<std::string>& sets) {
  SceneDesc scene = make_scene(D, scheme, "quadratic");
  for (const auto& s : sets)
    apply_parameter(scene, s.substr(0, s.find('=')), std::stod(s.substr(s.find('=') + 1)));
  MpmSimulation<double, D> sim(scene);
  randomize_particles<D>(sim, D == 2 ? 600 : 300, 31 + D, 0.3, 0.7, false,
                         !is_affine(scene.solver.scheme));
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  MpmProbe(sim).grid_velocity_update(0.0);
  auto& g = MpmProbe(sim).grid();
  std::mt19937_64 rng(5);
  const double dt = 0.01;
  for (std::size_t i = 0; i < g.size(); ++i)
    if (g.mass[i] > 0)
      g.velocity_new[i] = g.velocity[i] + test::random_vector<double, D>(rng, -0.5, 0.5);
  const test::GridMoments m = test::grid_moments<D>(g, dt);
  MpmProbe(sim).grid_to_particles(dt);
  const DiagnosticsRow after = sim.measure();
  return {(test::to3(after.p) - m.p).norm() / m.p_scale,
          (test::to3(after.L) - m.L).norm() / m.L_scale};
}

template <int D>
void g2p_moments_all() {
  const Moments apic = g2p_moments<D>("apic", {});
  const Moments asflip = g2p_moments<D>("asflip", {"solver.flip_alpha=1", "solver.asflip_beta=0"});
  const Moments asflip_beta =
      g2p_moments<D>("asflip", {"solver.flip_alpha=1", "solver.asflip_beta=1"});
  const Moments pic = g2p_moments<D>("pic", {});
  const Moments xpic = g2p_moments<D>("xpic", {"solver.xpic_order=4"});
  std::printf(
      "[ G2P %dD ] relative |dp|, |dL|: APIC %.2g %.2g; ASFLIP(1,0) %.2g %.2g; ASFLIP(1,1) "
      "%.2g %.2g; PIC %.2g %.2g; XPIC(4) %.2g %.2g\n",
      D, apic.dp, apic.dL, asflip.dp, asflip.dL, asflip_beta.dp, asflip_beta.dL, pic.dp, pic.dL,
      xpic.dp, xpic.dL);
  // Round-off of sums of ~10⁴ O(1) products: 1e-12 relative, as tests/mpm/test_transfers.cpp.
  for (const Moments& m : {apic, asflip, asflip_beta, pic, xpic}) EXPECT_LE(m.dp, 1e-12);
  EXPECT_LE(apic.dL, 1e-12);
  // The measured losses (random particles, |ṽ − vⁿ| ≤ 0.5): ASFLIP's FLIP term and XPIC's
  // smoothed field both move L by ~1e-3..1e-2 of its scale, ten orders above round-off.
  EXPECT_GT(asflip.dL, 1e-5);
  EXPECT_GT(asflip_beta.dL, 1e-5);
  EXPECT_GT(xpic.dL, 1e-5);
}

TEST(AsflipXpic, G2PConservesLinearMomentumNotAngular2D) { g2p_moments_all<2>(); }
TEST(AsflipXpic, G2PConservesLinearMomentumNotAngular3D) { g2p_moments_all<3>(); }

// Sec 5.4 of Jiang et al. 2017, as tests/mpm/test_transfers.cpp's OneParticleStable: one force-free
// particle keeps v_p and C_p for 1000 steps. ASFLIP: vⁿ_i = v + C r_i, so Σ w vⁿ = v_p and the FLIP
// term is zero. XPIC: S⁺S vⁿ = vⁿ on its nodes, so every term of the series past the first is zero.
template <int D>
void one_particle(const std::string& scheme, const std::string& kernel) {
  SCOPED_TRACE(::testing::Message() << scheme << " " << kernel << " " << D << "D");
  SceneDesc scene = make_scene(D, scheme, kernel);
  scene.solver.xpic_order = 5;
  MpmSimulation<double, D> sim(scene);
  randomize_particles<D>(sim, 1, 77 + D, 0.4, 0.45, false, scheme == "xpic");
  auto& p = MpmProbe(sim).particles();
  p.v[0] *= 0.1;
  p.volume0[0] = 0;
  const Vec<double, D> v0 = p.v[0], x0 = p.x[0];
  const Mat<double, D> C0 = p.C[0];
  const double dt = 1e-3;
  double verr = 0, cerr = 0;
  for (int s = 0; s < 1000; ++s) {
    sim.step_fixed(dt);
    verr = std::max(verr, (p.v[0] - v0).norm());
    cerr = std::max(cerr, (p.C[0] - C0).norm());
  }
  const double scale = v0.norm() / MpmProbe(sim).grid().dx + C0.norm();
  EXPECT_LE(verr, 1e-10 * scale);
  EXPECT_LE(cerr, 1e-10 * scale);
  EXPECT_LE((p.x[0] - (x0 + 1000 * dt * v0)).norm(), 1e-12);
  std::printf("[ one-particle %s %dD %-9s ] max |dv| = %.3g, max |dC| = %.3g over 1000 steps\n",
              scheme.c_str(), D, kernel.c_str(), verr, cerr);
}

TEST(AsflipXpic, OneParticleStable) {
  for (const char* s : {"asflip", "xpic"})
    for (const char* k : {"quadratic", "cubic"}) {
      one_particle<2>(s, k);
      one_particle<3>(s, k);
    }
}

// ASFLIP carries APIC's C: the diagnostics count its affine kinetic energy and angular momentum
// (½ m tr(C D Cᵀ), m (C D)ᵀ's skew part) exactly as APIC's.
TEST(AsflipXpic, DiagnosticsCountAsflipsAffineTerm) {
  MpmSimulation<double, 2> apic(disk("apic")), asflip(disk("asflip")), pic(disk("pic"));
  const DiagnosticsRow a = apic.measure(), s = asflip.measure(), p = pic.measure();
  EXPECT_EQ(a.kinetic, s.kinetic);
  EXPECT_EQ(a.L[2], s.L[2]);
  EXPECT_GT(a.L[2] - p.L[2], 1e-3 * a.L[2]);  // the affine term is there to count
}

}  // namespace
}  // namespace apiclab
