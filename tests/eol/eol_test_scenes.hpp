// Small Eulerian-on-Lagrangian scenes for the tests (sim/eol/): one object in an otherwise empty
// world, given as JSON so every test goes through the scene reader and the method registry.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/eol/eol_simulation.hpp"
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

}  // namespace apiclab::test
