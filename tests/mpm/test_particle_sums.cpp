// The diagnostics row's particle sums that G2P takes for a step asked for its row
// (step_fixed_measured, step; sim/mpm/particle_sums.hpp) against measure()'s own pass over the same
// particles (particle_sums, the readable oracle), for 2D and 3D, float and double, several
// schemes and kernels, on one and two threads. Also: taking the sums leaves the step unchanged.
// And the conservation ledger, whose sums G2P takes beside them (sim/mpm/stage_ledger.hpp).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "sim/mpm/particle_sums.hpp"
#include "sim/mpm/probe.hpp"
#include "sim/scene/scene.hpp"
#include "tests/shipped_scenes.hpp"

namespace apiclab {
namespace {

// The bench's block, small: fixed-corotated, spinning about z and falling, so that v, C (the
// rotation's skew part and the elastic waves) and x × v are all far from zero.
// cells_per_m: 32 (2D) and 16 (3D) unless given.
nlohmann::json spinning_block_json(int dim, const std::string& scheme, const std::string& kernel,
                                   double cells_per_m = 0) {
  using json = nlohmann::json;
  const bool d2 = dim == 2;
  const double dx = 1 / (cells_per_m > 0 ? cells_per_m : d2 ? 32.0 : 16.0);
  const json scene = {
      {"name", "spinning-block"},
      {"dim", dim},
      {"domain",
       {{"min", d2 ? json{0, 0} : json{0, 0, 0}},
        {"max", d2 ? json{1, 1} : json{1, 1, 1}},
        {"dx", dx},
        {"boundary", "sticky"}}},
      {"gravity", d2 ? json{0, -9.8} : json{0, -9.8, 0}},
      {"solver", {{"scheme", scheme}, {"kernel", kernel}}},
      {"materials", json::array({{{"name", "jelly"},
                                  {"model", "fixed-corotated"},
                                  {"E", 10000},
                                  {"nu", 0.3},
                                  {"rho", 1000}}})},
      {"objects", json::array({{{"shape",
                                 {{"type", "box"},
                                  {"min", d2 ? json{0.3, 0.35} : json{0.3, 0.35, 0.3}},
                                  {"max", d2 ? json{0.7, 0.65} : json{0.6, 0.65, 0.55}}}},
                                {"material", 0},
                                {"velocity", d2 ? json{0.3, 0.1} : json{0.3, 0.1, -0.2}},
                                {"angular_velocity", d2 ? json(2.0) : json{0.5, -1.0, 2.0}}}})},
  };
  return scene;
}

SceneDesc spinning_block(int dim, const std::string& scheme, const std::string& kernel,
                         double cells_per_m = 0) {
  SceneDesc s =
      parse_scene_text(spinning_block_json(dim, scheme, kernel, cells_per_m).dump(), "test");
  s.solver.parallel_min_particles = 0;  // the threaded G2P even for this small block
  return s;
}

// Σ_p of the absolute values of each particle's terms in the sums, the scale of their
// round-off: kinetic (non-negative terms: the sum itself), momentum Σ m |v|₁, angular momentum
// Σ m (|x| |v| + 2Δx² ‖C‖) (D_p ≤ Δx²/3 I for every kernel), gravity Σ m |g| |x|.
template <class T, int D>
ParticleSums term_scales(const MpmSimulation<T, D>& sim, const ParticleSums& oracle) {
  const auto& p = MpmProbe(sim).particles();
  const double dx = sim.scene().domain.dx, g = 9.8;
  ParticleSums s;
  s.kinetic = oracle.kinetic;
  for (std::size_t q = 0; q < p.size(); ++q) {
    const double m = double(p.mass[q]), v = double(p.v[q].norm()), x = double(p.x[q].norm());
    s.gravity += m * g * x;
    for (int a = 0; a < 3; ++a) {
      s.p[a] += m * v;
      s.L[a] += m * (x * v + 2 * dx * dx * double(p.C[q].norm()));
    }
  }
  return s;
}

double worst_ratio = 0;  // the largest difference seen, in units of ε_T Σ_p |term_p|

// ChunkTerms adds two vectors of particles' float terms in float before converting them to double:
// one rounding more a term in float.
template <class T>
constexpr int float_pair_add = sizeof(T) == 4 ? 1 : 0;

// The fused sums differ from the oracle's in each particle's terms, which both evaluate in T
// (sim/mpm/particle_sums.hpp, mpm_measure.hpp), and in the order of the double sums. Per term, the
// largest count of roundings in T (each ε_T of the term, all terms of the kinetic energy being
// positive): the fused kinetic energy ½ m (|v|² + k |C|²) takes D + D² + 3 (|v|² and |C|² with
// FMA, k |C|², the add, m), the oracle's ½ m |v|² + ½ m tr(C D Cᵀ) 2D + 2 (|v|², C D, the trace);
// the angular momenta and gravity fewer; in float the fused sums add two particles' terms in float
// before their conversion, one more. So (D² + 3D + 6) ε_T Σ_p |term_p| in float (16 in 2D, 24 in
// 3D), (D² + 3D + 5) in double.
// The double sums (G2P: chunks of 256 particles, the chunks' sums added in order; the oracle: each
// thread's share, the threads' sums added) are each within n ε_64 Σ_p |term_p| of the exact sum
// (recursive summation, Higham 2002, eq 4.4).
template <class T, int D>
void expect_fused_equals_oracle(const std::string& scheme, const std::string& kernel, int threads) {
  SCOPED_TRACE(std::to_string(D) + "D " + (sizeof(T) == 4 ? "float " : "double ") + scheme + " " +
               kernel + ", " + std::to_string(threads) + " thread(s)");
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(threads);
  MpmSimulation<T, D> fused(spinning_block(D, scheme, kernel));
  MpmSimulation<T, D> plain = fused;
  const double dt = 2e-4;
  const double bound =
      (D * D + 3 * D + 5 + float_pair_add<T>)*double(std::numeric_limits<T>::epsilon()) +
      2 * double(MpmProbe(fused).particles().size()) * std::numeric_limits<double>::epsilon();
  const int steps = threads == 1 ? 4 : 2;  // two threads: see all_schemes
  for (int step = 1; step <= steps; ++step) {
    const DiagnosticsRow row = fused.step_fixed_measured(dt);
    plain.step_fixed(dt);
    const ParticleSums oracle = MpmProbe(fused).particle_sums();
    const ParticleSums scale = term_scales(fused, oracle);
    ASSERT_GT(oracle.kinetic, 0);
    const double eps = double(std::numeric_limits<T>::epsilon());
    auto track = [&](double fused_value, double oracle_value, double term_scale) {
      worst_ratio =
          std::max(worst_ratio, std::abs(fused_value - oracle_value) / (eps * term_scale));
    };
    track(row.kinetic, oracle.kinetic, scale.kinetic);
    for (int a = 0; a < 3; ++a) {
      track(row.p[a], oracle.p[a], scale.p[a]);
      track(row.L[a], oracle.L[a], scale.L[a]);
    }
    EXPECT_NEAR(row.kinetic, oracle.kinetic, bound * scale.kinetic) << "step " << step;
    EXPECT_NEAR(row.potential - row.elastic, oracle.gravity, bound * scale.gravity)
        << "step " << step;
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(row.p[a], oracle.p[a], bound * scale.p[a]) << "step " << step << " p" << a;
      EXPECT_NEAR(row.L[a], oracle.L[a], bound * scale.L[a]) << "step " << step << " L" << a;
    }
    // The rest of the row is measure()'s.
    const DiagnosticsRow measured = fused.measure();
    EXPECT_EQ(row.step, measured.step);
    EXPECT_EQ(row.elastic, measured.elastic);
    EXPECT_EQ(row.kinetic_grid, measured.kinetic_grid);
    // Taking the sums does not change the step: the same particles, bit for bit.
    const auto &a = MpmProbe(fused).particles(), &b = MpmProbe(plain).particles();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t q = 0; q < a.size(); ++q) {
      ASSERT_EQ(a.x[q], b.x[q]) << "particle " << q << " step " << step;
      ASSERT_EQ(a.v[q], b.v[q]) << "particle " << q << " step " << step;
      ASSERT_EQ(a.C[q], b.C[q]) << "particle " << q << " step " << step;
      ASSERT_EQ(a.F[q], b.F[q]) << "particle " << q << " step " << step;
    }
  }
  omp_set_num_threads(threads_before);
}

// Every scheme and kernel on one thread; on two (the threads' slots added in order) five
// schemes, fewer because two threads on a loaded machine wait at every barrier.
template <class T, int D>
void all_schemes() {
  for (const char* scheme :
       {"apic", "pic", "flip", "polypic", "mls", "rpic", "tpic", "asflip", "xpic"})
    expect_fused_equals_oracle<T, D>(scheme, "quadratic", 1);
  expect_fused_equals_oracle<T, D>("apic", "cubic", 1);
  expect_fused_equals_oracle<T, D>("apic", "linear", 1);  // D_p from the stencil at x
  for (const char* scheme : {"apic", "pic", "flip", "polypic", "mls"})
    expect_fused_equals_oracle<T, D>(scheme, "quadratic", 2);
  std::printf(
      "worst |fused - oracle| / (eps_T sum |terms|): %.3g (bound D^2 + 3D + 5 (+1 in float) + "
      "2 n eps_64/eps_T)\n",
      worst_ratio);
  worst_ratio = 0;
}

TEST(ParticleSums, FusedEqualsOracle2DFloat) { all_schemes<float, 2>(); }
TEST(ParticleSums, FusedEqualsOracle2DDouble) { all_schemes<double, 2>(); }
TEST(ParticleSums, FusedEqualsOracle3DFloat) { all_schemes<float, 3>(); }
TEST(ParticleSums, FusedEqualsOracle3DDouble) { all_schemes<double, 3>(); }

// ChunkTerms on its own: any count of particles (partial vectors, a partial last chunk), C read
// from its array or per-particle terms, against the sums written out per particle in double from
// the same T inputs. ChunkTerms forms each particle's terms in T (as measure() does), with at most
// D² + D + 4 roundings of ε_T each (the kinetic energy: |v|², |C|², k |C|², their add, m, the
// extra terms' add; the others fewer), in float one more (two vectors' terms added before their
// conversion), then adds them in double: within (D² + D + 4 (+1)) ε_T Σ_p |term_p|
// + 8 n ε_64 Σ_p |term_p| (Higham 2002, eq 4.4).
template <class T, int D>
void chunk_sums_like_the_formula(int count, bool isotropic) {
  SCOPED_TRACE(std::to_string(D) + "D " + (sizeof(T) == 4 ? "float" : "double") + ", " +
               std::to_string(count) + (isotropic ? " particles, C columns" : " particles, terms"));
  constexpr int N = 256;
  auto terms = std::make_unique<ChunkTerms<T, D, N>>();
  std::mt19937 rng(count * 7 + D);
  std::uniform_real_distribution<double> u(-1, 1);
  // Exactly count of each: sum() must not read past them.
  std::vector<T> mass(static_cast<std::size_t>(count));
  std::vector<Vec<T, D>> xs(static_cast<std::size_t>(count)), vs(xs);
  std::vector<Mat<T, D>> Cs(static_cast<std::size_t>(count));
  const std::array<double, 3> g{0.3, -9.8, 1.1};
  const T k = T(1.0 / 3000);
  terms->isotropic_k = isotropic ? k : T(0);
  terms->extras = !isotropic;
  ParticleSums expect, scale;
  for (int j = 0; j < count; ++j) {
    mass[std::size_t(j)] = T(1 + 0.5 * u(rng));
    const double m = double(mass[std::size_t(j)]);
    Vec<T, D> x, v;
    Mat<T, D> C;
    for (int a = 0; a < D; ++a) {
      x[a] = T(u(rng));
      v[a] = T(3 * u(rng));
      for (int b = 0; b < D; ++b) C(a, b) = T(20 * u(rng));
    }
    xs[std::size_t(j)] = x;
    vs[std::size_t(j)] = v;
    Cs[std::size_t(j)] = C;
    double extra_kinetic = 0;
    Eigen::Vector3d extra_moment = Eigen::Vector3d::Zero();
    if (isotropic) {
      extra_kinetic = 0.5 * m * double(k) * C.template cast<double>().squaredNorm();
      extra_moment =
          m * double(k) * permutation_contract<double, D>(C.template cast<double>().transpose());
    } else {
      terms->extra_kinetic[j] = T(u(rng) + 1);
      extra_kinetic = double(terms->extra_kinetic[j]);
      for (int a = 0; a < terms->moments; ++a) {
        terms->affine_moment[a][j] = T(u(rng));
        extra_moment[D == 2 ? 2 : a] = double(terms->affine_moment[a][j]);
      }
    }
    const Vec<double, D> xd = x.template cast<double>(), vd = v.template cast<double>();
    const double kinetic = 0.5 * m * vd.squaredNorm() + extra_kinetic;
    expect.kinetic += kinetic;
    scale.kinetic += kinetic;
    const Eigen::Vector3d L = cross_moment<double, D>(xd, Vec<double, D>(m * vd)) + extra_moment;
    for (int a = 0; a < D; ++a) {
      expect.gravity -= m * g[std::size_t(a)] * xd[a];
      scale.gravity += std::abs(m * g[std::size_t(a)] * xd[a]);
      expect.p[std::size_t(a)] += m * vd[a];
      scale.p[std::size_t(a)] += std::abs(m * vd[a]);
    }
    for (int a = 0; a < 3; ++a) {
      expect.L[std::size_t(a)] += L[a];
      scale.L[std::size_t(a)] += m * xd.norm() * vd.norm() + std::abs(extra_moment[a]);
    }
  }
  const ParticleSums got = terms->sum(mass.data(), xs.data(), vs.data(), Cs.data(), count, g);
  const double tol = (D * D + D + 4 + float_pair_add<T>)*double(std::numeric_limits<T>::epsilon()) +
                     8 * std::max(count, 1) * std::numeric_limits<double>::epsilon();
  EXPECT_NEAR(got.kinetic, expect.kinetic, tol * scale.kinetic);
  EXPECT_NEAR(got.gravity, expect.gravity, tol * scale.gravity);
  for (std::size_t a = 0; a < 3; ++a) {
    EXPECT_NEAR(got.p[a], expect.p[a], tol * scale.p[a]) << "p" << a;
    EXPECT_NEAR(got.L[a], expect.L[a], tol * scale.L[a]) << "L" << a;
  }
  if (D == 2) {
    EXPECT_EQ(got.L[0], 0.0);
  }
  if (count > 0) {
    EXPECT_GT(got.kinetic, 0.0);
  }
}

TEST(ChunkTerms, SumsAnyCountLikeTheFormula) {
  for (int count : {0, 1, 3, 4, 5, 9, 15, 16, 17, 255, 256})
    for (bool isotropic : {true, false}) {
      chunk_sums_like_the_formula<float, 2>(count, isotropic);
      chunk_sums_like_the_formula<double, 2>(count, isotropic);
      chunk_sums_like_the_formula<float, 3>(count, isotropic);
      chunk_sums_like_the_formula<double, 3>(count, isotropic);
    }
}

// G2P's sums go in fixed chunks of particles, added in chunk order: the row is the same, bit for
// bit, on one thread and on two (the step itself does not depend on the thread count).
template <class T, int D>
void same_on_one_and_two_threads(const std::string& scheme) {
  SCOPED_TRACE(std::to_string(D) + "D " + (sizeof(T) == 4 ? "float " : "double ") + scheme);
  const int threads_before = omp_get_max_threads();
  // Finer than the other tests' block: three chunks of 1024 particles or more (sim/mpm/g2p.hpp).
  MpmSimulation<T, D> one(spinning_block(D, scheme, "quadratic", D == 2 ? 80 : 32));
  MpmSimulation<T, D> two = one;
  ASSERT_GT(MpmProbe(one).particles().size(), 2048u);
  for (int step = 1; step <= 2; ++step) {
    omp_set_num_threads(1);
    const DiagnosticsRow a = one.step_fixed_measured(2e-4);
    omp_set_num_threads(2);
    const DiagnosticsRow b = two.step_fixed_measured(2e-4);
    EXPECT_EQ(a.kinetic, b.kinetic) << "step " << step;
    EXPECT_EQ(a.potential, b.potential) << "step " << step;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(a.p[k], b.p[k]) << "step " << step;
      EXPECT_EQ(a.L[k], b.L[k]) << "step " << step;
    }
  }
  omp_set_num_threads(threads_before);
}

TEST(ParticleSums, RowIndependentOfThreadCount) {
  same_on_one_and_two_threads<float, 2>("apic");
  same_on_one_and_two_threads<double, 3>("polypic");
}

// step() takes its row from G2P's sums too: its row equals measure() of the state it leaves.
TEST(ParticleSums, StepRowIsMeasureOfTheNewState) {
  MpmSimulation<double, 3> sim(spinning_block(3, "apic", "quadratic"));
  for (int k = 0; k < 3; ++k) {
    DiagnosticsRow row;
    ASSERT_FALSE(sim.step(1.0, &row).has_value());
    const DiagnosticsRow measured = sim.measure();
    EXPECT_EQ(row.t, measured.t);
    EXPECT_NEAR(row.kinetic, measured.kinetic, 1e-13 * measured.kinetic);
    EXPECT_NEAR(row.total, measured.total, 1e-13 * std::abs(measured.kinetic));
    EXPECT_NEAR(row.L[2], measured.L[2], 1e-13 * std::abs(measured.L[2]));
  }
}

// The conservation ledger (solver.ledger, sim/mpm/stage_ledger.hpp): the block of spinning_block
// dropped against the sticky floor and a slip collider plane at x = 0.25, so that every stage
// acts. Its stages add up to the step's change of the row, each to the round-off of the sums it
// takes one state from the next with.
template <class T, int D>
MpmSimulation<T, D> ledger_block(const std::string& scheme, const std::string& kernel,
                                 const std::string& integrator = "symplectic") {
  using json = nlohmann::json;
  json scene = spinning_block_json(D, scheme, kernel);
  scene["solver"]["ledger"] = true;
  scene["solver"]["integrator"] = integrator;
  json& box = scene["objects"][0]["shape"];
  box["min"][0] = 0.26;
  box["min"][1] = 0.02;
  box["max"][1] = 0.3;
  scene["colliders"] = json::array({{{"type", "plane"},
                                     {"point", D == 2 ? json{0.25, 0} : json{0.25, 0, 0}},
                                     {"normal", D == 2 ? json{1, 0} : json{1, 0, 0}},
                                     {"condition", "slip"}}});
  SceneDesc s = parse_scene_text(scene.dump(), "test");
  s.solver.parallel_min_particles = 0;
  return MpmSimulation<T, D>(s);
}

// Σ |stage| of each quantity, the scale of the stages' round-off.
struct LedgerScale {
  double p = 0, L = 0, E = 0;
};

LedgerScale ledger_scale(const DiagnosticsRow& before, const DiagnosticsRow& after) {
  LedgerScale s;
  for (const ConservedSums& c : after.stages) {
    s.E += std::abs(c.energy);
    for (int a = 0; a < 3; ++a) {
      s.p += std::abs(c.p[a]);
      s.L += std::abs(c.L[a]);
    }
  }
  s.E += std::abs(before.total) + std::abs(after.kinetic) + std::abs(after.potential);
  for (int a = 0; a < 3; ++a) {
    s.p += std::abs(before.p[a]);
    s.L += std::abs(before.L[a]);
  }
  return s;
}

template <int D>
void expect_stages_add_up(const std::string& scheme, const std::string& kernel,
                          const std::string& integrator = "symplectic") {
  SCOPED_TRACE(std::to_string(D) + "D " + scheme + " " + kernel + " " + integrator);
  MpmSimulation<double, D> sim = ledger_block<double, D>(scheme, kernel, integrator);
  DiagnosticsRow before = sim.measure();
  ASSERT_TRUE(before.ledger);
  ConservedSums acted;  // |change| of the walls and colliders over the steps
  for (int step = 1; step <= 4; ++step) {
    const DiagnosticsRow row = sim.step_fixed_measured(2e-4);
    ASSERT_TRUE(row.ledger);
    ConservedSums sum;
    for (const ConservedSums& c : row.stages) sum += c;
    const LedgerScale scale = ledger_scale(before, row);
    const double eps = 1e-13;  // a few ε_64 of the sums, taken in different orders
    EXPECT_NEAR(sum.mass, 0, eps * sim.total_mass()) << "step " << step;
    EXPECT_NEAR(sum.energy, row.total - before.total, eps * scale.E) << "step " << step;
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(sum.p[a], row.p[a] - before.p[a], eps * scale.p) << "step " << step;
      EXPECT_NEAR(sum.L[a], row.L[a] - before.L[a], eps * scale.L) << "step " << step;
    }
    // Linear momentum through P2G for every scheme (Jiang et al. 2017, Sec 5.1.1, 5.2), and
    // through G2P for the schemes of the paper (Sec 5.1.3; FLIP's Σ m_p Δv_p = Σ m_i Δv_i).
    const ConservedSums& p2g = row.stages[std::size_t(LedgerStage::p2g)];
    const ConservedSums& g2p = row.stages[std::size_t(LedgerStage::g2p)];
    for (int a = 0; a < D; ++a) {
      EXPECT_NEAR(p2g.p[a], 0, eps * scale.p) << "step " << step;
      if (scheme == "pic" || scheme == "flip" || scheme == "apic" || scheme == "rpic") {
        EXPECT_NEAR(g2p.p[a], 0, eps * scale.p) << "step " << step;
      }
    }
    for (LedgerStage st : {LedgerStage::walls, LedgerStage::colliders}) {
      acted.p[std::size_t(st == LedgerStage::walls)] += std::abs(row.stages[std::size_t(st)].p[1]);
      acted.p[2] += std::abs(row.stages[std::size_t(st)].p[0]);
    }
    before = row;
  }
  EXPECT_GT(acted.p[1], 0) << "the floor never acted";
  EXPECT_GT(acted.p[2], 0) << "the walls and colliders never acted";
}

TEST(StageLedger, StagesAddUpToTheStep2D) {
  for (const char* scheme :
       {"apic", "pic", "flip", "rpic", "polypic", "mls", "tpic", "asflip", "xpic"})
    expect_stages_add_up<2>(scheme, "quadratic");
  expect_stages_add_up<2>("apic", "linear");  // D_p from the stencil at x
  expect_stages_add_up<2>("apic", "cubic");
  expect_stages_add_up<2>("apic", "quadratic", "midpoint");
}

TEST(StageLedger, StagesAddUpToTheStep3D) {
  expect_stages_add_up<3>("apic", "quadratic");
  expect_stages_add_up<3>("flip", "quadratic");
}

// With the ledger on, the step is the same, bit for bit.
TEST(StageLedger, LeavesTheStepUnchanged) {
  MpmSimulation<float, 2> on = ledger_block<float, 2>("apic", "quadratic");
  SceneDesc plain = on.scene();
  plain.solver.ledger = false;
  MpmSimulation<float, 2> off(plain);
  for (int step = 0; step < 3; ++step) {
    on.step_fixed_measured(2e-4);
    off.step_fixed_measured(2e-4);
  }
  const auto &a = MpmProbe(on).particles(), &b = MpmProbe(off).particles();
  ASSERT_GT(a.size(), 100u);
  for (std::size_t q = 0; q < a.size(); ++q) {
    ASSERT_EQ(a.x[q], b.x[q]) << "particle " << q;
    ASSERT_EQ(a.v[q], b.v[q]) << "particle " << q;
    ASSERT_EQ(a.C[q], b.C[q]) << "particle " << q;
  }
}

// The step's start is the last row unless the state was written since: after v and C are
// written between steps (as the Python module does) or the scheme switched, P2G still keeps
// the momentum of the state it transfers (a start taken from the old row would book the write
// on P2G). And a start taken from the row equals the start summed again, to round-off.
TEST(StageLedger, StartIsTheWrittenState) {
  MpmSimulation<double, 2> sim = ledger_block<double, 2>("apic", "quadratic");
  for (int step = 0; step < 2; ++step) sim.step_fixed_measured(2e-4);
  auto& p = MpmProbe(sim).particles();
  for (std::size_t q = 0; q < p.size(); ++q) {
    p.v[q] += Vec<double, 2>(0.5, -0.25);
    p.C[q] *= 2.0;
  }
  const DiagnosticsRow written = sim.measure();
  DiagnosticsRow row = sim.step_fixed_measured(2e-4);
  const LedgerScale scale = ledger_scale(written, row);
  for (int a = 0; a < 2; ++a)
    EXPECT_NEAR(row.stages[std::size_t(LedgerStage::p2g)].p[a], 0, 1e-13 * scale.p);
  sim.set_scheme(Scheme::pic, 0);  // C dropped: the kinetic energy and L lose its share
  const DiagnosticsRow switched = sim.measure();
  row = sim.step_fixed_measured(2e-4);
  ConservedSums sum;
  for (const ConservedSums& c : row.stages) sum += c;
  EXPECT_NEAR(sum.energy, row.total - switched.total, 1e-13 * ledger_scale(switched, row).E);
  EXPECT_NEAR(sum.L[2], row.L[2] - switched.L[2], 1e-13 * ledger_scale(switched, row).L);
}

TEST(StageLedger, StartFromTheRowEqualsTheSummedStart) {
  MpmSimulation<double, 2> kept = ledger_block<double, 2>("apic", "linear");
  MpmSimulation<double, 2> summed = ledger_block<double, 2>("apic", "linear");
  for (int step = 1; step <= 4; ++step) {
    MpmProbe(summed).particles();  // writable access: the start is summed again
    const DiagnosticsRow a = kept.step_fixed_measured(2e-4), b = summed.step_fixed_measured(2e-4);
    const LedgerScale scale = ledger_scale(a, a);
    for (int s = 0; s < ledger_stage_count; ++s) {
      const ConservedSums &x = a.stages[std::size_t(s)], &y = b.stages[std::size_t(s)];
      EXPECT_NEAR(x.energy, y.energy, 1e-13 * scale.E) << "step " << step << " stage " << s;
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(x.p[c], y.p[c], 1e-13 * scale.p) << "step " << step << " stage " << s;
        EXPECT_NEAR(x.L[c], y.L[c], 1e-13 * scale.L) << "step " << step << " stage " << s;
      }
    }
    EXPECT_EQ(std::memcmp(&a.total, &b.total, sizeof(double)), 0) << "step " << step;
  }
}

// Sec 5 as numbers on the rotating disk (Sec 6.1) under symplectic Euler, where the transfers
// are the paper's: APIC's and RPIC's P2G and G2P change L by round-off (Sec 5.3, 5.1.2, 5.1.4),
// PIC's P2G too but its G2P measurably (Sec 2.1: the local angular momentum l̂_p is lost).
// Largest |stage ΔL_z| / |L_z| over the steps.
std::array<double, ledger_stage_count> disk_dL(const std::string& scheme) {
  SceneDesc s = load_scene(apiclab::test::shipped_scene_path("rotating-disk"),
                           {"solver.scheme=" + scheme, "solver.integrator=symplectic",
                            "time.dt.rule=elastic", "solver.ledger=true"});
  auto sim = make_simulation(s);
  std::array<double, ledger_stage_count> worst{};
  for (int step = 0; step < 5; ++step) {
    DiagnosticsRow row;
    EXPECT_FALSE(sim->step(1.0, &row).has_value());
    for (int st = 0; st < ledger_stage_count; ++st)
      worst[std::size_t(st)] =
          std::max(worst[std::size_t(st)], std::abs(row.stages[std::size_t(st)].L[2] / row.L[2]));
  }
  return worst;
}

TEST(StageLedger, AngularMomentumOfTheTransfersOnTheRotatingDisk) {
  const auto p2g = std::size_t(LedgerStage::p2g), g2p = std::size_t(LedgerStage::g2p);
  for (const char* scheme : {"apic", "rpic"}) {
    const auto dL = disk_dL(scheme);
    std::printf("%s: largest |dL_z / L_z| of P2G %.1e, G2P %.1e\n", scheme, dL[p2g], dL[g2p]);
    EXPECT_LT(dL[p2g], 1e-12) << scheme;
    EXPECT_LT(dL[g2p], 1e-12) << scheme;
  }
  const auto pic = disk_dL("pic");
  std::printf("pic: largest |dL_z / L_z| of P2G %.1e, G2P %.1e\n", pic[p2g], pic[g2p]);
  EXPECT_LT(pic[p2g], 1e-12);
  EXPECT_GT(pic[g2p], 1e-6);
}

}  // namespace
}  // namespace apiclab
