// The optimised explicit step (MpmSimulation::step_fixed) against the readable one in
// sim/reference/reference_step.hpp: same state, 20 steps, every scheme × kernel, 2D and 3D, walls
// (with a collider plane) and periodic; x, v, C and F must agree to round-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "sim/mpm/probe.hpp"
#include "sim/reference/reference_setup.hpp"

namespace apiclab {
namespace {

constexpr double kDx = 1.0 / 16, kDt = 5e-4;
constexpr int kSteps = 20;

struct Case {
  Scheme scheme;
  double flip_alpha;
  KernelType kernel = KernelType::quadratic;
  bool periodic = false;
  double asflip_beta = 0;  // ASFLIP's position correction (Fei et al. 2021)
  int xpic_order = 1;      // XPIC's m (Hammerquist and Nairn 2017)
  int polypic_modes = 0;   // PolyPIC's kept modes (Fu et al. 2017; 0 = all)
  std::string name() const {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s(α=%.2f β=%.2f m=%d modes %d) %s %s",
                  std::string(key_of(scheme)).c_str(), flip_alpha, asflip_beta, xpic_order,
                  polypic_modes, std::string(key_of(kernel)).c_str(),
                  periodic ? "periodic" : "walls");
    return buf;
  }
};

// Unit square (cube), Δx = 1/16. The block touches the lower walls: slip and separate in 2D,
// sticky, separate and slip in 3D; in 2D also a slanted collider plane (slip) at its far
// corner. Neo-Hookean in 2D, fixed corotated in 3D.
SceneDesc scene_for(int dim, const Case& c) {
  SceneDesc s;
  s.name = "reference-step";
  s.dim = dim;
  s.domain.min = {0, 0, 0};
  s.domain.max = {1, 1, dim == 3 ? 1.0 : 0.0};
  s.domain.dx = kDx;
  using BC = BoundaryCondition;
  if (c.periodic)
    s.domain.walls.fill(BC::periodic);
  else if (dim == 2)
    s.domain.walls = {BC::slip, BC::sticky, BC::separate, BC::slip, BC::slip, BC::slip};
  else
    s.domain.walls = {BC::sticky, BC::slip, BC::separate, BC::slip, BC::slip, BC::sticky};
  if (!c.periodic) {
    const double n = -1 / std::sqrt(2.0);
    ColliderDesc plane;
    plane.point = {0.5, 0.5, 0.5};
    plane.normal = {n, n, 0};
    plane.condition = BC::slip;
    s.colliders.push_back(plane);
  }
  s.gravity = {0.5, -9.8, 0};
  s.solver.scheme = c.scheme;
  s.solver.flip_alpha = c.flip_alpha;
  s.solver.asflip_beta = c.asflip_beta;
  s.solver.xpic_order = c.xpic_order;
  s.solver.kernel = c.kernel;
  s.solver.polypic_modes = c.polypic_modes;
  s.solver.integrator = Integrator::symplectic;
  MaterialDesc m;
  m.name = "elastic";
  m.model = dim == 2 ? MaterialModel::neo_hookean : MaterialModel::fixed_corotated;
  // Linear weights have ∇w ≠ 0 where w → 0, so a node with a sliver of mass gets the full
  // stress force: explicit steps at E = 1000 blow up in a few steps. A softer block keeps
  // every kernel stable over the 20 steps (a blow-up would turn round-off into O(1)).
  m.E = c.kernel == KernelType::linear ? 10 : 1000;
  m.nu = 0.3;
  m.rho = 1;
  s.materials.push_back(m);
  return s;
}

// A block on a jittered lattice (spacing Δx/2, so no particle sits on a cell face), rotating
// and translating into the lower walls, or straddling the periodic x boundary; F slightly
// deformed so that stresses act from the first step.
template <int D>
void place_block(MpmSimulation<double, D>& sim, const Case& c) {
  std::mt19937_64 rng(7 + D);
  std::uniform_real_distribution<double> jitter(-0.25, 0.25), small(-0.04, 0.04);
  const double h = kDx / 2;
  Vec<double, D> lo, hi, v0;
  for (int a = 0; a < D; ++a) {
    lo[a] = c.periodic && a == 0 ? -0.13 : 0.02 + 0.01 * a;
    hi[a] = lo[a] + (D == 2 ? 0.45 : 0.24);
    v0[a] = -1.5 + 0.5 * a;
  }
  const Vec<double, D> center = 0.5 * (lo + hi);
  const Vec3d w = {1.0, 2.0, 4.0};  // angular velocity; 2D uses z
  std::array<int, D> count;
  std::size_t n = 1;
  for (int a = 0; a < D; ++a) n *= std::size_t(count[a] = int((hi[a] - lo[a]) / h));
  auto& p = MpmProbe(sim).particles();
  p.resize(n);
  for (std::size_t q = 0; q < n; ++q) {
    Vec<double, D> x;
    std::size_t k = q;
    for (int a = 0; a < D; ++a) {
      x[a] = lo[a] + h * (double(k % std::size_t(count[a])) + 0.5 + jitter(rng));
      k /= std::size_t(count[a]);
    }
    const Vec<double, D> r = x - center;
    Mat<double, D> W;  // ω*
    if constexpr (D == 2)
      W << 0, -w[2], w[2], 0;
    else
      W << 0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0;
    if (c.periodic && x[0] < 0) x[0] += 1;
    p.x[q] = x;
    p.v[q] = v0 + W * r;
    Mat<double, D> A;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) A(i, j) = small(rng);
    p.C[q].setZero();
    if (is_affine(c.scheme)) p.C[q] = W + 10 * A;
    for (auto& mode : p.modes)  // PolyPIC's higher modes: velocities of the size of v
      for (int a = 0; a < D; ++a) mode[q][a] = 10 * small(rng);
    if (c.scheme == Scheme::rpic) p.C[q] = W;
    p.F[q] = Mat<double, D>::Identity() + A;
    p.volume0[q] = std::pow(h, D);
    p.mass[q] = p.volume0[q] * sim.scene().materials[0].rho;
    p.material[q] = 0;
    p.object[q] = 0;
    p.id[q] = std::int32_t(q);
  }
}

// The larger of a and b, NaN if either is (std::max would drop a NaN b).
double worse(double a, double b) { return std::isnan(b) || b > a ? b : a; }

// Largest differences after kSteps, relative to each quantity's scale (F is O(1)).
struct Differences {
  double x = 0, v = 0, C = 0, F = 0, modes = 0;  // modes: PolyPIC's, relative to their max
  void max_with(const Differences& o) {
    x = worse(x, o.x), v = worse(v, o.v), C = worse(C, o.C), F = worse(F, o.F);
    modes = worse(modes, o.modes);
  }
};

template <int D>
Differences run_both(const Case& c) {
  const SceneDesc scene = scene_for(D, c);
  MpmSimulation<double, D> sim(scene);
  place_block<D>(sim, c);
  const auto& p = MpmProbe(sim).particles();
  reference::ParticleState<double, D> ref = reference::state_of(p);
  const reference::Setup<double, D> setup = reference::setup_of<double, D>(scene);
  for (int k = 0; k < kSteps; ++k) {
    sim.step_fixed(kDt);
    reference::step<double, D>(setup, ref, kDt);
    for (const Vec<double, D>& x : ref.x)
      if (!x.allFinite()) {  // the scene blew up: nothing left to compare (and no grid index)
        ADD_FAILURE() << "the reference state became non-finite at step " << k + 1;
        const double nan = std::nan("");
        return {nan, nan, nan, nan, nan};
      }
  }
  // The solver sorts its particles; match them by id. Positions on a periodic axis are compared
  // as the shortest distance around the domain.
  double vscale = 0, Cscale = 0, mscale = 0;
  for (std::size_t q = 0; q < ref.x.size(); ++q) {
    vscale = std::max(vscale, ref.v[q].norm());
    Cscale = std::max(Cscale, ref.C[q].norm());
    for (const auto& m : ref.modes) mscale = std::max(mscale, m[q].norm());
  }
  Differences d;
  for (std::size_t q = 0; q < p.size(); ++q) {
    const std::size_t id = std::size_t(p.id[q]);
    Vec<double, D> dx = p.x[q] - ref.x[id];
    for (int a = 0; a < D; ++a)
      if (c.periodic) dx[a] -= std::round(dx[a]);
    d.x = worse(d.x, dx.norm());
    d.v = worse(d.v, (p.v[q] - ref.v[id]).norm() / vscale);
    d.C =
        worse(d.C, Cscale > 0 ? (p.C[q] - ref.C[id]).norm() / Cscale : (p.C[q] - ref.C[id]).norm());
    d.F = worse(d.F, (p.F[q] - ref.F[id]).norm());
    for (std::size_t j = 0; j < p.modes.size(); ++j)
      d.modes = worse(d.modes, (p.modes[j][q] - ref.modes[j][id]).norm() / mscale);
  }
  if (p.modes.size() != ref.modes.size()) d.modes = std::nan("");
  return d;
}

// Both steps add the same O(1) terms in different orders (the solver by 8-lane rows and
// coloured blocks, the reference node by node; C = B/(kΔx²) against B D_p⁻¹ with D_p summed;
// x_p + Δt Σ w ṽ_i against Σ w x̃_i). One step differs by a few ulps per quantity (measured
// ≤ 4e-14 for C, ≤ 8e-16 for x, v and F), and 20 steps of elastic response carry and grow
// that: measured ≤ 1.1e-13 for quadratic and cubic, so 1e-12 (a factor 9 of room). Linear
// weights are worse conditioned: ∇w stays finite where w → 0, so a node holding a sliver of
// mass gets a large ṽ = v + Δt f/m whose round-off reaches F and C through Σ ṽ ∇wᵀ; measured
// ≤ 8.3e-12 (3D APIC) with GCC -march=native; the ASan build (clang -O1, x86-64 without FMA,
// so other roundings) gave 1.4e-10 for F (2D periodic APIC and TPIC): so 1e-9. ASFLIP
// (α = 0.95, β = 1) with linear weights: measured 1.05e-10 for C (2D periodic), since its FLIP
// term carries a sliver node's round-off into v_p from step to step and its position correction
// moves x_p by it, where APIC resets v_p to Σ w ṽ. A wrong sign anywhere in the step gives 1e-4
// or more, five orders above 1e-9.
double round_off_bound(KernelType kernel) { return kernel == KernelType::linear ? 1e-9 : 1e-12; }

template <int D>
void compare_all() {
  // PolyPIC with every mode, and with 6 (2D: 1, x, y, xy, Gx, Gy; 3D: up to xz).
  // And every registered scheme not listed here, with its defaults.
  std::vector<Case> cases = {{Scheme::pic, 1.0},
                             {Scheme::flip, 1.0},
                             {Scheme::flip, 0.95},
                             {Scheme::apic, 1.0},
                             {Scheme::rpic, 1.0},
                             {Scheme::mls, 1.0},
                             {Scheme::asflip, 0.95, KernelType::quadratic, false, 1.0},
                             {Scheme::asflip, 1.0, KernelType::quadratic, false, 0.0},
                             {Scheme::xpic, 1.0, KernelType::quadratic, false, 0.0, 3},
                             {Scheme::tpic, 1.0},
                             {Scheme::polypic, 1.0},
                             {Scheme::polypic, 1.0, KernelType::quadratic, false, 0.0, 1, 6}};
  for (const auto& registered : scheme_choices())
    if (std::none_of(cases.begin(), cases.end(),
                     [&](const Case& c) { return c.scheme == registered.value; }))
      cases.push_back({registered.value, 1.0});
  for (KernelType kernel : {KernelType::linear, KernelType::quadratic, KernelType::cubic}) {
    Differences worst;
    for (bool periodic : {false, true})
      for (Case c : cases) {
        if (c.scheme == Scheme::mls && kernel == KernelType::linear) continue;  // refused (D_p)
        if (c.scheme == Scheme::polypic && kernel != KernelType::quadratic) continue;  // refused
        c.kernel = kernel;
        c.periodic = periodic;
        SCOPED_TRACE(c.name() + " " + std::to_string(D) + "D");
        const Differences d = run_both<D>(c);
        worst.max_with(d);
        const double bound = round_off_bound(kernel);
        EXPECT_LE(d.x, bound) << "position";
        EXPECT_LE(d.v, bound) << "velocity (relative to max |v|)";
        EXPECT_LE(d.C, bound) << "affine matrix C (relative to max |C|)";
        EXPECT_LE(d.F, bound) << "deformation gradient";
        // PolyPIC's higher modes are up to third differences of ṽ across the stencil (Σ w ṽ G_x G_y
        // G_z, G = 8 (w₁w₂, −2w₀w₂, w₀w₁)): they carry the two steps' ṽ round-off (|dv|/|v| ≤
        // 2e-14) amplified up to 4³ = 64-fold. Measured ≤ 1.1e-11 (3D, walls), so 1e-10; a wrong
        // basis or projection gives O(1).
        EXPECT_LE(d.modes, 1e-10) << "PolyPIC's higher modes (relative to their largest)";
      }
    std::printf(
        "[ reference ] %dD %-9s %d steps: max |dx| %.1e, |dv|/|v| %.1e, |dC|/|C| %.1e, |dF| %.1e, "
        "PolyPIC modes %.1e\n",
        D, std::string(key_of(kernel)).c_str(), kSteps, worst.x, worst.v, worst.C, worst.F,
        worst.modes);
  }
}

TEST(ReferenceStep, OptimisedStepMatches2D) { compare_all<2>(); }
TEST(ReferenceStep, OptimisedStepMatches3D) { compare_all<3>(); }

// The comparison is only worth something if the scene exercises the step: over the 20 steps
// the walls, the collider plane and the stress must each change the motion. Checked on the
// reference step (which the solver matches) by leaving each out in turn.
TEST(ReferenceStep, WallsColliderAndStressChangeTheMotion) {
  const Case c{Scheme::apic, 1.0, KernelType::quadratic, false};
  MpmSimulation<double, 2> sim(scene_for(2, c));
  place_block<2>(sim, c);
  const auto& p = MpmProbe(sim).particles();
  auto final_velocities = [&](const reference::Setup<double, 2>& setup) {
    reference::ParticleState<double, 2> s = reference::state_of(p);
    for (int k = 0; k < kSteps; ++k) reference::step<double, 2>(setup, s, kDt);
    return s.v;
  };
  auto largest_change = [&](const std::vector<Vec<double, 2>>& a,
                            const std::vector<Vec<double, 2>>& b) {
    double d = 0;
    for (std::size_t q = 0; q < a.size(); ++q) d = std::max(d, (a[q] - b[q]).norm());
    return d;
  };
  const reference::Setup<double, 2> full = reference::setup_of<double, 2>(scene_for(2, c));
  reference::Setup<double, 2> no_walls = full, no_collider = full, no_stress = full;
  no_walls.walls.fill(BoundaryCondition::periodic);  // the block stays clear of the wrap
  no_walls.colliders.clear();
  no_collider.colliders.clear();
  no_stress.lame = {0, 0};
  const auto v = final_velocities(full);
  const double walls = largest_change(v, final_velocities(no_walls));
  const double collider = largest_change(v, final_velocities(no_collider));
  const double stress = largest_change(v, final_velocities(no_stress));
  std::printf(
      "[ reference ] largest |Δv| without walls %.3g, without collider %.3g, without stress %.3g\n",
      walls, collider, stress);
  EXPECT_GT(walls, 0.1);
  EXPECT_GT(collider, 1e-3);
  EXPECT_GT(stress, 0.1);
}

}  // namespace
}  // namespace apiclab
