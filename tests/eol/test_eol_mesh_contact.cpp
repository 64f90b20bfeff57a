// A mesh rest shape under the surface contact rows (Fan et al. 2013, Sec 3.5): its triangles are
// split to the grid's cell (rest_surface.hpp), so a rod pressing between the OBJ's vertices
// meets it with rows over its footprint, and a cylinder dropped on the floor gets rows and stops.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "sim/eol/contact/body_contact.hpp"
#include "sim/eol/eol_simulation.hpp"
#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"

namespace apiclab {
namespace {

// The cylinder OBJ this repository first shipped (radius 1, x from −2 to 2, a 32-gon of sides
// 4 long, fan caps: 66 vertices, 128 triangles), written into a folder of this process's own.
struct CoarseCylinder {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("apiclab_mesh_contact_" + std::to_string(::getpid()));
  std::filesystem::path file = dir / "cylinder.obj";
  CoarseCylinder() {
    std::filesystem::create_directories(dir);
    std::ofstream out(file);
    out.precision(17);
    const int n = 32;
    for (double x : {-2.0, 2.0})
      for (int k = 0; k < n; ++k)
        out << "v " << x << ' ' << std::cos(2 * M_PI * k / n) << ' ' << std::sin(2 * M_PI * k / n)
            << '\n';
    out << "v -2 0 0\nv 2 0 0\n";
    for (int k = 0; k < n; ++k) {
      const int a = k + 1, b = (k + 1) % n + 1;  // OBJ numbers from 1
      out << "f " << a << ' ' << b << ' ' << b + n << "\nf " << a << ' ' << b + n << ' ' << a + n
          << '\n';
      out << "f " << 2 * n + 1 << ' ' << b << ' ' << a << "\nf " << 2 * n + 2 << ' ' << a + n << ' '
          << b + n << '\n';
    }
  }
  ~CoarseCylinder() {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
};

// One cylinder (r = 0.1, length 0.4, along x) of `file` lying on the floor y = 0 with its bottom
// `lift` above it; colliders and material as given.
nlohmann::json cylinder_scene(const std::string& file, double dx, double lift,
                              const nlohmann::json& colliders, const nlohmann::json& material) {
  return {{"name", "mesh-contact"},
          {"dim", 3},
          {"domain",
           {{"min", {0, 0, 0}}, {"max", {1, 0.5, 0.6}}, {"dx", dx}, {"boundary", "separate"}}},
          {"gravity", {0, -9.8, 0}},
          {"time", {{"end", 1}, {"fps", 24}, {"dt", {{"rule", "elastic"}, {"nu", 0.3}}}}},
          {"solver", {{"method", "eol"}, {"contact", "surface"}}},
          {"materials", {material}},
          {"objects",
           {{{"shape",
              {{"type", "mesh"},
               {"file", file},
               {"scale", 0.1},
               {"translate", {0.5, 0.1 + lift, 0.3}}}},
             {"material", 0}}}},
          {"colliders", colliders}};
}

const nlohmann::json kJelly = {{"name", "jelly"}, {"model", "neo-hookean"},
                               {"E", 2000},       {"nu", 0.3},
                               {"rho", 1},        {"viscosity", 0.2}};

// The old OBJ's sides are 16 cells long at Δx = 0.025: split, every edge is at most Δx
// and the surface keeps the OBJ's area and volume (the midpoints of flat triangles lie on them).
// A rod across the cylinder's middle, 0.01 m into its top and between the OBJ's vertices, gives
// rows whose patch Σ w |n·N| is the area of the cylinder's surface inside the rod, computed here
// by quadrature; with the OBJ's own triangles (no vertex inside the rod) it gave no row.
TEST(EolMeshContact, ARodBetweenTheObjVerticesMeetsTheSplitMesh) {
  const CoarseCylinder obj;
  const double dx = 0.025, r = 0.1, rod_r = 0.03, rod_y = 0.2 + rod_r - 0.01;
  const nlohmann::json rod = {{"type", "rod"},          {"center", {0.5, rod_y, 0.3}},
                              {"length", 0.3},          {"radius", rod_r},
                              {"axis", {0, 1, 0}},      {"degrees", 90},
                              {"condition", "separate"}};
  auto sim = make_simulation(parse_scene_text(
      cylinder_scene(obj.file.string(), dx, 0, nlohmann::json::array({rod}), kJelly).dump(),
      "mesh-contact.json"));
  auto& e = dynamic_cast<eol::EolSimulation<double, 3>&>(*sim);
  e.place_surfaces();
  auto& o = e.objects()[0];
  const auto& X = o.surface.X;
  const auto& tri = o.surface.simplex;
  double longest = 0, area = 0, volume = 0;
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (std::size_t t = 0; t < tri.size(); t += 3) {
    const Vec<double, 3> a = X[tri[t]], b = X[tri[t + 1]], c = X[tri[t + 2]];
    longest = std::max({longest, (b - a).norm(), (c - b).norm(), (a - c).norm()});
    area += 0.5 * (b - a).cross(Vec<double, 3>(c - a)).norm();
    volume += a.dot(b.cross(c)) / 6;
    for (int k = 0; k < 3; ++k)
      ++edges[{tri[t + std::size_t(k)], tri[t + std::size_t((k + 1) % 3)]}];
  }
  int open = 0;
  for (const auto& [edge, count] : edges)
    open += count != 1 || edges.count({edge.second, edge.first}) != 1;
  // The 32-gon's area and volume at scale 0.1: sides 32 × 0.4 × chord, caps 2 × 16 sin(2π/32) r².
  const double chord = 2 * r * std::sin(M_PI / 32), cap = 16 * std::sin(2 * M_PI / 32) * r * r;
  EXPECT_LE(longest, dx);
  EXPECT_EQ(open, 0);
  EXPECT_NEAR(area, 32 * 0.4 * chord + 2 * cap, 1e-12);
  EXPECT_NEAR(volume, 0.4 * cap, 1e-12);

  std::vector<ColliderPose> poses;
  eol::place_bodies(eol::scene_bodies(e.scene()), 3, 0.0, poses);
  const auto patch = [&](const std::vector<Vec<double, 3>>& y,
                         const std::vector<std::uint32_t>& s) {
    eol::ContactRows<double, 3> rows;
    eol::assemble_body_rows(o.grid, y, s, o.frame.rotation(), o.frame.p, poses, dx, 0u, rows);
    double sum = 0;  // Σ over entries of |coeff| = Σ_q w_q |n·N| (Σ_s Φ_s = 1)
    for (const auto& c : rows.coeff) sum += c.norm();
    return std::pair{rows.rows(), sum};
  };
  const auto [rows, footprint] = patch(o.surface_y, tri);
  // The exact footprint: points (x, 0.1 + r cos θ, 0.3 + r sin θ) within rod_r of the rod's axis.
  double exact = 0;
  const int nx = 2000, nt = 2000;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nt; ++j) {
      const double x = 0.5 - rod_r + 2 * rod_r * (i + 0.5) / nx, th = -0.5 + (j + 0.5) / nt;
      const double dy = 0.1 + r * std::cos(th) - rod_y;
      if ((x - 0.5) * (x - 0.5) + dy * dy <= rod_r * rod_r) exact += (2 * rod_r / nx) * r / nt;
    }
  // The OBJ's own triangles, placed as the object is at rest (x = y + p, frame unturned).
  std::vector<Vec<double, 3>> y_obj;
  std::vector<std::uint32_t> tri_obj;
  {
    std::ifstream in(obj.file);
    std::string tag;
    while (in >> tag) {
      if (tag == "v") {
        Vec<double, 3> v;
        in >> v[0] >> v[1] >> v[2];
        y_obj.push_back(Vec<double, 3>(0.1 * v + Vec<double, 3>(0.5, 0.1, 0.3) - o.frame.p));
      } else {
        for (int k = 0; k < 3; ++k) {
          std::uint32_t i;
          in >> i;
          tri_obj.push_back(i - 1);
        }
      }
    }
  }
  const auto [rows_obj, footprint_obj] = patch(y_obj, tri_obj);
  std::printf(
      "[eol mesh contact] split mesh: %zu triangles, longest edge %.4f m (dx %.3f); rod rows %zu, "
      "patch %.3e m^2 against the exact footprint %.3e m^2; the OBJ's own %zu triangles: %zu "
      "rows, patch %.3e m^2\n",
      tri.size() / 3, longest, dx, rows, footprint, exact, tri_obj.size() / 3, rows_obj,
      footprint_obj);
  EXPECT_GT(rows, 0u);
  EXPECT_NEAR(footprint, exact, 0.25 * exact);
}

// The shipped cylinder.obj (jelly, η = 0.2 Pa s) dropped 0.02 m onto the floor at Δx = 0.05 under
// the surface rows: rows on the steps it touches, no vertex deeper than 0.1 Δx below the floor,
// and over its last 0.2 s of 1.5 s a kinetic energy under 1 % of the m g h the fall released
// (it bounces and rocks for about a second), its centre within 0.1 Δx of its height at rest
// (r = 0.1, less the sag). Full tier: 5,200 steps, about 14 CPU-s.
TEST(EolMeshContactFull, ACylinderDroppedOnTheFloorGetsRowsAndStops) {
  const double dx = 0.05, lift = 0.02;
  const std::string file = std::string(APICLAB_SOURCE_DIR) + "/assets/meshes/cylinder.obj";
  auto sim = make_simulation(parse_scene_text(
      cylinder_scene(file, dx, lift, nlohmann::json::array(), kJelly).dump(), "mesh-contact.json"));
  auto& e = dynamic_cast<eol::EolSimulation<double, 3>&>(*sim);
  const auto centre_y = [&]() {
    double my = 0, m = 0;
    for (const auto& o : e.objects())
      for (std::size_t i = 0; i < o.grid.size(); ++i) {
        my += o.grid.mass[i] * o.x[i][1];
        m += o.grid.mass[i];
      }
    return std::pair{my / m, m};
  };
  const auto [y0, mass] = centre_y();
  std::size_t most_rows = 0, contact_steps = 0, steps = 0;
  double depth = 0, kinetic = 0;
  const double end = 1.5;
  while (sim->time() < end) {
    ASSERT_FALSE(sim->step(end));
    ++steps;
    if (sim->time() > end - 0.2) kinetic = std::max(kinetic, sim->measure().kinetic);
    const std::size_t rows = e.last_contact_rows().rows();
    if (rows == 0) continue;
    ++contact_steps;
    most_rows = std::max(most_rows, rows);
    for (const auto& o : e.objects())  // placed on the steps with rows
      for (std::size_t k = 0; k < o.surface_y.size(); ++k)
        depth = std::max(depth, -o.surface_world(k)[1]);
  }
  const double released = mass * 9.8 * lift;
  const double rest = centre_y().first;
  std::printf(
      "[eol mesh contact] cylinder dropped %.2f m (dx %.2f): %zu steps, %zu with rows (at most "
      "%zu), deepest vertex %.2e m below the floor; kinetic at most %.2e J over the last 0.2 s "
      "of 1.5 s, of %.2e J released; "
      "centre at %.4f m (start %.4f)\n",
      lift, dx, steps, contact_steps, most_rows, depth, kinetic, released, rest, y0);
  EXPECT_GT(contact_steps, 0u);
  EXPECT_LT(depth, 0.1 * dx);
  EXPECT_LT(kinetic, 0.01 * released);
  EXPECT_NEAR(rest, 0.1, 0.1 * dx);
}

}  // namespace
}  // namespace apiclab
