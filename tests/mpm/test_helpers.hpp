// Shared helpers for the solver tests: small scenes as JSON text, random particle states.
#pragma once
#include <cstdio>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "sim/mpm/probe.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab::test {

// A unit-square (cube) scene with one small box of material; the particles it samples are
// usually replaced by the test.
inline std::string scene_json(int dim, const std::string& scheme, const std::string& kernel,
                              double dx = 1.0 / 16, const std::string& boundary = "\"slip\"",
                              double E = 1000.0) {
  // `boundary` is JSON text: "\"slip\"" or an object of walls.
  const std::vector<double> lo(std::size_t(dim), 0.0), hi(std::size_t(dim), 1.0),
      box_min(std::size_t(dim), 0.45), box_max(std::size_t(dim), 0.55);
  const nlohmann::json scene = {
      {"name", "unit"},
      {"dim", dim},
      {"domain",
       {{"min", lo}, {"max", hi}, {"dx", dx}, {"boundary", nlohmann::json::parse(boundary)}}},
      {"solver", {{"scheme", scheme}, {"kernel", kernel}}},
      {"materials", {{{"name", "m"}, {"model", "neo-hookean"}, {"E", E}, {"nu", 0.3}, {"rho", 1}}}},
      {"objects",
       {{{"shape", {{"type", "box"}, {"min", box_min}, {"max", box_max}}}, {"material", 0}}}}};
  return scene.dump();
}

inline SceneDesc make_scene(int dim, const std::string& scheme, const std::string& kernel,
                            double dx = 1.0 / 16, const std::string& boundary = "\"slip\"",
                            double E = 1000.0) {
  return parse_scene_text(scene_json(dim, scheme, kernel, dx, boundary, E), "test");
}

template <class T, int D>
Mat<T, D> random_matrix(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Mat<T, D> M;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) M(i, j) = T(u(rng));
  return M;
}

template <class T, int D>
Vec<T, D> random_vector(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  Vec<T, D> x;
  for (int a = 0; a < D; ++a) x[a] = T(u(rng));
  return x;
}

// Replaces the simulation's particles by n random ones in [lo, hi]^D with random mass,
// velocity and affine matrix (skew when `skew_C`, zero when `zero_C`).
template <int D>
void randomize_particles(MpmSimulation<double, D>& sim, std::size_t n, std::uint64_t seed,
                         double lo = 0.3, double hi = 0.7, bool skew_C = false,
                         bool zero_C = false) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> um(0.5, 2.0);
  auto& p = MpmProbe(sim).particles();
  p.resize(n);
  for (std::size_t q = 0; q < n; ++q) {
    p.x[q] = random_vector<double, D>(rng, lo, hi);
    p.v[q] = random_vector<double, D>(rng, -1.0, 1.0);
    Mat<double, D> C = random_matrix<double, D>(rng, 2.0);
    if (skew_C) C = (0.5 * (C - C.transpose())).eval();  // eval: C aliases Cᵀ
    if (zero_C) C.setZero();
    p.C[q] = C;
    p.F[q].setIdentity();
    p.mass[q] = um(rng);
    p.volume0[q] = p.mass[q];
    p.material[q] = 0;
    p.object[q] = 0;
    p.id[q] = std::int32_t(q);
  }
}

// The grid's momentum Σ m_i ṽ_i and angular momentum Σ x̃_i × m_i ṽ_i (x̃_i = x_i + Δt ṽ_i, ṽ
// the velocity_new of every node with mass), with the scales Σ |m ṽ| and Σ |x̃| |m ṽ| that the
// G2P conservation tests divide by.
struct MovedGridMoments {
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), L = Eigen::Vector3d::Zero();
  double p_scale = 0, L_scale = 0;
};
template <int D>
MovedGridMoments moved_grid_moments(const Grid<double, D>& g, double dt) {
  MovedGridMoments m;
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (g.mass[i] <= 0) continue;
    const Vec<double, D> xt = g.node_position(i) + dt * g.velocity_new[i];
    const Vec<double, D> mv = g.mass[i] * g.velocity_new[i];
    for (int a = 0; a < D; ++a) m.p[a] += mv[a];
    m.L += cross_moment<double, D>(xt, mv);
    m.p_scale += mv.norm();
    m.L_scale += xt.norm() * mv.norm();
  }
  return m;
}

// rotating-disk with symplectic Euler and the explicit elastic time-step limit (the scene itself
// runs the paper's midpoint rule), scheme `scheme`, then the `extra` overrides.
inline SceneDesc disk_symplectic(const std::string& scheme, std::vector<std::string> extra = {}) {
  extra.insert(extra.begin(),
               {"solver.integrator=symplectic", R"(time.dt={"rule":"elastic","nu":0.3})"});
  extra.push_back("solver.scheme=" + scheme);
  return load_scene(std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json", extra);
}

inline double norm3(const Eigen::Vector3d& a) { return a.norm(); }
inline Eigen::Vector3d to3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// A grid over the box [lo, lo + 1] per axis, every wall slip or every axis periodic, the whole
// domain stored (for stencil tests).
template <class T, int D>
Grid<T, D> unit_box_grid(bool periodic, double dx, const std::array<double, 3>& lo = {0, 0, 0}) {
  SceneDesc s;
  s.dim = D;
  s.domain.min = {lo[0], lo[1], lo[2]};
  s.domain.max = {lo[0] + 1, lo[1] + 1, D == 3 ? lo[2] + 1 : 0.0};
  s.domain.dx = dx;
  s.domain.walls.fill(periodic ? BoundaryCondition::periodic : BoundaryCondition::slip);
  Grid<T, D> g;
  g.init(s);
  g.store_whole_domain();
  return g;
}

}  // namespace apiclab::test
