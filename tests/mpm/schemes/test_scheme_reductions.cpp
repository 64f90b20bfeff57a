// A scheme against what its paper says it reduces to or is: ASFLIP at α = 0 is APIC, XPIC(1) is
// PIC (both to the bit, whole runs); XPIC(m) is the operator series (I − (I − P)^m) on the particle
// velocities, P the PIC round trip, and never carries P's null modes; PolyPIC with the affine
// modes is APIC, with the constant mode PIC; PolyPIC's modes are orthogonal under the weights, and
// it refuses what it cannot run.
#include <Eigen/Dense>

#include "tests/mpm/schemes/scheme_fixture.hpp"

namespace apiclab {
namespace {

using test::make_scene;
using test::randomize_modes;
using test::randomize_particles;
using test::scheme_scene;

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
TEST(SchemeReductions, AsflipWithoutBlendIsApic) {
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
TEST(SchemeReductions, XpicOrderOneIsPic) {
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
TEST(SchemeReductions, XpicIsTheOperatorSeriesAndDropsTheNullSpace) {
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

// The modes are orthogonal under the weights at any particle position (the premise of the
// projection): Σ_i w s_r s_t = 0 for r ≠ t, for all 27 modes in 3D.
TEST(SchemeReductions, PolypicModesAreOrthogonal) {
  SceneDesc s = scheme_scene(3, "polypic", "quadratic");
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

TEST(SchemeReductions, PolypicReducesToApicAndPic) {
  const std::string disk = std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json";
  auto disk_scene = [&](const std::string& scheme, int modes) {
    return load_scene(disk, {"solver.integrator=symplectic", "solver.scheme=" + scheme,
                             "solver.polypic_modes=" + std::to_string(modes)});
  };
  const double apic2 = max_difference<2>(disk_scene("polypic", 3), disk_scene("apic", 0), false);
  const double pic2 = max_difference<2>(disk_scene("polypic", 1), disk_scene("pic", 0), false);
  const double apic3 = max_difference<3>(scheme_scene(3, "polypic", "quadratic", 4),
                                         scheme_scene(3, "apic", "quadratic"), true);
  const double pic3 = max_difference<3>(scheme_scene(3, "polypic", "quadratic", 1),
                                        scheme_scene(3, "pic", "quadratic"), true);
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

// PolyPIC needs the quadratic kernel and at most 3^dim modes; one clear line each.
TEST(SchemeReductions, PolypicRefusesOtherKernelsAndTooManyModes) {
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
