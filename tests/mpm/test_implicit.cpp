// Implicit grid updates (Jiang et al. 2017, Secs 3.4, 4.1-4.2): derivatives of the objective
// against finite differences, and the paper's conservation claims for the midpoint rule.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "sim/mpm/implicit/implicit_probe.hpp"
#include "sim/mpm/implicit/round_off_floor.hpp"
#include "sim/mpm/probe.hpp"
#include "sim/scene/scene.hpp"
#include "tests/shipped_scenes.hpp"

using namespace apiclab;

namespace {

// A small disk (2D) or ball (3D) away from the walls, with a given material model.
SceneDesc small_scene(int dim, const std::string& model) {
  std::string v = dim == 2 ? "[0.3, -0.2]" : "[0.3, -0.2, 0.1]";
  std::string json =
      std::string(R"({"dim":)") + std::to_string(dim) + R"(,
    "domain":{"min":)" +
      (dim == 2 ? "[0,0]" : "[0,0,0]") + R"(,"max":)" + (dim == 2 ? "[1,1]" : "[1,1,1]") +
      R"(,"dx":0.1},
    "gravity":)" +
      (dim == 2 ? "[0,-1]" : "[0,-1,0]") + R"(,
    "solver":{"scheme":"apic","integrator":"midpoint"},
    "materials":[{"model":")" +
      model + R"(","E":100,"nu":0.3,"rho":1}],
    "objects":[{"shape":{"type":"ball","center":)" +
      (dim == 2 ? "[0.5,0.5]" : "[0.5,0.5,0.5]") +
      R"(,"radius":0.2},"material":0,"sampling":{"type":"ppc","ppc":4},"velocity":)" + v + "}]}";
  return parse_scene_text(json, "test");
}

template <int D>
struct Fixture {
  MpmSimulation<double, D> sim;
  std::vector<Vec<double, D>> dv, dir;
  explicit Fixture(const SceneDesc& s, double dt, unsigned seed) : sim(s) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    for (auto& F : MpmProbe(sim).particles().F) {  // a deformed state, away from the rest shape
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j) F(i, j) += 0.15 * u(rng);
    }
    MpmProbe(sim).sort_particles();
    MpmProbe(sim).clear_grid();
    MpmProbe(sim).particles_to_grid(false);
    ImplicitProbe(sim).template implicit_begin<QuadraticKernel>(dt);
    dv.assign(MpmProbe(sim).grid().size(), Vec<double, D>::Zero());
    dir = dv;
    for (auto i : ImplicitProbe(sim).active_nodes()) {
      for (int a = 0; a < D; ++a) {
        dv[i][a] = 0.3 * u(rng);
        dir[i][a] = u(rng);
      }
    }
  }
  double energy(double h) {
    auto x = dv;
    for (auto i : ImplicitProbe(sim).active_nodes()) x[i] += h * dir[i];
    return ImplicitProbe(sim).template implicit_energy<QuadraticKernel>(x, false);
  }
  std::vector<Vec<double, D>> gradient(double h) {
    auto x = dv;
    for (auto i : ImplicitProbe(sim).active_nodes()) x[i] += h * dir[i];
    ImplicitProbe(sim).template implicit_energy<QuadraticKernel>(x, true);
    return ImplicitProbe(sim).implicit_gradient();
  }
};

template <int D>
void check_derivatives(const std::string& model, double dt) {
  Fixture<D> f(small_scene(D, model), dt, 7);
  const double h = 1e-5;
  // Gradient: central difference of E along dir, O(h²) accurate.
  auto g = f.gradient(0);
  double analytic = 0;
  for (auto i : ImplicitProbe(f.sim).active_nodes()) analytic += g[i].dot(f.dir[i]);
  double numeric = (f.energy(h) - f.energy(-h)) / (2 * h);
  EXPECT_NEAR(numeric, analytic, 1e-6 * std::abs(analytic)) << model << " " << D << "D";
  // Hessian-vector product (unprojected ∂P/∂F) against the difference of gradients.
  f.gradient(0);  // Fy at Δv
  ImplicitProbe(f.sim).implicit_update_hessian(false);
  std::vector<Vec<double, D>> Hd(MpmProbe(f.sim).grid().size(), Vec<double, D>::Zero());
  ImplicitProbe(f.sim).template implicit_hessian_apply<QuadraticKernel>(f.dir, Hd);
  auto gp = f.gradient(h), gm = f.gradient(-h);
  double err = 0, norm = 0;
  for (auto i : ImplicitProbe(f.sim).active_nodes()) {
    Vec<double, D> fd = (gp[i] - gm[i]) / (2 * h);
    err += (fd - Hd[i]).squaredNorm();
    norm += Hd[i].squaredNorm();
  }
  EXPECT_LT(std::sqrt(err / norm), 1e-6) << model << " " << D << "D";
}

double norm3(const std::array<double, 3>& a) {
  return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

}  // namespace

TEST(Implicit, GradientAndHessianMatchFiniteDifferences) {
  for (const char* model : {"neo-hookean", "fixed-corotated"}) {
    check_derivatives<2>(model, 0.01);
    check_derivatives<3>(model, 0.01);
  }
}

TEST(Implicit, MidpointConservesAngularMomentumOnRotatingDisk) {
  // Sec 5.3: exact for the exact solve, so |ΔL|/|L| is bounded by the Newton tolerance (1e-6,
  // a velocity-relative residual); measured 2e-9 over the paper's 2 s at CFL ν = 1.
  SceneDesc s = load_scene(apiclab::test::shipped_scene_path("rotating-disk"),
                           {"solver.integrator=midpoint", R"(time.dt={"rule":"cfl","nu":1})"});
  auto sim = make_simulation(s);
  DiagnosticsRow first = sim->measure();
  DiagnosticsRow last = first;
  double max_drift = 0;
  ASSERT_FALSE(sim->advance_to(2.0, [&](const DiagnosticsRow& r) {
    last = r;
    max_drift = std::max(max_drift, std::abs(r.total - first.total) / first.total);
  }));
  EXPECT_LT(std::abs(last.L[2] - first.L[2]) / std::abs(first.L[2]), 1e-7);
  // Fig 3: midpoint keeps the total energy within a few percent (measured 0.2%).
  EXPECT_LT(max_drift, 0.02);
}

// The same in 3D: a ball tumbling about a tilted axis, so every component of the Σ w (ṽ × vⁿ)
// term of eq 38 (G2P with moved nodes) carries angular momentum. No gravity, walls far away.
TEST(Implicit, MidpointConservesAngularMomentumOfTumblingBall3D) {
  const std::string json = R"({"name":"tumbling-ball","dim":3,
    "domain":{"min":[0,0,0],"max":[1,1,1],"dx":0.0625,"boundary":"slip"},
    "time":{"end":1,"fps":24,"dt":{"rule":"cfl","nu":1}},
    "solver":{"scheme":"apic","kernel":"quadratic","integrator":"midpoint"},
    "materials":[{"name":"m","model":"fixed-corotated","E":1000,"nu":0.3,"rho":10}],
    "objects":[{"shape":{"type":"ball","center":[0.5,0.5,0.5],"radius":0.2},"material":0,
      "sampling":{"type":"ppc","ppc":8},"angular_velocity":[0.6,-0.9,1.5]}]})";
  auto sim = make_simulation(parse_scene_text(json, "test"));
  const DiagnosticsRow first = sim->measure();
  DiagnosticsRow last = first;
  ASSERT_FALSE(sim->advance_to(0.5, [&](const DiagnosticsRow& r) { last = r; }));
  ASSERT_GT(last.step, 5);
  const double L0 = norm3(first.L);
  double dL = 0;
  for (int a = 0; a < 3; ++a) dL = std::max(dL, std::abs(last.L[a] - first.L[a]));
  std::printf("[ tumbling ball 3D, midpoint ] %ld steps: max |dL_a| / |L0| = %.3g\n", last.step,
              dL / L0);
  EXPECT_LT(dL / L0, 1e-6);
}

TEST(Implicit, LinearMomentumExactEvenWithTwoCgIterations) {
  // Sec 4.2: CG in the mass inner product keeps every vector velocity-like, so without external
  // forces Σ m v is preserved to round-off however early CG stops; block-Jacobi CG with the
  // translations deflated keeps it too (with gravity as well:
  // tests/mpm/test_cg_preconditioner.cpp). The disk gets a net velocity first.
  for (const char* preconditioner : {"mass", "block-jacobi"}) {
    SceneDesc s =
        load_scene(apiclab::test::shipped_scene_path("rotating-disk"),
                   {"solver.integrator=midpoint", "solver.cg_max_iterations=2",
                    std::string("solver.preconditioner=") + preconditioner,
                    "objects.0.velocity=[0.05,-0.03]", R"(time.dt={"rule":"cfl","nu":1})"});
    auto sim = make_simulation(s);
    DiagnosticsRow first = sim->measure();
    DiagnosticsRow last = first;
    ASSERT_FALSE(sim->advance_to(0.5, [&](const DiagnosticsRow& r) { last = r; }));
    double p0 = norm3(first.p);
    EXPECT_GT(last.cg_iters, 0);
    for (int a = 0; a < 2; ++a) EXPECT_NEAR(last.p[a], first.p[a], 1e-13 * p0) << preconditioner;
  }
}

TEST(Implicit, BackwardEulerVisiblyLosesEnergy) {
  auto run = [](const std::string& integrator) {
    SceneDesc s =
        load_scene(apiclab::test::shipped_scene_path("rotating-disk"),
                   {"solver.integrator=" + integrator, R"(time.dt={"rule":"cfl","nu":1})"});
    auto sim = make_simulation(s);
    double e0 = sim->measure().total;
    EXPECT_FALSE(sim->advance_to(2.0));
    return (sim->measure().total - e0) / e0;
  };
  double be = run("backward"), mp = run("midpoint");
  EXPECT_LT(be, -0.01);  // measured −2.5 % over 2 s
  EXPECT_LT(std::abs(mp), 0.01);
}

TEST(Implicit, LargeStepBlowsUpExplicitButNotImplicit) {
  // dt = 0.01 s is 8x the explicit elastic limit Δx / c ≈ 1.2e-3 s of the disk.
  auto run = [](const std::string& integrator, DiagnosticsRow* first, DiagnosticsRow* last) {
    SceneDesc s = load_scene(apiclab::test::shipped_scene_path("rotating-disk"),
                             {"solver.integrator=" + integrator, "time.end=1.0",
                              R"(time.dt={"rule":"fixed","value":0.01})"});
    auto sim = make_simulation(s);
    *first = sim->measure();
    *last = *first;
    return sim->advance_to(1.0, [&](const DiagnosticsRow& r) { *last = r; });
  };
  DiagnosticsRow f, l;
  auto blow = run("symplectic", &f, &l);
  ASSERT_TRUE(blow.has_value());
  EXPECT_FALSE(blow->quantity.empty());
  EXPECT_NE(blow->message.find("step"), std::string::npos);
  EXPECT_FALSE(run("backward", &f, &l).has_value());
  EXPECT_FALSE(run("midpoint", &f, &l).has_value());
  EXPECT_LT(std::abs(l.L[2] - f.L[2]) / std::abs(f.L[2]), 1e-6);
}

TEST(Implicit, NewtonConvergesQuadratically) {
  // One large midpoint step on a deformed ball: once the residual is small, each Newton
  // iteration roughly squares it (optimisation-stabilised Newton with an exact Hessian).
  SceneDesc s = small_scene(2, "neo-hookean");
  s.solver.newton_tolerance = 1e-13;
  s.solver.cg_tolerance = 1e-12;
  s.solver.cg_max_iterations = 1000;
  MpmSimulation<double, 2> sim(s);
  for (auto& F : MpmProbe(sim).particles().F) F << 1.2, 0.1, -0.05, 0.85;
  sim.step_fixed(0.02);
  const auto& r = ImplicitProbe(sim).newton_residuals();
  ASSERT_GE(r.size(), 3u);
  bool saw_quadratic = false;
  for (std::size_t k = 1; k + 1 < r.size(); ++k) {
    if (r[k] > 1e-3 * r[0] || r[k + 1] < 1e-12) continue;
    // r_{k+1} / r_k² bounded and the rate well above linear.
    double order = std::log(r[k + 1] / r[0]) / std::log(r[k] / r[0]);
    if (order > 1.6) saw_quadratic = true;
  }
  std::string seq;
  for (double x : r) seq += std::to_string(x) + " ";
  EXPECT_TRUE(saw_quadratic) << "residuals: " << seq;
}

// The ringing test's Lagrangian triangle mesh and penalty springs (Sec 6.7) enter E, its
// gradient and its Hessian like the particle elasticity: check them the same way.
TEST(Implicit, TriangleMeshGradientAndHessianMatchFiniteDifferences) {
  for (const char* model : {"neo-hookean", "fixed-corotated"}) {
    SceneDesc s =
        parse_scene_text(std::string(R"({"dim":2,"domain":{"min":[0,0],"max":[1,1],"dx":0.1},
      "gravity":[0,-1],"solver":{"scheme":"apic","kernel":"cubic","integrator":"backward"},
      "materials":[{"model":")") +
                             model + R"(","E":100,"nu":0.3,"rho":1}],
      "objects":[{"shape":{"type":"box","min":[0.3,0.3],"max":[0.6,0.7]},"material":0,
                  "sampling":{"type":"triangulated","spacing":0.05},"velocity":[0.5,0.1],
                  "anchors":{"rows":["top"],"stiffness":1000}}]})",
                         "test");
    MpmSimulation<double, 2> sim(s);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    MpmProbe(sim).sort_particles();
    MpmProbe(sim).clear_grid();
    MpmProbe(sim).particles_to_grid(false);
    ImplicitProbe(sim).implicit_begin<CubicKernel>(0.02);
    std::vector<Vec<double, 2>> dv((MpmProbe(sim).grid().size()), Vec<double, 2>::Zero()), dir = dv;
    for (auto i : ImplicitProbe(sim).active_nodes())
      for (int a = 0; a < 2; ++a) {
        dv[i][a] = 0.5 * u(rng);
        dir[i][a] = u(rng);
      }
    auto shifted = [&](double h) {
      auto x = dv;
      for (auto i : ImplicitProbe(sim).active_nodes()) x[i] += h * dir[i];
      return x;
    };
    const double h = 1e-5;
    ImplicitProbe(sim).implicit_energy<CubicKernel>(dv, true);
    auto g = ImplicitProbe(sim).implicit_gradient();
    double analytic = 0;
    for (auto i : ImplicitProbe(sim).active_nodes()) analytic += g[i].dot(dir[i]);
    double numeric = (ImplicitProbe(sim).implicit_energy<CubicKernel>(shifted(h), false) -
                      ImplicitProbe(sim).implicit_energy<CubicKernel>(shifted(-h), false)) /
                     (2 * h);
    EXPECT_NEAR(numeric, analytic, 1e-6 * std::abs(analytic)) << model;
    ImplicitProbe(sim).implicit_energy<CubicKernel>(dv, true);
    ImplicitProbe(sim).implicit_update_hessian(false);
    std::vector<Vec<double, 2>> Hd((MpmProbe(sim).grid().size()), Vec<double, 2>::Zero());
    ImplicitProbe(sim).implicit_hessian_apply<CubicKernel>(dir, Hd);
    ImplicitProbe(sim).implicit_energy<CubicKernel>(shifted(h), true);
    auto gp = ImplicitProbe(sim).implicit_gradient();
    ImplicitProbe(sim).implicit_energy<CubicKernel>(shifted(-h), true);
    auto gm = ImplicitProbe(sim).implicit_gradient();
    double err = 0, norm = 0;
    for (auto i : ImplicitProbe(sim).active_nodes()) {
      err += ((gp[i] - gm[i]) / (2 * h) - Hd[i]).squaredNorm();
      norm += Hd[i].squaredNorm();
    }
    EXPECT_LT(std::sqrt(err / norm), 1e-6) << model;
  }
}

// Fig 1 as numbers: at t = 40/24 s the FLIP target still carries velocity null modes and is
// far from its rest shape; PIC and APIC have filtered them out. The distance to the rest shape
// is the RMS corotated strain ‖F − R‖ over the target's triangles (a smooth swing of the whole
// target, which APIC still shows at this time, costs little; FLIP's scrambled mesh costs much).
TEST(Implicit, RingingFlipKeepsNoiseApicAndPicDoNot) {
  struct Result {
    double target_v_rms, target_strain_rms;
  };
  SceneDesc scene = load_scene(apiclab::test::shipped_scene_path("ringing"));
  const ObjectDesc& target = scene.objects[1];
  const double h = target.sampling.spacing;
  const int nx = int(std::lround((target.shape.max[0] - target.shape.min[0]) / h));
  const int ny = int(std::lround((target.shape.max[1] - target.shape.min[1]) / h));
  auto run = [&](const std::string& scheme) {
    SceneDesc s =
        load_scene(apiclab::test::shipped_scene_path("ringing"), {"solver.scheme=" + scheme});
    auto sim = make_simulation(s);
    auto start = sim->snapshot();
    EXPECT_FALSE(sim->advance_to(40.0 / 24.0)) << scheme;
    auto end = sim->snapshot();
    std::size_t first = 0;
    while (start->object[first] != 1)
      ++first;  // target vertices follow the projectile's, row by row
    auto at = [&](const Snapshot& snap, int i, int j) {
      std::size_t k = first + std::size_t(j) * std::size_t(nx + 1) + std::size_t(i);
      return Eigen::Vector2d(snap.positions[2 * k], snap.positions[2 * k + 1]);
    };
    double v2 = 0, strain2 = 0;
    int n = 0, tris = 0;
    for (std::size_t k = first; k < end->count(); ++k, ++n)
      v2 += std::pow(end->velocities[2 * k], 2) + std::pow(end->velocities[2 * k + 1], 2);
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (int t = 0; t < 2; ++t) {
          int c[3][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}};
          if (t == 1) {
            c[1][0] = i + 1;
            c[1][1] = j + 1;
            c[2][0] = i;
            c[2][1] = j + 1;
          }
          Eigen::Matrix2d Dm, Ds;
          Dm << at(*start, c[1][0], c[1][1]) - at(*start, c[0][0], c[0][1]),
              at(*start, c[2][0], c[2][1]) - at(*start, c[0][0], c[0][1]);
          Ds << at(*end, c[1][0], c[1][1]) - at(*end, c[0][0], c[0][1]),
              at(*end, c[2][0], c[2][1]) - at(*end, c[0][0], c[0][1]);
          Eigen::Matrix2d F = Ds * Dm.inverse(), R, S;
          polar_decomposition<double, 2>(F, R, S);
          strain2 += (F - R).squaredNorm();
          ++tris;
        }
    return Result{std::sqrt(v2 / n), std::sqrt(strain2 / tris)};
  };
  Result flip = run("flip"), apic = run("apic"), pic = run("pic");
  std::printf(
      "target velocity RMS: FLIP %.4g, APIC %.4g, PIC %.4g m/s; strain RMS: FLIP %.4g, APIC %.4g, "
      "PIC %.4g\n",
      flip.target_v_rms, apic.target_v_rms, pic.target_v_rms, flip.target_strain_rms,
      apic.target_strain_rms, pic.target_strain_rms);
  EXPECT_GT(flip.target_v_rms, 5 * apic.target_v_rms);  // measured 27x
  EXPECT_GT(flip.target_v_rms, 5 * pic.target_v_rms);
  EXPECT_LT(apic.target_strain_rms, flip.target_strain_rms);
}

// In float, Newton's and CG's tolerances are held to what float can resolve
// (sim/mpm/implicit/round_off_floor.hpp). One torus of torus-drop at the scene's resolution (8.5k
// particles; the whole scene stalled: 20 Newton and 2,268 CG iterations, not converged, on one
// free-fall step) takes one large midpoint step in free fall: it must converge in a few Newton
// iterations, and every particle must move at -g dt. Without the floor this torus alone stalls
// the same way (measured before the fix: 20 Newton, 2,265 CG iterations, residual 2.2e-7
// against a tolerance of 2e-7, 4.5 s); a coarser grid does not show it (dx = 0.02: 1 iteration).
TEST(Implicit, FloatFreeFallStepConvergesInAFewIterations) {
  SceneDesc s = load_scene(apiclab::test::shipped_scene_path("torus-drop"));
  s.objects.resize(1);
  MpmSimulation<float, 3> sim(s);
  const double dt = 0.02, c = s.materials[0].wave_speed();
  ASSERT_GT(c * dt / s.domain.dx, 5) << "the step must be far past the explicit limit";
  sim.step_fixed(dt);
  const DiagnosticsRow row = sim.measure();
  const auto& r = ImplicitProbe(sim).newton_residuals();
  std::string seq;
  for (double x : r) seq += std::to_string(x) + " ";
  EXPECT_TRUE(row.converged) << "residuals: " << seq;
  EXPECT_LE(r.size(), 4u) << "more than 3 Newton iterations: " << seq;
  EXPECT_LT(row.cg_iters, 200) << "CG iterations";
  const double v = 9.8 * dt;  // free fall: v_y = -g dt for every particle
  for (const auto& vp : MpmProbe(sim).particles().v) ASSERT_NEAR(vp[1], -v, 1e-4 * v);
}

// The floors: negligible in double (no tolerance in use is raised), decisive in float, and
// growing with the elastic Courant number (c dt / dx)² as derived in
// sim/mpm/implicit/round_off_floor.hpp.
TEST(Implicit, RoundOffFloorScalesWithEpsilonAndCourantNumber) {
  const double v = 0.2, dt = 0.02, dx = 0.4 / 70, c = 6.36, b = 0.25;
  const RoundOffFloor d = implicit_round_off_floor<double>(v, dt, dx, c, b);
  const RoundOffFloor f = implicit_round_off_floor<float>(v, dt, dx, c, b);
  EXPECT_LT(d.newton, 1e-6 * 1e-6 * v);  // far below the default tolerance 1e-6 v
  EXPECT_LT(d.cg, 1e-6 * 1e-6);
  EXPECT_GT(f.newton, 1e-6 * v);  // the default tolerance is below what float resolves here
  EXPECT_NEAR(f.newton / d.newton, double(FLT_EPSILON) / DBL_EPSILON, 1e-6 * f.newton / d.newton);
  const RoundOffFloor small = implicit_round_off_floor<float>(v, dt / 10, dx, c, b);
  // The velocity term ε v (1 + C²) and the stress's own round-off ε c C, C = c Δt / Δx (the
  // second was missing, and a body at rest was held to a tolerance its forces cannot resolve).
  const double courant = c * dt / 10 / dx;
  EXPECT_NEAR(small.newton, FLT_EPSILON * (v * (1 + courant * courant) + c * courant), 1e-12);
  EXPECT_LT(small.cg, f.cg);
  // With nothing moving the floor stays above zero: the stress term alone.
  EXPECT_NEAR(implicit_round_off_floor<double>(0, dt, dx, c, b).newton,
              DBL_EPSILON * c * c * dt / dx, 1e-20);
}

// Counts a run's steps whose implicit solve did not meet its tolerance, and its most Newton
// iterations in a step.
struct SolveCounts {
  long steps = 0, unconverged = 0;
  double max_newton = 0, worst_residual = 0;
  std::optional<Failure> failure;
};
SolveCounts run_counting(const SceneDesc& s) {
  SolveCounts c;
  auto sim = make_simulation(s);
  c.failure = sim->advance_to(s.time.end, [&](const DiagnosticsRow& r) {
    ++c.steps;
    c.unconverged += r.converged ? 0 : 1;
    c.max_newton = std::max(c.max_newton, r.newton_iters);
    c.worst_residual = std::max(c.worst_residual, r.residual);
  });
  return c;
}

// The flagship scene as shipped (midpoint, steps of the cfl rule) converges at every step. Its
// Newton solve used to stop after 2 of 20 iterations at a residual 7 % above the tolerance: the
// line search could not see E fall below E's own round-off (sim/mpm/implicit/newton_cg.hpp).
TEST(Implicit, RotatingDiskConvergesAtEveryStep) {
  const SolveCounts c =
      run_counting(load_scene(apiclab::test::shipped_scene_path("rotating-disk")));
  ASSERT_FALSE(c.failure) << c.failure->message;
  EXPECT_GT(c.steps, 0);
  EXPECT_EQ(c.unconverged, 0) << "worst residual " << c.worst_residual;
  EXPECT_LT(c.max_newton, 20) << "a step used the whole Newton cap";
}

// PIC's damping takes the disk's velocities down towards round-off; the tolerance stays relative
// to the scene's velocity scale, so small steps (the stability map's quarter and half of the
// explicit limit, 16x16 grid) converge at every step. Measured before: 40 and 88 (midpoint), 166
// and 90 (backward) steps not converged.
TEST(Implicit, PicSmallStepsConvergeAsItsVelocitiesDecay) {
  for (const char* integrator : {"midpoint", "backward"})
    for (double factor : {0.25, 0.5}) {
      const double dx = 0.0625, c = std::sqrt((1000.0 * 0.3 / (1.3 * 0.4) + 1000.0 / 1.3) / 2);
      const double dt = factor * dx / (c + 0.4 * 0.3);  // the sweep's dt_factor
      SceneDesc s = load_scene(
          apiclab::test::shipped_scene_path("rotating-disk"),
          {"solver.scheme=pic", std::string("solver.integrator=") + integrator, "time.end=0.5",
           "domain.dx=0.0625", R"(time.dt={"rule":"fixed","value":)" + std::to_string(dt) + "}"});
      const SolveCounts n = run_counting(s);
      ASSERT_FALSE(n.failure) << n.failure->message;
      EXPECT_EQ(n.unconverged, 0) << integrator << " at " << factor << " of the explicit limit, "
                                  << n.steps << " steps, worst residual " << n.worst_residual;
    }
}

// A body at rest, turned by a rotation (F = R: no stress but round-off, no velocity, no
// gravity), is neither unconverged nor blown up, explicit or implicit: its energy is round-off
// (it was more than 10 x the 1e-300 "energy available" of a scene with none), and its residual
// the stress's round-off (it was held to 1e-6 x 1e-12 m/s). Symplectic Euler takes the elastic
// rule's steps: at the scene's cfl steps (the frame interval, with nothing moving) it really
// explodes from that round-off, as the next test checks.
TEST(Implicit, BodyAtRestIsNeitherUnconvergedNorBlownUp) {
  for (const char* integrator : {"symplectic", "midpoint", "backward"}) {
    std::vector<std::string> sets = {"objects.0.angular_velocity=0", "time.end=0.25",
                                     std::string("solver.integrator=") + integrator};
    if (std::string(integrator) == "symplectic")
      sets.push_back(R"(time.dt={"rule":"elastic","nu":0.5})");
    SceneDesc s = load_scene(apiclab::test::shipped_scene_path("rotating-disk"), sets);
    MpmSimulation<double, 2> sim(s);
    const double a = 0.3;
    for (auto& F : MpmProbe(sim).particles().F)
      F << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    long unconverged = 0;
    double worst = 0;
    const auto failure = sim.advance_to(s.time.end, [&](const DiagnosticsRow& r) {
      unconverged += r.converged ? 0 : 1;
      worst = std::max(worst, r.residual);
    });
    EXPECT_FALSE(failure) << integrator << ": " << failure->message;
    EXPECT_EQ(unconverged, 0) << integrator << ", worst residual " << worst;
    EXPECT_LT(sim.measure().kinetic, 1e-20) << integrator << ": it did not stay at rest";
  }
}

// A run that really explodes is still caught: symplectic Euler 20x past the explicit limit on
// the same resting, rotated disk (round-off grows by a factor each step).
TEST(Implicit, BlowUpFromRestIsStillCaught) {
  SceneDesc s =
      load_scene(apiclab::test::shipped_scene_path("rotating-disk"),
                 {"objects.0.angular_velocity=0", "time.end=1", "solver.integrator=symplectic",
                  R"(time.dt={"rule":"fixed","value":0.025})"});
  MpmSimulation<double, 2> sim(s);
  for (auto& F : MpmProbe(sim).particles().F)
    F << std::cos(0.3), -std::sin(0.3), std::sin(0.3), std::cos(0.3);
  const auto failure = sim.advance_to(s.time.end);
  ASSERT_TRUE(failure) << "no blow-up at 20x the explicit limit";
  EXPECT_NE(failure->message.find("energy"), std::string::npos) << failure->message;
  EXPECT_GT(failure->step, 1) << "blown up on the first step, before round-off could grow: "
                              << failure->message;
}
