// The Eulerian-on-Lagrangian pieces against their equations (Fan et al. 2013): the mass
// matrix's nullspace (eq 20), the least-squares split (eqs 23-24), internal forces (zero net
// force and torque, the gradient of the grid's elastic energy), affine-exact advection (eq 15),
// and bad input. Whole runs are in test_eol_runs.cpp.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <utility>

#include "sim/eol/grid/advection.hpp"
#include "sim/eol/least_squares_split.hpp"
#include "sim/scene/parameters.hpp"
#include "tests/eol/eol_test_scenes.hpp"

namespace apiclab {
namespace {

using namespace apiclab::eol;

template <int D>
Vec<double, D> random_vec(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Vec<double, D> v;
  for (int a = 0; a < D; ++a) v[a] = u(rng);
  return v;
}

template <int D>
Mat<double, D> random_rotation(std::mt19937_64& rng) {
  RigidFrame<double, D> f;
  std::uniform_real_distribution<double> u(-3, 3);
  if constexpr (D == 2) {
    f.angle = u(rng);
  } else {
    f.q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
  }
  return f.rotation();
}

// Eq 20: M₁ = M₁₂ M₂⁻¹ M₁₂ᵀ for rigid frames, with M₁ from the rigid-body formula (mass, first
// moment, inertia) and M₁₂, M₂ assembled node by node from eq 6's blocks.
template <int D>
void check_nullspace_identity() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mass(0.1, 2.0);
  const int n = 200;
  std::vector<double> m(n);
  std::vector<Vec<double, D>> r(n);
  constexpr int K = frame_dofs<D>;
  Eigen::MatrixXd M12(K, D * n), M2inv = Eigen::MatrixXd::Zero(D * n, D * n);
  for (int i = 0; i < n; ++i) {
    m[std::size_t(i)] = mass(rng);
    r[std::size_t(i)] = random_vec<D>(rng, 1.5);
    M12.middleCols(D * i, D) =
        m[std::size_t(i)] * rigid_jacobian<double, D>(r[std::size_t(i)]).transpose();
    M2inv.block(D * i, D * i, D, D) = Eigen::MatrixXd::Identity(D, D) / m[std::size_t(i)];
  }
  const Eigen::MatrixXd product = M12 * M2inv * M12.transpose();
  const FrameMatrix<D> M1 = rigid_mass_matrix<double, D>(m, r);
  const double err = (product - Eigen::MatrixXd(M1)).norm() / M1.norm();
  EXPECT_LT(err, 1e-14) << "D = " << D;
  // The nullspace of eq 22: (q̇₁, −M₂⁻¹ M₁₂ᵀ q̇₁) carries no momentum of either kind.
  const Eigen::Matrix<double, K, 1> q = Eigen::Matrix<double, K, 1>::Random();
  const Eigen::VectorXd v = -M2inv * M12.transpose() * q;
  const Eigen::VectorXd p1 = Eigen::MatrixXd(M1) * q + M12 * v;
  EXPECT_LT(p1.norm() / (Eigen::MatrixXd(M1) * q).norm(), 1e-14);
}

TEST(EolSplit, LagrangianMassEqualsCouplingProductEq20) {
  check_nullspace_identity<2>();
  check_nullspace_identity<3>();
}

// Eqs 23-24 on a random field: every node keeps its spatial velocity u = J q̇₁ + R v*, and the
// Eulerian remainder is orthogonal to every rigid field (the normal equations of eq 23).
template <int D>
void check_split_keeps_velocity() {
  std::mt19937_64 rng(11);
  const int n = 300;
  std::vector<Vec<double, D>> u(n), r(n), v(n);
  std::vector<double> m(n, 1.0);
  for (int i = 0; i < n; ++i) {
    u[std::size_t(i)] = random_vec<D>(rng, 3.0);
    r[std::size_t(i)] = random_vec<D>(rng, 1.0);
    if (i % 7 == 0) m[std::size_t(i)] = 0;  // empty nodes are left out of the fit
  }
  const Mat<double, D> R = random_rotation<D>(rng);
  const FrameVec<double, D> q = split_frame_velocity(u, r, m);
  eulerian_remainder(u, r, q, R, v);
  double worst = 0;
  FrameVec<double, D> normal = FrameVec<double, D>::Zero();
  for (int i = 0; i < n; ++i) {
    const auto k = std::size_t(i);
    const Vec<double, D> back = rigid_jacobian<double, D>(r[k]) * q + R * v[k];
    worst = std::max(worst, (back - u[k]).norm() / u[k].norm());
    if (m[k] > 0) normal += rigid_jacobian<double, D>(r[k]).transpose() * (R * v[k]);
  }
  EXPECT_LT(worst, 1e-14) << "D = " << D;
  EXPECT_LT(normal.norm() / n, 1e-13) << "D = " << D;
  EXPECT_GT(q.norm(), 0.01);
}

TEST(EolSplit, EveryNodeKeepsItsSpatialVelocity) {
  check_split_keeps_velocity<2>();
  check_split_keeps_velocity<3>();
}

// A rigid field ν + ω × r splits into the frame alone: q̇₁ = (ν, ω) and v* ≡ 0.
template <int D>
void check_rigid_field_is_frame() {
  std::mt19937_64 rng(5);
  const int n = 150;
  FrameVec<double, D> q;
  for (int k = 0; k < frame_dofs<D>; ++k) q[k] = std::uniform_real_distribution<double>(-2, 2)(rng);
  std::vector<Vec<double, D>> u(n), r(n), v(n);
  std::vector<double> m(n, 0.5);
  for (int i = 0; i < n; ++i) {
    r[std::size_t(i)] = random_vec<D>(rng, 1.0);
    u[std::size_t(i)] = rigid_jacobian<double, D>(r[std::size_t(i)]) * q;
  }
  const FrameVec<double, D> fit = split_frame_velocity(u, r, m);
  eulerian_remainder(u, r, fit, random_rotation<D>(rng), v);
  EXPECT_LT((fit - q).norm() / q.norm(), 1e-13) << "D = " << D;
  double vmax = 0;
  for (const auto& x : v) vmax = std::max(vmax, x.norm());
  EXPECT_LT(vmax / q.norm(), 1e-13) << "D = " << D;
}

TEST(EolSplit, RigidFieldSplitsIntoFrameVelocityWithZeroEulerianVelocity) {
  check_rigid_field_is_frame<2>();
  check_rigid_field_is_frame<3>();
}

// The split's sums run in blocks of node_block nodes (sum_node_blocks: the same bits for any
// thread count), not in one index-order sweep. Against that sweep (the formula before the
// blocks) on 9,000 nodes, 9 blocks: each of the normal equations' sums may differ by at most
// (n + blocks) ε Σ|terms| (two recursive sums of the same terms, Higham's bound (n − 1) ε Σ|x|
// for each), and the solve amplifies a relative change of b by at most cond(A). And 1 thread
// against 2, bit for bit.
template <int D>
void check_block_sums_match_one_sweep() {
  std::mt19937_64 rng(23);
  const std::size_t n = 9 * node_block;
  std::vector<Vec<double, D>> u(n), r(n);
  std::vector<double> m(n, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    // A drift and a spin under the noise, so the sums do not cancel to noise (which would
    // loosen the bound below by Σ|terms| / |Σ terms|).
    r[i] = random_vec<D>(rng, 1.0) + Vec<double, D>::Constant(0.3);  // off-centre: c ≠ 0
    u[i] = random_vec<D>(rng, 0.5) + Vec<double, D>::Constant(1.5);
    u[i][0] -= 2 * r[i][1];
    u[i][1] += 2 * r[i][0];
    if (i % 5 == 0) m[i] = 0;
  }
  // One sweep in index order (the old split_frame_velocity).
  RigidMoments<D> moments;
  Eigen::Vector3d sum_u = Eigen::Vector3d::Zero(), sum_moment = Eigen::Vector3d::Zero();
  double abs_b = 0;  // Σ|terms| of the right-hand side
  for (std::size_t i = 0; i < n; ++i) {
    if (!(m[i] > 0)) continue;
    moments.template add<double>(1.0, r[i]);
    for (int a = 0; a < D; ++a) sum_u[a] += u[i][a];
    const Eigen::Vector3d rxu = cross_moment<double, D>(r[i], u[i]);
    sum_moment += rxu;
    abs_b += u[i].template lpNorm<1>() + rxu.lpNorm<1>();
  }
  constexpr int K = frame_dofs<D>;
  const FrameMatrix<D> A = moments.matrix();
  Eigen::Matrix<double, K, 1> b;
  b.template head<D>() = sum_u.template head<D>();
  if constexpr (D == 2)
    b[2] = sum_moment[2];
  else
    b.template tail<3>() = sum_moment;
  const Eigen::Matrix<double, K, 1> sweep = A.ldlt().solve(b);
  const Eigen::JacobiSVD<FrameMatrix<D>> svd(A);
  const double cond = svd.singularValues()[0] / svd.singularValues()[K - 1];
  // A's own sums (Σ r, Σ r rᵀ) move by the same relative amount as b's terms at most: their
  // terms are no larger relative to A than b's are to b here (r within [-0.7, 1.3]).
  const double eps = std::numeric_limits<double>::epsilon();
  const double blocks = double(n / node_block);
  const double bound = 2 * cond * (double(n) + blocks) * eps * abs_b / b.norm();

  std::vector<SplitSums<D, 1>> partial;
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  const FrameVec<double, D> one = split_frame_velocity(u, r, m, true, partial);
  omp_set_num_threads(2);
  const FrameVec<double, D> two = split_frame_velocity(u, r, m, true, partial);
  omp_set_num_threads(saved);
  const double diff = (one - sweep).norm() / sweep.norm();
  std::printf("[eol split] %dD: blocks against one sweep %.1e relative (bound %.1e, cond %.1f)\n",
              D, diff, bound, cond);
  EXPECT_LT(diff, bound) << "D = " << D;
  EXPECT_GT(sweep.norm(), 1e-3);  // the fit is not trivially zero
  EXPECT_EQ(std::memcmp(one.data(), two.data(), sizeof(one)), 0) << "D = " << D;
}

TEST(EolSplit, BlockSumsMatchOneSweepAndAnyThreadCount) {
  check_block_sums_match_one_sweep<2>();
  check_block_sums_match_one_sweep<3>();
}

// Distorts X inside an object's grid smoothly (a stretch plus a bump), keeping it invertible.
template <int D>
void distort(EulerianGrid<double, D>& g, const Vec<double, D>& center) {
  for (std::size_t i = 0; i < g.size(); ++i) {
    Vec<double, D> d = g.X[i] - center;
    Vec<double, D> out = d;
    out[0] = 0.9 * d[0] + 0.05 * std::sin(6 * d[1]);
    out[1] = 1.08 * d[1] + 0.04 * std::sin(5 * d[0]);
    if constexpr (D == 3) out[2] = 0.97 * d[2] + 0.03 * std::sin(4 * d[0] + 3 * d[1]);
    g.X[i] = center + out;
  }
}

// Internal (elastic) forces of a distorted object: zero net force and zero net torque (the
// Cauchy stress P Fᵀ / J is symmetric), relative to the sum of their magnitudes.
template <int D>
void check_internal_forces_balance() {
  test::EolSceneSpec spec;
  spec.dim = D;
  spec.dx = D == 2 ? 1.0 / 32 : 1.0 / 16;
  auto sim = test::make_eol<D>(spec);
  ASSERT_TRUE(sim);
  auto& o = sim->objects()[0];
  distort<D>(o.grid, Vec<double, D>::Constant(0.5));
  sim->update_mass(o);
  std::vector<Vec<double, D>> f(o.grid.size());
  ElasticForces<double, D> forces;
  forces.compute(o.grid, sim->materials(), f, false);
  Vec<double, D> net = Vec<double, D>::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  double magnitude = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    net += f[i];
    torque += cross_moment<double, D>(o.grid.y(i), f[i]);
    magnitude += f[i].norm();
  }
  ASSERT_GT(magnitude, 1.0);
  EXPECT_LT(net.norm() / magnitude, 1e-13) << "D = " << D;
  EXPECT_LT(torque.norm() / magnitude, 1e-13) << "D = " << D;
}

TEST(EolForces, InternalForcesHaveZeroNetForceAndTorque) {
  check_internal_forces_balance<2>();
  check_internal_forces_balance<3>();
}

// The step's shortcuts against the straightforward passes on the same state: the mass after
// extrapolation (re-evaluated only where extrapolation wrote) equals a full update_mass, the
// forces computed ahead at the step's end equal compute_forces, and the diagnostics' elastic
// energy (Ψ at the forces' Gauss points) equals elastic_energy_moved to round-off.
template <int D>
void check_step_shortcuts() {
  test::EolSceneSpec spec;
  spec.dim = D;
  spec.dx = D == 2 ? 1.0 / 32 : 1.0 / 16;
  spec.velocity = {0.5, -0.3, 0.2};
  spec.spin = 2;
  spec.gravity = {0, -9.8, 0};
  auto sim = test::make_eol<D>(spec);
  ASSERT_TRUE(sim);
  distort<D>(sim->objects()[0].grid, Vec<double, D>::Constant(0.5));
  sim->update_mass(sim->objects()[0]);
  sim->spatial_state(sim->objects()[0]);
  sim->reset_energy_reference();
  for (int s = 0; s < 4; ++s) {
    DiagnosticsRow row;
    ASSERT_FALSE(sim->step(1e9, &row));
    const auto& ahead = std::as_const(*sim).objects()[0];
    const double reference = elastic_energy_moved(ahead.grid, sim->materials());
    ASSERT_GT(reference, 0);
    EXPECT_NEAR(row.elastic, reference, 1e-12 * reference) << "D = " << D << " step " << s;
    auto full = std::make_unique<EolSimulation<double, D>>(*sim);
    auto& o = full->objects()[0];
    const auto mass = o.grid.mass, fill = o.grid.fill;
    const auto force = o.force;
    full->update_mass(o);
    full->compute_forces(o);
    int differing = 0;
    for (std::size_t i = 0; i < o.grid.size(); ++i)
      differing += o.grid.mass[i] != mass[i] || o.grid.fill[i] != fill[i] || o.force[i] != force[i];
    EXPECT_EQ(differing, 0) << "D = " << D << " step " << s;
  }
}

TEST(EolStep, ShortcutsEqualTheFullPasses) {
  check_step_shortcuts<2>();
  check_step_shortcuts<3>();
}

// f = −∂E/∂y: the forces against central differences of the grid's elastic energy with each
// tested node moved by ±h along each axis (X and the fill held), for both materials.
template <int D>
void check_forces_are_energy_gradient(const std::string& model) {
  test::EolSceneSpec spec;
  spec.dim = D;
  spec.dx = D == 2 ? 1.0 / 32 : 1.0 / 12;
  auto sim = test::make_eol<D>(spec);
  ASSERT_TRUE(sim);
  auto& o = sim->objects()[0];
  distort<D>(o.grid, Vec<double, D>::Constant(0.5));
  sim->update_mass(o);
  std::vector<ElasticMaterial<double>> mats = sim->materials();
  mats[0].model =
      model == "neo-hookean" ? MaterialModel::neo_hookean : MaterialModel::fixed_corotated;
  std::vector<Vec<double, D>> f(o.grid.size());
  ElasticForces<double, D> forces;
  forces.compute(o.grid, mats, f, false);
  const double h = 1e-6 * o.grid.dx;
  std::vector<Vec<double, D>> dy(o.grid.size(), Vec<double, D>::Zero());
  double fmax = 0;
  for (const auto& x : f) fmax = std::max(fmax, x.norm());
  int tested = 0;
  for (std::size_t i = 0; i < o.grid.size(); i += 3) {
    if (!(o.grid.fill[i] > 0)) continue;
    for (int a = 0; a < D; ++a) {
      dy[i][a] = h;
      const double plus = elastic_energy_moved(o.grid, mats, dy);
      dy[i][a] = -h;
      const double minus = elastic_energy_moved(o.grid, mats, dy);
      dy[i][a] = 0;
      const double fd = -(plus - minus) / (2 * h);
      EXPECT_NEAR(f[i][a], fd, 1e-6 * fmax) << model << " node " << i << " axis " << a;
    }
    ++tested;
  }
  EXPECT_GE(tested, 12);
}

TEST(EolForces, ElasticForceIsMinusTheGradientOfTheGridEnergy) {
  check_forces_are_energy_gradient<2>("neo-hookean");
  check_forces_are_energy_gradient<2>("fixed-corotated");
  check_forces_are_energy_gradient<3>("neo-hookean");
}

// The forces' lanes (cell_points.hpp; the neo-Hookean Kirchhoff stress μ F Fᵀ + (λ log J − μ) I
// from adj(A), glibc's vector log) against the plain per-point formula f_k = −Σ V₀ P Fᵀ ∇_y N_k
// with F = Δx A⁻¹ and P, Ψ from materials.hpp, on a distorted grid. The two differ only in the
// order of their arithmetic (and ≤ 1 ulp in log J), so they agree to round-off: P Fᵀ near F = I
// is a difference of O(μ) parts (neo-Hookean μ F Fᵀ and (λ log J − μ) I; fixed corotated
// 2μ (F − R) Fᵀ and λ (J − 1) J I) and a node's force a sum of terms that nearly cancel, so the
// scale is the largest Σ V₀ |parts| |∇_y N| of a node, and 64 ε of it bounds the difference;
// the energies to 1e-13 relative.
template <int D>
void check_forces_match_the_per_point_formula(MaterialModel model) {
  test::EolSceneSpec spec;
  spec.dim = D;
  spec.dx = D == 2 ? 1.0 / 32 : 1.0 / 16;
  auto sim = test::make_eol<D>(spec);
  ASSERT_TRUE(sim);
  auto& o = sim->objects()[0];
  const auto& g = o.grid;
  distort<D>(o.grid, Vec<double, D>::Constant(0.5));
  sim->update_mass(o);
  std::vector<ElasticMaterial<double>> mats = sim->materials();
  mats[0].model = model;
  std::vector<Vec<double, D>> f(g.size());
  ElasticForces<double, D> forces;
  forces.compute(g, mats, f, false);
  const CellQuadrature<double, D> quad;
  std::vector<Vec<double, D>> ref(g.size(), Vec<double, D>::Zero());
  std::vector<double> terms(g.size(), 0.0);  // Σ V₀ |parts| |∇_y N| per node
  double energy = 0;
  for (std::size_t base = 0; base < g.size(); ++base) {
    if (!is_cell_base(g, base)) continue;
    const int m = cell_material(g, base);
    if (m < 0) continue;
    for (int q = 0; q < quad.points; ++q) {
      Mat<double, D> A = Mat<double, D>::Zero();
      double fill = 0;
      for (int k = 0; k < quad.corners; ++k) {
        const std::size_t i = corner_node(g, base, k);
        A += g.X[i] * quad.dN[std::size_t(q)][std::size_t(k)].transpose();
        fill += quad.N[std::size_t(q)][std::size_t(k)] * g.fill[i];
      }
      if (!(fill > 0) || !(A.determinant() > 0)) continue;
      const double volume = A.determinant() * quad.weight * fill;
      const Mat<double, D> F = g.dx * A.inverse();
      double psi = 0;
      const Mat<double, D> Pk =
          first_piola_and_energy<double, D>(model, F, mats[std::size_t(m)].lame, psi);
      energy += volume * psi;
      const Lame<double>& l = mats[std::size_t(m)].lame;
      const double J = F.determinant(), root_d = std::sqrt(double(D));
      const double parts =
          model == MaterialModel::neo_hookean
              ? l.mu * F.squaredNorm() + std::abs(l.lambda * std::log(J) - l.mu) * root_d
              : 2 * l.mu * (F.norm() + root_d) * F.norm() +
                    std::abs(l.lambda * (J - 1) * J) * root_d;
      for (int k = 0; k < quad.corners; ++k) {
        const Vec<double, D> term =
            volume * Pk * F.transpose() * quad.dN[std::size_t(q)][std::size_t(k)] / g.dx;
        ref[corner_node(g, base, k)] -= term;
        terms[corner_node(g, base, k)] +=
            volume * parts * (quad.dN[std::size_t(q)][std::size_t(k)] / g.dx).norm();
      }
    }
  }
  double fmax = 0, scale = 0, worst = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    fmax = std::max(fmax, ref[i].norm());
    scale = std::max(scale, terms[i]);
    worst = std::max(worst, (f[i] - ref[i]).norm());
  }
  ASSERT_GT(fmax, 0.1);
  constexpr double eps = std::numeric_limits<double>::epsilon();
  std::printf(
      "[eol forces] %dD %s: max |f - f_ref| = %.1f eps of the scale (%.1e of max |f|), "
      "energy %.1e relative\n",
      D, model == MaterialModel::neo_hookean ? "neo-hookean" : "fixed-corotated",
      worst / (eps * scale), worst / fmax, std::abs(forces.energy() - energy) / energy);
  EXPECT_LT(worst, 64 * eps * scale);
  EXPECT_NEAR(forces.energy(), energy, 1e-13 * energy);
}

TEST(EolForces, LanesMatchThePerPointFormula) {
  check_forces_match_the_per_point_formula<2>(MaterialModel::neo_hookean);
  check_forces_match_the_per_point_formula<3>(MaterialModel::neo_hookean);
  check_forces_match_the_per_point_formula<2>(MaterialModel::fixed_corotated);
  check_forces_match_the_per_point_formula<3>(MaterialModel::fixed_corotated);
}

// Eq 15 with semi-Lagrangian multilinear interpolation: an affine X = A y + b is advected
// exactly by any velocity, also where the departure point leaves the grid.
template <int D>
void check_affine_advection() {
  std::mt19937_64 rng(3);
  EulerianGrid<double, D> g;
  std::array<int, D> n;
  for (int a = 0; a < D; ++a) n[std::size_t(a)] = 9 + 2 * a;
  g.resize(n);
  g.dx = 0.1;
  g.origin = Vec<double, D>::Constant(-0.4);
  const Mat<double, D> A = Mat<double, D>::Identity() + 0.3 * Mat<double, D>::Random();
  const Vec<double, D> b = random_vec<D>(rng, 2.0);
  std::vector<Vec<double, D>> vel(g.size()), out(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    g.X[i] = A * g.y(i) + b;
    vel[i] = random_vec<D>(rng, 5.0);  // departures up to 2.5 cells away, some off the grid
  }
  const double dt = 0.05;
  advect(g, vel, dt, g.X, out, false);
  double worst = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const Vec<double, D> exact = A * (g.y(i) - dt * vel[i]) + b;
    worst = std::max(worst, (out[i] - exact).norm() / exact.norm());
  }
  EXPECT_LT(worst, 1e-14) << "D = " << D;
}

TEST(EolAdvection, AffineMaterialCoordinatesAreAdvectedExactly) {
  check_affine_advection<2>();
  check_affine_advection<3>();
}

// A y that is NaN or ±∞ (a state blowing up within a step; fuzz_scene found one) takes an edge
// cell without converting a non-finite value to int; +∞ takes the top cell, as a finite y above
// the grid does. The weights carry the NaN on for the blow-up check.
TEST(EolGrid, NonFinitePositionsTakeAnEdgeCell) {
  EulerianGrid<double, 2> g;
  g.resize({5, 7});
  g.dx = 0.5;
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto cell = [&](double y0, double y1) {
    std::array<int, 2> c;
    std::array<double, 2> t;
    g.cell_at(Vec<double, 2>(y0, y1), c, t);
    return c;
  };
  EXPECT_EQ(cell(inf, -inf), (std::array<int, 2>{3, 0}));
  EXPECT_EQ(cell(1e300, 1e30), (std::array<int, 2>{3, 5}));
  EXPECT_EQ(cell(nan, 1.2), (std::array<int, 2>{0, 2}));
  EXPECT_EQ(cell(-1e300, nan), (std::array<int, 2>{0, 0}));
  const auto cw = g.cell_weights(Vec<double, 2>(nan, 0.3));
  for (const std::size_t k : cw.index) EXPECT_LT(k, g.size());
  EXPECT_TRUE(std::isnan(cw.weight[0]));
}

// The mass of eq 6 with J̄ = det ∇X: a ball's lumped mass matches ρ times its area (volume)
// within the smoothed surface's second-order error.
TEST(EolGrid, LumpedMassMatchesTheRestShape) {
  for (int dim : {2, 3}) {
    test::EolSceneSpec spec;
    spec.dim = dim;
    spec.dx = dim == 2 ? 1.0 / 64 : 1.0 / 24;
    spec.radius = 0.25;
    spec.rho = 3;
    const double exact = dim == 2 ? 3 * M_PI * 0.0625 : 3 * 4.0 / 3.0 * M_PI * std::pow(0.25, 3);
    const double mass =
        dim == 2 ? test::make_eol<2>(spec)->total_mass() : test::make_eol<3>(spec)->total_mass();
    EXPECT_NEAR(mass / exact, 1.0, dim == 2 ? 2e-3 : 1e-2) << "dim " << dim;
  }
}

// Bad input: one line naming the cause.
TEST(EolScene, BadInputGetsOneLineNamingTheKey) {
  auto message = [](const std::string& text, const std::vector<std::string>& overrides) {
    try {
      SceneDesc s = parse_scene_text(text, "bad.json", overrides);
      make_simulation(s);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const test::EolSceneSpec spec;
  const std::string eol = test::eol_scene_json(spec);
  nlohmann::json mpm = nlohmann::json::parse(eol);
  mpm["solver"] = {{"method", "mpm"}, {"alpha", 0.5}};
  const std::string cases[][2] = {
      {message(mpm.dump(), {}), "'solver.alpha': unknown key"},
      {message(eol, {"solver.scheme=apic"}), "'solver.scheme': unknown key"},
      {message(eol, {"solver.grid_extent=0.2"}), "'objects.0.shape': the rest shape spans"},
      {message(eol, {"solver.alpha=1"}), "'solver.alpha'"},
      {message(eol, {"solver.method=eulerian", "solver.padding=2"}),
       "'solver.padding': unknown key"},
  };
  for (const auto& c : cases) {
    EXPECT_NE(c[0].find(c[1]), std::string::npos) << c[0];
    EXPECT_NE(c[0].find("bad.json"), std::string::npos) << c[0];
    EXPECT_EQ(c[0].find('\n'), std::string::npos) << c[0];
  }
}

}  // namespace
}  // namespace apiclab
