// The implicit solve's CG preconditioners (sim/mpm/implicit/newton_cg.hpp,
// sim/mpm/implicit/implicit.hpp): the block-Jacobi blocks are H's node blocks, deflation keeps
// linear momentum exact however early CG stops, and both preconditioners reach the same step to the
// Newton tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sim/mpm/implicit/implicit_probe.hpp"
#include "sim/mpm/probe.hpp"
#include "sim/scene/scene.hpp"
#include "tests/shipped_scenes.hpp"

using namespace apiclab;

namespace {

// A ball falling under gravity, far from the walls (no constraint acts on it).
SceneDesc falling_ball(int dim, const std::string& preconditioner, int cg_max_iterations) {
  const bool d2 = dim == 2;
  const std::string json = std::string(R"({"dim":)") + std::to_string(dim) +
                           R"(,"domain":{"min":)" + (d2 ? "[0,0]" : "[0,0,0]") + R"(,"max":)" +
                           (d2 ? "[1,1]" : "[1,1,1]") + R"(,"dx":0.0625},
    "gravity":)" + (d2 ? "[0,-9.8]" : "[0,-9.8,0]") +
                           R"(,"time":{"end":1,"fps":24,"dt":{"rule":"cfl","nu":1}},
    "solver":{"scheme":"apic","integrator":"midpoint","preconditioner":")" +
                           preconditioner + R"(","cg_max_iterations":)" +
                           std::to_string(cg_max_iterations) + R"(},
    "materials":[{"model":"neo-hookean","E":2000,"nu":0.3,"rho":1}],
    "objects":[{"shape":{"type":"ball","center":)" +
                           (d2 ? "[0.5,0.7]" : "[0.5,0.7,0.5]") +
                           R"(,"radius":0.15},"material":0,"sampling":{"type":"ppc","ppc":4},
      "velocity":)" + (d2 ? "[0.4,0.2]" : "[0.4,0.2,-0.3]") +
                           R"(,"angular_velocity":)" + (d2 ? "3" : "[1,-2,3]") + "}]}";
  return parse_scene_text(json, "test");
}

template <int D>
void check_blocks(unsigned seed) {
  SceneDesc s = falling_ball(D, "block-jacobi", 200);
  MpmSimulation<double, D> sim(s);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (auto& F : MpmProbe(sim).particles().F)  // a deformed state, so ∂P/∂F is far from isotropic
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) F(i, j) += 0.2 * u(rng);
  MpmProbe(sim).sort_particles();
  MpmProbe(sim).clear_grid();
  MpmProbe(sim).particles_to_grid(false);
  const double dt = 0.02;
  ImplicitProbe(sim).template implicit_begin<QuadraticKernel>(dt);
  std::vector<Vec<double, D>> dv((MpmProbe(sim).grid().size()), Vec<double, D>::Zero());
  ImplicitProbe(sim).template implicit_energy<QuadraticKernel>(dv,
                                                               true);  // F at the force position
  ImplicitProbe(sim).implicit_update_hessian(true);
  ImplicitProbe(sim).template implicit_block_jacobi<QuadraticKernel>();
  // H e_(i,a), column by column, through the operator CG uses; its node-i part is H_ii e_a.
  std::vector<Vec<double, D>> e((MpmProbe(sim).grid().size()), Vec<double, D>::Zero()), He = e;
  const auto& active = ImplicitProbe(sim).active_nodes();
  double worst = 0, stiffness = 0;
  for (std::size_t n = 0; n < active.size(); n += 7) {
    const std::uint32_t i = active[n];
    const Mat<double, D> block = ImplicitProbe(sim).block_jacobi_inverse()[i].inverse();
    for (int a = 0; a < D; ++a) {
      e[i][a] = 1;
      ImplicitProbe(sim).template implicit_hessian_apply<QuadraticKernel>(e, He);
      e[i][a] = 0;
      worst = std::max(worst, (He[i] - block.col(a)).norm() / He[i].norm());
      stiffness = std::max(stiffness, He[i].norm() / MpmProbe(sim).grid().mass[i]);
    }
  }
  std::printf(
      "[ block-Jacobi %dD ] max |H_ii e_a - block e_a| / |H_ii e_a| = %.2g (H/m up to %.3g)\n", D,
      worst, stiffness);
  EXPECT_LT(worst, 1e-13) << D << "D";
  EXPECT_GT(stiffness, 10.0) << "the stiffness part must dominate somewhere, or the test shows "
                                "nothing beyond the mass";
}

// Σ m v after every step against p₀ + t Σm g: what deflated CG guarantees (Σ r = 0, so the
// step's momentum is exact at the linear level) even when CG stops after two iterations.
template <int D>
double momentum_error(const std::string& preconditioner) {
  SceneDesc s = falling_ball(D, preconditioner, 2);
  auto sim = make_simulation(s);
  const DiagnosticsRow first = sim->measure();
  const double mass = sim->total_mass();
  double worst = 0, scale = 0;
  EXPECT_FALSE(sim->advance_to(0.25, [&](const DiagnosticsRow& r) {
    for (int a = 0; a < D; ++a) {
      const double expected = first.p[a] + r.t * mass * s.gravity[a];
      worst = std::max(worst, std::abs(r.p[a] - expected));
      scale = std::max(scale, std::abs(expected));
    }
  }));
  return worst / scale;
}

}  // namespace

TEST(CgPreconditioner, BlockJacobiBlocksAreTheHessiansNodeBlocks) {
  check_blocks<2>(3);
  check_blocks<3>(5);
}

TEST(CgPreconditioner, DeflationKeepsMomentumExactUnderGravityWithTwoCgIterations) {
  for (int dim : {2, 3}) {
    const double deflated =
        dim == 2 ? momentum_error<2>("block-jacobi") : momentum_error<3>("block-jacobi");
    const double mass = dim == 2 ? momentum_error<2>("mass") : momentum_error<3>("mass");
    std::printf(
        "[ %dD, 2 CG iterations a Newton step ] |p - p0 - t M g| / |p|: block-Jacobi "
        "(deflated) %.2g, mass %.2g\n",
        dim, deflated, mass);
    EXPECT_LT(deflated, 1e-12) << dim << "D";
  }
}

TEST(CgPreconditioner, BothPreconditionersTakeTheSameStepsToTheNewtonTolerance) {
  // Rotating disk, midpoint, 1 s: the two solves stop at different CG iterates, so states
  // differ by what the Newton tolerance (1e-6 of the reference speed) leaves, not more.
  std::vector<std::unique_ptr<MpmSimulation<double, 2>>> sims;
  long cg[2] = {0, 0};
  int k = 0;
  for (const char* pc : {"mass", "block-jacobi"}) {
    SceneDesc s = load_scene(apiclab::test::shipped_scene_path("rotating-disk"),
                             {std::string("solver.preconditioner=") + pc});
    sims.push_back(std::make_unique<MpmSimulation<double, 2>>(s));
    ASSERT_FALSE(
        sims.back()->advance_to(1.0, [&](const DiagnosticsRow& r) { cg[k] += r.cg_iters; }));
    ++k;
  }
  const auto &a = MpmProbe(*sims[0]).particles(), &b = MpmProbe(*sims[1]).particles();
  ASSERT_EQ(a.size(), b.size());
  double dx = 0, dv = 0, vmax = 0;
  for (std::size_t q = 0; q < a.size(); ++q) {
    dx = std::max(dx, (a.x[q] - b.x[q]).norm());
    dv = std::max(dv, (a.v[q] - b.v[q]).norm());
    vmax = std::max(vmax, a.v[q].norm());
  }
  std::printf(
      "[ rotating disk 1 s ] CG iterations mass %ld, block-Jacobi %ld (%.2f); max |dx| = "
      "%.2g m, max |dv| / max |v| = %.2g\n",
      cg[0], cg[1], double(cg[1]) / double(cg[0]), dx, dv / vmax);
  EXPECT_LT(dv / vmax, 1e-6);
  EXPECT_LT(dx, 1e-6);
  EXPECT_LT(cg[1], cg[0]);
}
