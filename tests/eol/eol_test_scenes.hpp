// Small Eulerian-on-Lagrangian scenes for the tests (sim/eol/): one object in an otherwise empty
// world, given as JSON so every test goes through the scene reader and the method registry; and
// placed balls without a scene for the contact rows' tests.
#pragma once
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/eol/eol_simulation.hpp"
#include "sim/eol/surface/rest_surface.hpp"
#include "sim/eol/surface/surface_placement.hpp"
#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"

namespace apiclab::test {

struct EolSceneSpec {
  int dim = 2;
  std::string method = "eol";
  std::vector<double> domain_max = {1, 1, 1};
  double dx = 1.0 / 32;
  std::vector<double> center = {0.5, 0.5, 0.5};
  double radius = 0.15;
  std::vector<double> velocity = {0, 0, 0};
  double spin = 0;  // about z (2D) or the z axis (3D)
  std::vector<double> gravity = {0, 0, 0};
  double E = 1000, rho = 1;
  std::string boundary = "slip";
  double end = 1, fps = 10;
  nlohmann::json colliders = nlohmann::json::array();
  std::string contact;  // solver.contact; empty: the default
};

inline std::string eol_scene_json(const EolSceneSpec& s) {
  const auto take = [&](const std::vector<double>& v) {
    return std::vector<double>(v.begin(), v.begin() + s.dim);
  };
  nlohmann::json object = {
      {"shape", {{"type", "ball"}, {"center", take(s.center)}, {"radius", s.radius}}},
      {"material", 0},
      {"velocity", take(s.velocity)}};
  if (s.spin != 0) {
    if (s.dim == 2)
      object["angular_velocity"] = s.spin;
    else
      object["angular_velocity"] = {0, 0, s.spin};
  }
  nlohmann::json solver = {{"method", s.method}};
  if (!s.contact.empty()) solver["contact"] = s.contact;
  const nlohmann::json scene = {
      {"name", "eol-test"},
      {"dim", s.dim},
      {"domain",
       {{"min", std::vector<double>(std::size_t(s.dim), 0.0)},
        {"max", take(s.domain_max)},
        {"dx", s.dx},
        {"boundary", s.boundary}}},
      {"gravity", take(s.gravity)},
      {"time", {{"end", s.end}, {"fps", s.fps}, {"dt", {{"rule", "elastic"}, {"nu", 0.3}}}}},
      {"solver", solver},
      {"materials",
       {{{"name", "jelly"}, {"model", "neo-hookean"}, {"E", s.E}, {"nu", 0.3}, {"rho", s.rho}}}},
      {"objects", {object}},
      {"colliders", s.colliders}};
  return scene.dump();
}

template <int D>
std::unique_ptr<eol::EolSimulation<double, D>> make_eol(const EolSceneSpec& spec) {
  SceneDesc scene = parse_scene_text(eol_scene_json(spec), "eol-test.json");
  std::unique_ptr<Simulation> sim = make_simulation(scene);
  auto* eol = dynamic_cast<eol::EolSimulation<double, D>*>(sim.get());
  if (!eol) return nullptr;
  sim.release();
  return std::unique_ptr<eol::EolSimulation<double, D>>(eol);
}

// An object built without a scene, for the contact rows' tests: a grid (cell dx) whose
// reference map is a fixed affine X = G y, a ball's rest surface placed on it (Algorithm 2),
// and a rigid frame x = R y + p.
template <int D>
struct PlacedBall {
  eol::EulerianGrid<double, D> grid;
  eol::RestSurface<D> surface;
  std::vector<Vec<double, D>> y;
  Mat<double, D> R = Mat<double, D>::Identity();
  Vec<double, D> p = Vec<double, D>::Zero();
  eol::ContactObject<double, D> object(std::uint32_t offset) const {
    eol::ContactObject<double, D> o;
    o.grid = &grid;
    o.y = &y;
    o.simplex = &surface.simplex;
    o.R = R;
    o.p = p;
    o.node_offset = offset;
    return o;
  }
  Vec<double, D> world(std::size_t k) const { return R * y[k] + p; }
};

// A ball of radius r (material centre 0, its surface's cell `surface_h`) on a grid of cell dx
// reaching 1.2 r + 2 dx each side, every node of mass 1, placed at world `centre` turned by R.
template <int D>
std::unique_ptr<PlacedBall<D>> make_placed_ball(double r, double dx, double surface_h,
                                                const Vec<double, D>& centre,
                                                const Mat<double, D>& R, const Mat<double, D>& G) {
  auto b = std::make_unique<PlacedBall<D>>();
  ShapeDesc shape;
  shape.type = ShapeType::ball;
  shape.radius = r;
  eol::append_rest_surface<D>(shape, 0, surface_h, b->surface);
  const double half = 1.2 * r + 2 * dx;
  const int n = int(std::ceil(2 * half / dx)) + 1;
  b->grid.dx = dx;
  b->grid.origin = Vec<double, D>::Constant(-half);
  std::array<int, D> size;
  size.fill(n);
  b->grid.resize(size);
  for (std::size_t i = 0; i < b->grid.size(); ++i) {
    b->grid.X[i] = G * b->grid.y(i);
    b->grid.mass[i] = 1.0;
  }
  b->y = b->surface.X;  // the first guess of Algorithm 2
  EXPECT_EQ(eol::place_surface(b->grid, b->surface.X, b->y, false), 0);
  b->R = R;
  b->p = centre;
  return b;
}

}  // namespace apiclab::test
