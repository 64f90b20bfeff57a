// Mesh rest shapes for the EoL solver (sim/eol/shape/mesh_distance.hpp): the sampled signed
// distance of an icosphere against the ball's, of a placed box OBJ against the box shape's
// (transform and sign), and the lumped mass of a mesh against ρ₀ × the OBJ's volume.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "sim/eol/shape/rest_shape.hpp"
#include "sim/geometry/obj_mesh.hpp"
#include "sim/geometry/sampling.hpp"
#include "tests/eol/eol_test_scenes.hpp"

namespace apiclab {
namespace {

// An OBJ file in a folder of this process's own (ctest runs each test in a process, other
// checkouts too), removed with it.
struct ScratchObj {
  std::filesystem::path dir, file;
  explicit ScratchObj(const std::string& name)
      : dir(std::filesystem::temp_directory_path() /
            ("apiclab_eol_mesh_" + std::to_string(::getpid()))),
        file(dir / name) {
    std::filesystem::create_directories(dir);
  }
  ~ScratchObj() {
    std::error_code ignored;
    std::filesystem::remove(file, ignored);
    std::filesystem::remove(dir, ignored);  // only when empty
  }
  std::string path() const { return file.string(); }
};

// A unit icosphere: the icosahedron, each face split in four `levels` times, every vertex on
// the sphere. Written as an OBJ (outward faces).
ObjMesh icosphere(int levels) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<std::uint32_t, 3>> f = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& x : v) x.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto middle = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = std::uint32_t(v.size() - 1);
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& [a, b, c] : f) {
      const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      next.insert(next.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    f = next;
  }
  ObjMesh m;
  for (const auto& x : v) m.vertices.push_back({x[0], x[1], x[2]});
  m.triangles = f;
  return m;
}

void write_obj(const ObjMesh& m, const std::string& path) {
  std::ofstream out(path);
  out.precision(17);
  for (const auto& x : m.vertices) out << "v " << x[0] << ' ' << x[1] << ' ' << x[2] << '\n';
  for (const auto& t : m.triangles)
    out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

ShapeDesc mesh_shape(const std::string& file, double scale, const Vec3d& translate) {
  ShapeDesc s;
  s.type = ShapeType::mesh;
  s.file = file;
  s.scale = scale;
  s.translate = translate;
  return s;
}

// The sagitta δ: how far the icosphere's faces sink below the sphere. Nested surfaces δ apart
// (Hausdorff) have signed distances within δ of each other everywhere.
double sagitta(const ObjMesh& m, double radius) {
  double nearest = 1e300;
  for (const auto& t : m.triangles) {
    auto at = [&](int k) {
      const auto& x = m.vertices[t[std::size_t(k)]];
      return Eigen::Vector3d(x[0], x[1], x[2]);
    };
    nearest = std::min(nearest,
                       eol::point_triangle_distance(Eigen::Vector3d::Zero(), at(0), at(1), at(2)));
  }
  return radius * (1 - nearest);
}

// The icosphere's sampled distance against the ball's φ = |x − c| − r: within the fade
// (|φ| < cell/2, where the mass reads it) to δ + the trilinear interpolation error of the
// ball's distance, (s²/8) Σ_a max|∂²φ/∂x_a²| ≤ 3 s² / (8 ρ_min), ρ_min the smallest |x − c| of a
// cell there; everywhere with the ball's sign (where |φ| exceeds that bound) and, away from the
// centre's kink, never shorter than the ball's by more than the same bound at the point's own
// ρ (the chamfer beyond the band is an upper bound of the distance).
TEST(EolMeshDistance, IcosphereMatchesTheBallDistance) {
  const double r = 0.3, cell = 0.05;
  const Vec3d c{0.5, 0.6, 0.4};
  const ObjMesh unit = icosphere(3);  // 1280 faces
  const ScratchObj scratch("icosphere3.obj");
  const std::string file = scratch.path();
  write_obj(unit, file);
  const eol::MeshDistance phi(load_obj_mesh(file), mesh_shape(file, r, c), cell);
  const double s = phi.spacing();
  const double delta = sagitta(unit, r);
  const double rho_min = r - 0.5 * cell - std::sqrt(3.0) * s;
  const double bound = delta + 3 * s * s / (8 * rho_min);
  double worst_fade = 0, worst_short = 0;
  int fade_points = 0, sign_errors = 0;
  for (int k = -40; k <= 40; ++k)
    for (int j = -40; j <= 40; ++j)
      for (int i = -40; i <= 40; ++i) {  // a lattice off the sampled one, past its edges
        const Vec3d x{c[0] + 0.0123 * i, c[1] + 0.0117 * j, c[2] + 0.0131 * k};
        const double ball = std::hypot(x[0] - c[0], x[1] - c[1], x[2] - c[2]) - r;
        const double mesh = phi(x);
        if (std::abs(ball) < 0.5 * cell) {
          worst_fade = std::max(worst_fade, std::abs(mesh - ball));
          ++fade_points;
        } else if (ball + r > r / 2) {  // off the centre, where the ball's φ has its kink
          const double local = delta + 3 * s * s / (8 * (ball + r - std::sqrt(3.0) * s));
          worst_short = std::max(worst_short, (std::abs(ball) - std::abs(mesh)) / local);
        }
        if (std::abs(ball) > bound && (mesh < 0) != (ball < 0)) ++sign_errors;
      }
  EXPECT_GT(fade_points, 10000);
  EXPECT_LT(worst_fade, bound) << "delta " << delta << " bound " << bound;
  std::printf(
      "[eol mesh] icosphere: max |phi_mesh - phi_ball| in the fade %.3g (bound %.3g: "
      "sagitta %.3g), %d points; shortest beyond %.2f of the local bound\n",
      worst_fade, bound, delta, fade_points, worst_short);
  EXPECT_LT(worst_short, 1.0);  // in units of the local bound
  EXPECT_EQ(sign_errors, 0);
  // Far outside the lattice: positive, at least the way to the ball.
  EXPECT_GE(phi({c[0] + 3, c[1], c[2]}), 3 - r - bound);
  EXPECT_NEAR(phi(c), -r, r * 0.2);  // the centre, deep inside (chamfer: within its metric)
}

// A box OBJ (quads, fan-triangulated on load) scaled, rotated and translated as a mesh shape
// is the box shape with the same rotation, its centre at `translate`: near the middle of each
// face φ is linear, which trilinear interpolation reproduces, so the two agree to round-off
// there. A transposed rotation, a scale applied twice or a translation before the rotation
// moves the faces by centimetres.
TEST(EolMeshDistance, PlacedBoxMatchesTheBoxShape) {
  // Half-sides exact in binary, so the box is exactly the shape.
  const double half[3] = {0.25, 0.125, 0.09375}, scale = 1.5, cell = 0.04;
  const ScratchObj scratch("box.obj");
  const std::string file = scratch.path();
  {
    std::ofstream out(file);
    for (int k = 0; k < 8; ++k)
      out << "v " << (k & 1 ? half[0] : -half[0]) << ' ' << (k & 2 ? half[1] : -half[1]) << ' '
          << (k & 4 ? half[2] : -half[2]) << '\n';
    // Corners numbered 1 + (x + 2y + 4z); each face counter-clockwise from outside.
    out << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  }
  ShapeDesc mesh = mesh_shape(file, scale, {0.6, 0.5, 0.4});
  mesh.rotation_axis = {1, 2, 3};
  mesh.rotation_degrees = 30;
  ShapeDesc box;
  box.type = ShapeType::box;
  box.center = mesh.translate;
  for (int a = 0; a < 3; ++a) {
    box.min[std::size_t(a)] = box.center[std::size_t(a)] - scale * half[a];
    box.max[std::size_t(a)] = box.center[std::size_t(a)] + scale * half[a];
  }
  box.rotation_axis = mesh.rotation_axis;
  box.rotation_degrees = mesh.rotation_degrees;
  const eol::MeshDistance phi(load_obj_mesh(file), mesh, cell);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d centre(0.6, 0.5, 0.4);
  double worst = 0;
  int points = 0;
  for (int a = 0; a < 3; ++a)
    for (int side : {-1, 1})
      for (double t = -0.5 * cell; t <= 0.5 * cell; t += 0.1 * cell)
        for (double u : {-0.02, 0.0, 0.015})
          for (double w : {-0.01, 0.0, 0.01}) {
            Eigen::Vector3d local = Eigen::Vector3d::Zero();
            local[a] = side * (scale * half[a] + t);
            local[(a + 1) % 3] = u;
            local[(a + 2) % 3] = w;
            const Eigen::Vector3d x = centre + R * local;
            const Vec3d xv{x[0], x[1], x[2]};
            worst = std::max(worst, std::abs(phi(xv) - eol::rest_distance(box, xv, 3)));
            ++points;
          }
  EXPECT_EQ(points, 2 * 3 * 11 * 9);
  EXPECT_LT(worst, 1e-12) << "points " << points;
  std::printf("[eol mesh] placed box: max |phi_mesh - phi_box| = %.2g over %d points\n", worst,
              points);
  EXPECT_LT(phi({0.6, 0.5, 0.4}), -0.1);  // the centre: deep inside (true -0.14)
}

// The lumped mass of an icosphere rest shape (sim/eol, eq 6 with J̄ = 1 at rest) against
// ρ₀ × the OBJ's volume. The fill fades linearly across |φ| < h/2; the fade's error is odd in φ,
// so over a surface of area A and mean curvature H it leaves ρ₀ H A h²/12 (the level sets' area
// grows as A(1 + 2Hφ)); the sampled φ adds at most ρ₀ A × (interpolation bound). The bound is
// their sum doubled for the cell quadrature of the kinked fill; the mass must also match the
// analytic ball's in the same grid to ρ₀ A (δ + interpolation), the fill being 1/h-Lipschitz in φ
// over a band of width h.
TEST(EolMeshDistance, MassOfAMeshRestShapeIsRhoTimesTheObjVolume) {
  const double r = 0.25, h = 1.0 / 24, rho = 3;
  const ObjMesh unit = icosphere(3);
  const ScratchObj scratch("icosphere3-mass.obj");
  const std::string file = scratch.path();
  write_obj(unit, file);
  test::EolSceneSpec spec;
  spec.dim = 3;
  spec.dx = h;
  spec.radius = r;
  spec.rho = rho;
  const double ball_mass = test::make_eol<3>(spec)->total_mass();
  nlohmann::json scene = nlohmann::json::parse(test::eol_scene_json(spec));
  scene["objects"][0]["shape"] = {
      {"type", "mesh"}, {"file", file}, {"scale", r}, {"translate", spec.center}};
  std::unique_ptr<Simulation> sim = make_simulation(parse_scene_text(scene.dump(), "mesh.json"));
  const double mass = dynamic_cast<eol::EolSimulation<double, 3>&>(*sim).total_mass();
  const double volume = unit.volume() * r * r * r, area = 4 * M_PI * r * r;
  const double s = 0.5 * h, interpolation = 3 * s * s / (8 * (r - 0.5 * h - std::sqrt(3.0) * s));
  const double bound = 2 * rho * (area * h * h / (12 * r) + area * interpolation);
  const double eps = sagitta(unit, r) + interpolation;
  EXPECT_NEAR(mass, rho * volume, bound) << "relative " << mass / (rho * volume) - 1;
  std::printf(
      "[eol mesh] icosphere mass / (rho V_obj) - 1 = %.3g (bound %.3g); vs the ball's "
      "mass %.3g (bound %.3g)\n",
      mass / (rho * volume) - 1, bound / (rho * volume), mass / ball_mass - 1,
      rho * area * eps * (1 + 2 * eps / h) / ball_mass);
  EXPECT_NEAR(mass, ball_mass, rho * area * eps * (1 + 2 * eps / h));
}

// One scene, two solver families: the MPM sampler's particles and the EoL grid's mass put the
// same off-centre, scaled, turned box OBJ in the same place, at the analytic centroid
// R (scale c_OBJ) + translate (the sampling lattice and the fade are symmetric about it to a
// fraction of a cell: tolerance Δx/4). Turning about the OBJ's box centre instead of its origin
// moves it by 0.1 m.
TEST(EolMeshDistance, MpmAndEolPlaceAMeshAlike) {
  const ScratchObj scratch("offset-box.obj");
  {
    std::ofstream out(scratch.path());
    for (int k = 0; k < 8; ++k)
      out << "v " << (k & 1 ? 0.35 : 0.1) << ' ' << (k & 2 ? 0.2 : 0.0) << ' '
          << (k & 4 ? 0.15 : 0.0) << '\n';
    out << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  }
  test::EolSceneSpec spec;
  spec.dim = 3;
  nlohmann::json scene = nlohmann::json::parse(test::eol_scene_json(spec));
  scene["objects"][0]["shape"] = {{"type", "mesh"},
                                  {"file", scratch.path()},
                                  {"scale", 1.2},
                                  {"translate", {0.45, 0.45, 0.45}},
                                  {"rotation", {{"axis", {0, 1, 1}}, {"degrees", 50}}}};
  const SceneDesc eol_scene = parse_scene_text(scene.dump(), "mesh.json");
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(50 * M_PI / 180, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  const Eigen::Vector3d expected =
      R * (1.2 * Eigen::Vector3d(0.225, 0.1, 0.075)) + Eigen::Vector3d(0.45, 0.45, 0.45);
  // EoL: Σ m x / Σ m over the grid at t = 0.
  std::unique_ptr<Simulation> sim = make_simulation(eol_scene);
  const auto& eol = dynamic_cast<eol::EolSimulation<double, 3>&>(*sim);
  Eigen::Vector3d eol_centre = Eigen::Vector3d::Zero();
  double mass = 0;
  for (const auto& o : eol.objects())
    for (std::size_t i = 0; i < o.grid.size(); ++i) {
      eol_centre += o.grid.mass[i] * o.x[i];
      mass += o.grid.mass[i];
    }
  eol_centre /= mass;
  // MPM: the particles' volume-weighted centre.
  scene["solver"] = {{"method", "mpm"}};
  const SampledParticles mpm = sample_object(parse_scene_text(scene.dump(), "mesh.json"), 0);
  Eigen::Vector3d mpm_centre = Eigen::Vector3d::Zero();
  double volume = 0;
  for (std::size_t p = 0; p < mpm.positions.size(); ++p) {
    mpm_centre += mpm.volumes[p] *
                  Eigen::Vector3d(mpm.positions[p][0], mpm.positions[p][1], mpm.positions[p][2]);
    volume += mpm.volumes[p];
  }
  mpm_centre /= volume;
  EXPECT_LT((eol_centre - expected).norm(), 0.25 * spec.dx) << eol_centre.transpose();
  EXPECT_LT((mpm_centre - expected).norm(), 0.25 * spec.dx) << mpm_centre.transpose();
  std::printf("[eol mesh] centroid off the analytic one: EoL %.2g m, MPM %.2g m (dx %.3g)\n",
              (eol_centre - expected).norm(), (mpm_centre - expected).norm(), spec.dx);
}

}  // namespace
}  // namespace apiclab
