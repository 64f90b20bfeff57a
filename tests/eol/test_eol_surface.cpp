// The EoL surface (Fan et al. 2013, Sec 3.8): the rest surface built from φ₀ (closed, on
// φ₀ = 0, the right size), and Algorithm 2's placement: exact for rigid frames and for affine
// material coordinates, and on the object (within the grid's interpolation error) in a run
// that deforms it. 2D and 3D.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <utility>

#include "sim/eol/surface/surface_placement.hpp"
#include "tests/eol/eol_test_scenes.hpp"

namespace apiclab {
namespace {

using namespace apiclab::eol;

ShapeDesc ball(double radius) {
  ShapeDesc s;
  s.type = ShapeType::ball;
  s.center = {0.3, 0.4, 0.5};
  s.radius = radius;
  return s;
}

struct SurfaceMeasure {
  double max_phi = 0;  // max |φ₀(X_s)|
  double size = 0;     // 2D length, 3D enclosed volume (divergence theorem: signed)
  bool closed = true;  // 2D: every vertex in two segments; 3D: every edge in two triangles,
                       // once in each direction (consistently oriented)
};

template <int D>
SurfaceMeasure measure_surface(const ShapeDesc& shape, double h) {
  RestSurface<D> s;
  append_rest_surface<D>(shape, 0, h, s);
  SurfaceMeasure m;
  for (const auto& X : s.X) m.max_phi = std::max(m.max_phi, std::abs(rest_phi<D>(shape, X)));
  if constexpr (D == 2) {
    std::vector<int> degree(s.size(), 0);
    for (std::size_t e = 0; e < s.simplices(); ++e) {
      const auto a = s.simplex[2 * e], b = s.simplex[2 * e + 1];
      ++degree[a];
      ++degree[b];
      m.size += (s.X[a] - s.X[b]).norm();
    }
    for (int d : degree) m.closed = m.closed && d == 2;
  } else {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t t = 0; t < s.simplices(); ++t) {
      const std::uint32_t* v = &s.simplex[3 * t];
      m.size += s.X[v[0]].dot(s.X[v[1]].cross(s.X[v[2]])) / 6;
      for (int k = 0; k < 3; ++k) ++directed[{v[k], v[(k + 1) % 3]}];
    }
    for (const auto& [edge, count] : directed)
      m.closed = m.closed && count == 1 && directed.count({edge.second, edge.first}) == 1;
  }
  EXPECT_GT(s.size(), 20u);
  return m;
}

TEST(EolSurface, RestSurfaceIsClosedOnTheRestShapeAndTheRightSize) {
  const double r = 0.2, h = 0.025;
  ShapeDesc box;
  box.type = ShapeType::box;
  box.min = {0.1, 0.2, 0.3};
  box.max = {0.5, 0.45, 0.6};
  box.center = {0.3, 0.325, 0.45};  // the scene reader's (min + max)/2: φ₀ is centred on it
  ShapeDesc annulus = ball(0);
  annulus.type = ShapeType::annulus;
  annulus.inner = 0.1;
  annulus.outer = 0.25;
  ShapeDesc torus = annulus;
  torus.type = ShapeType::torus;
  // Chords of a circle of radius r at most ~h long: length short by ≤ h²/(24 r²) relative;
  // inscribed triangles: volume short by O(h²/r²). The box is exact (flat faces; the
  // projection moves the vertices near an edge onto one face, cutting the edge by ≤ h).
  struct Case {
    const char* name;
    int dim;
    ShapeDesc shape;
    double size, tolerance;
  };
  const double pi = M_PI;
  const Case cases[] = {
      {"ball 2D", 2, ball(r), 2 * pi * r, 0.01},
      {"box 2D", 2, box, 2 * (0.4 + 0.25), 0.02},
      {"annulus 2D", 2, annulus, 2 * pi * (0.1 + 0.25), 0.01},
      {"ball 3D", 3, ball(r), 4.0 / 3 * pi * r * r * r, 0.03},
      {"box 3D", 3, box, 0.4 * 0.25 * 0.3, 0.05},
      {"torus 3D", 3, torus, 2 * pi * pi * 0.175 * 0.075 * 0.075, 0.06},
  };
  for (const Case& c : cases) {
    const SurfaceMeasure m =
        c.dim == 2 ? measure_surface<2>(c.shape, h) : measure_surface<3>(c.shape, h);
    std::printf("[eol surface] %-10s max|phi0| = %.1e, %s %.5f (exact %.5f, %+.2f %%)\n", c.name,
                m.max_phi, c.dim == 2 ? "length" : "volume", m.size, c.size,
                100 * (m.size / c.size - 1));
    EXPECT_LT(m.max_phi, 1e-12) << c.name;
    EXPECT_TRUE(m.closed) << c.name;
    EXPECT_NEAR(m.size / c.size, 1.0, c.tolerance) << c.name;
  }
}

// Moves every surface vertex's starting guess by up to `cells` cells, so Algorithm 2 has
// something to find.
template <int D>
void scatter_guesses(EolObject<double, D>& o, double cells, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-cells, cells);
  for (auto& y : o.surface_y)
    for (int a = 0; a < D; ++a) y[a] += u(rng) * o.grid.dx;
}

template <int D>
Mat<double, D> rotation_of(RigidFrame<double, D>& f) {
  if constexpr (D == 2)
    f.angle = 2.1;
  else
    f.q = Eigen::Quaterniond(Eigen::AngleAxisd(2.1, Eigen::Vector3d(1, -2, 0.5).normalized()));
  return f.rotation();
}

// A rigid motion of the frame with v ≡ 0 (X untouched): every vertex lands at R (X_s − p₀) + p,
// i.e. R X_s + t with t = p − R p₀, to round-off; the snapshot carries the same points.
template <int D>
void check_rigid_placement() {
  test::EolSceneSpec spec;
  spec.dim = D;
  spec.dx = D == 2 ? 1.0 / 32 : 1.0 / 16;
  auto sim = test::make_eol<D>(spec);
  auto& o = sim->objects()[0];
  const Vec<double, D> p0 = o.frame.p;
  Vec<double, D> t;
  for (int a = 0; a < D; ++a) t[a] = 3.7 - 1.3 * a;
  o.frame.p = p0 + t;
  const Mat<double, D> R = rotation_of<D>(o.frame);
  sim->spatial_state(o);
  scatter_guesses(o, 1.5, 3);
  sim->place_surface(o);
  EXPECT_EQ(o.surface_misses, 0);
  double worst = 0;
  for (std::size_t s = 0; s < o.surface.size(); ++s) {
    const Vec<double, D> expected = R * (o.surface.X[s] - p0) + p0 + t;
    worst = std::max(worst, (o.surface_world(s) - expected).norm() / expected.norm());
  }
  std::printf("[eol surface] %dD rigid frame, %zu vertices: max |x - (R X + t)|/|x| = %.1e\n", D,
              o.surface.size(), worst);
  EXPECT_LT(worst, 1e-14);
  const auto snap = sim->snapshot();
  ASSERT_EQ(snap->surfaces.size(), 1u);
  ASSERT_EQ(snap->surfaces[0].positions.size(), D * o.surface.size());
  EXPECT_EQ(snap->surfaces[0].elements, o.surface.simplex);
  for (std::size_t s = 0; s < o.surface.size(); ++s)
    for (int a = 0; a < D; ++a)
      EXPECT_FLOAT_EQ(snap->surfaces[0].positions[D * s + a], float(o.surface_world(s)[a]));
}

TEST(EolSurface, RigidFramePlacesEveryVertexAtRXPlusT) {
  check_rigid_placement<2>();
  check_rigid_placement<3>();
}

// An affine reference map X(y) = A y + b on the grid: Algorithm 2 inverts it exactly, y_s =
// A⁻¹ (X_s − b), from guesses up to 3 cells off.
template <int D>
void check_affine_placement() {
  test::EolSceneSpec spec;
  spec.dim = D;
  spec.dx = D == 2 ? 1.0 / 32 : 1.0 / 16;
  auto sim = test::make_eol<D>(spec);
  auto& o = sim->objects()[0];
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  Mat<double, D> A = Mat<double, D>::Identity();
  Vec<double, D> b = o.frame.p;
  for (int i = 0; i < D; ++i) {
    b[i] += u(rng) * 0.2;
    for (int j = 0; j < D; ++j) A(i, j) += u(rng);
  }
  ASSERT_GT(A.determinant(), 0.3);
  for (std::size_t i = 0; i < o.grid.size(); ++i) o.grid.X[i] = A * o.grid.y(i) + b;
  scatter_guesses(o, 3, 5);
  sim->place_surface(o);
  EXPECT_EQ(o.surface_misses, 0);
  const Mat<double, D> Ainv = A.inverse();
  double worst = 0;
  for (std::size_t s = 0; s < o.surface.size(); ++s) {
    const Vec<double, D> expected = Ainv * (o.surface.X[s] - b);
    worst = std::max(worst, (o.surface_y[s] - expected).norm() / spec.dx);
  }
  std::printf("[eol surface] %dD affine X: max |y - A^-1 (X_s - b)| = %.1e cells\n", D, worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(EolSurface, AffineMaterialCoordinatesPlaceTheAnalyticImage) {
  check_affine_placement<2>();
  check_affine_placement<3>();
}

// A ball thrown down onto the floor (the two drop tests below).
test::EolSceneSpec ball_drop(int dim, const std::string& method) {
  test::EolSceneSpec spec;
  spec.dim = dim;
  spec.method = method;
  spec.dx = dim == 2 ? 1.0 / 32 : 1.0 / 16;
  spec.radius = 0.2;
  spec.center = {0.5, 0.3, 0.5};
  spec.gravity = {0, -9.8, 0};
  spec.velocity = {0.4, -1.0, 0};
  return spec;
}

// A ball dropped on the floor, past the impact (the grid's X no longer affine): every vertex is
// found (X(p) = X_s to ε) and lies on the object: the nodes' φ₀(X_i), interpolated at the
// vertex, vanish up to multilinear interpolation's error, Σ_a (Δx²/8) |∂²φ/∂y_a²| ≤
// D Δx²/(8 r) for a ball of radius r (the distance's curvature 1/r at its surface); the
// deformation adds its own curvature, so the test allows twice that.
template <int D>
void check_vertices_on_the_object(const std::string& method) {
  test::EolSceneSpec spec = ball_drop(D, method);
  spec.end = 0.25;
  auto sim = test::make_eol<D>(spec);
  const auto& o = sim->objects()[0];
  double lowest = 1e300;  // the lowest any vertex came, sampled every 5 ms
  for (int k = 1; k <= 50; ++k) {
    const auto failure = sim->advance_to(spec.end * k / 50);
    ASSERT_FALSE(failure) << failure->message;
    for (std::size_t s = 0; s < o.surface.size(); ++s)
      lowest = std::min(lowest, double(o.surface_world(s)[1]));
  }
  EXPECT_EQ(o.surface_misses, 0);
  const ShapeDesc& shape = sim->scene().objects[0].shape;
  std::vector<double> phi(o.grid.size());
  for (std::size_t i = 0; i < o.grid.size(); ++i) phi[i] = rest_phi<D>(shape, o.grid.X[i]);
  double worst_X = 0, worst_phi = 0;
  for (std::size_t s = 0; s < o.surface.size(); ++s) {
    const Vec<double, D> X = o.grid.interpolate(o.grid.X, o.surface_y[s]);
    worst_X = std::max(worst_X, (X - o.surface.X[s]).template lpNorm<Eigen::Infinity>());
    worst_phi = std::max(worst_phi, std::abs(o.grid.interpolate(phi, o.surface_y[s])));
  }
  const double bound = 2 * D * spec.dx * spec.dx / (8 * spec.radius);
  std::printf(
      "[eol surface] %dD %s drop to t = %.2f s: max|X(p) - X_s| = %.1e, max|phi(p)| = %.2e "
      "(bound %.2e), lowest vertex y on the way = %.4f\n",
      D, method.c_str(), spec.end, worst_X, worst_phi, bound, lowest);
  EXPECT_LT(worst_X, 64 * 2.3e-16);
  EXPECT_LT(worst_phi, bound);
  // The ball reached the floor: the surface came down to it, and not through it by more than
  // a cell (the node–plane rows hold nodes, the surface lies between them). The Eulerian
  // baseline stops about a cell higher (measured 1.05 Δx): its mass smears over the cell
  // above the floor nodes, so two cells are allowed.
  EXPECT_LT(lowest, 2 * spec.dx) << "the drop should have reached the floor by then";
  EXPECT_GT(lowest, -spec.dx);
}

TEST(EolSurface, VerticesStayOnTheObjectThroughADrop) {
  check_vertices_on_the_object<2>("eol");
  check_vertices_on_the_object<3>("eol");
  check_vertices_on_the_object<2>("eulerian");
}

// Algorithm 2 runs only at frame times (step() places the surface when a step lands on its
// t_limit). Through the same drop (steps that never land on a frame, so nothing places the
// surface between), one placement after the whole run, warm-started from the rest positions
// 0.25 s back, finds every vertex where placing after every step does: both meet Algorithm 2's
// tolerance X(p) = X_s to ε_s = 64 ε |X_s| (the drop test's bound), and the two positions agree
// to 4 ε_s: both are within ε_s of the one root of the cell's multilinear map, so they differ by
// at most 2 ε_s ‖(∂X/∂y)⁻¹‖, and ‖(∂X/∂y)⁻¹‖ ≤ 2 allows the impact's compression (measured
// ≤ 1.0 ε_s, 4e-13 cells).
template <int D>
void check_frame_placement_matches_every_step(const std::string& method) {
  const test::EolSceneSpec spec = ball_drop(D, method);
  auto every = test::make_eol<D>(spec), framed = test::make_eol<D>(spec);
  int steps = 0;
  while (framed->time() < 0.25) {
    ASSERT_FALSE(every->step(1e9, nullptr));
    every->place_surfaces();
    ASSERT_FALSE(framed->step(1e9, nullptr));
    ++steps;
  }
  ASSERT_FALSE(framed->surfaces_placed()) << "a step that lands on no frame placed the surface";
  framed->place_surfaces();
  const auto& a = std::as_const(*every).objects()[0];
  const auto& b = std::as_const(*framed).objects()[0];
  EXPECT_EQ(a.surface_misses, 0);
  EXPECT_EQ(b.surface_misses, 0);
  double worst_y = 0, worst_ratio = 0, worst_X = 0;
  for (std::size_t s = 0; s < b.surface.size(); ++s) {
    const double dy = (a.surface_y[s] - b.surface_y[s]).norm();
    worst_y = std::max(worst_y, dy / spec.dx);
    worst_ratio = std::max(worst_ratio, dy / placement_tolerance<double, D>(b.surface.X[s]));
    const Vec<double, D> X = b.grid.interpolate(b.grid.X, b.surface_y[s]);
    worst_X = std::max(worst_X, (X - b.surface.X[s]).template lpNorm<Eigen::Infinity>());
  }
  std::printf(
      "[eol surface] %dD %s: placed once after %d steps vs every step: max |dy| = %.1e cells "
      "(%.2f of the tolerance), max|X(p) - X_s| = %.1e\n",
      D, method.c_str(), steps, worst_y, worst_ratio, worst_X);
  EXPECT_LT(worst_X, 64 * 2.3e-16);
  EXPECT_LT(worst_ratio, 4.0);
}

TEST(EolSurface, PlacementAtFrameTimesMatchesEveryStep) {
  check_frame_placement_matches_every_step<2>("eol");
  check_frame_placement_matches_every_step<3>("eol");
  check_frame_placement_matches_every_step<2>("eulerian");
}

}  // namespace
}  // namespace apiclab
