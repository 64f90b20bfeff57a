// Shared helpers for the solver tests: small scenes as JSON text, random particle states.
#pragma once
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "sim/mpm.hpp"
#include "sim/scene.hpp"

namespace apiclab::test {

// A unit-square (cube) scene with one small box of material; the particles it samples are
// usually replaced by the test.
inline std::string scene_json(int dim, const std::string& scheme, const std::string& kernel,
                              double dx = 1.0 / 16, const std::string& boundary = "\"slip\"",
                              double E = 1000.0) {
  auto v = [dim](double a) {
    std::string s = "[" + std::to_string(a);
    for (int i = 1; i < dim; ++i) s += "," + std::to_string(a);
    return s + "]";
  };
  char dxs[64];
  std::snprintf(dxs, sizeof dxs, "%.17g", dx);
  char Es[64];
  std::snprintf(Es, sizeof Es, "%.17g", E);
  return std::string("{\"name\":\"unit\",\"dim\":") + std::to_string(dim) +
         ",\"domain\":{\"min\":" + v(0) + ",\"max\":" + v(1) + ",\"dx\":" + dxs +
         ",\"boundary\":" + boundary + "},\"solver\":{\"scheme\":\"" + scheme + "\",\"kernel\":\"" +
         kernel + "\"},\"materials\":[{\"name\":\"m\",\"model\":\"neo-hookean\",\"E\":" + Es +
         ",\"nu\":0.3,\"rho\":1}],\"objects\":[{\"shape\":{\"type\":\"box\",\"min\":" + v(0.45) +
         ",\"max\":" + v(0.55) + "},\"material\":0}]}";
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
  auto& p = sim.particles();
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

inline double norm3(const Eigen::Vector3d& a) { return a.norm(); }
inline Eigen::Vector3d to3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

}  // namespace apiclab::test
