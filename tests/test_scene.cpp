// Scene parsing: every shipped scene loads; bad input gives one SceneError line that names the
// file and the offending key (DESIGN.md, Scenes and Command line).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/mpm.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"

namespace apiclab {
namespace {

const std::string kGood = R"({
  "name": "good", "dim": 2,
  "domain": {"min": [0, 0], "max": [1, 1], "dx": 0.05, "boundary": "slip"},
  "gravity": [0, -9.8],
  "time": {"end": 1.0, "fps": 24, "dt": {"rule": "elastic", "nu": 0.3}},
  "solver": {"scheme": "apic", "kernel": "quadratic", "integrator": "symplectic"},
  "materials": [{"name": "jelly", "model": "neo-hookean", "E": 1000, "nu": 0.3, "rho": 2}],
  "objects": [{"name": "disk", "shape": {"type": "ball", "center": [0.5, 0.5], "radius": 0.2},
               "material": "jelly", "sampling": {"type": "ppc", "ppc": 4}, "velocity": [0.1, 0]}]
})";

// Runs `fn`, expects a SceneError whose message is one line and contains every needle.
template <class Fn>
void expect_scene_error(Fn&& fn, const std::vector<std::string>& needles, const std::string& what) {
  SCOPED_TRACE(what);
  try {
    fn();
    ADD_FAILURE() << "no error for " << what;
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
    EXPECT_FALSE(msg.empty());
    for (const auto& n : needles) EXPECT_NE(msg.find(n), std::string::npos) << "'" << n << "' not in: " << msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type for " << what << ": " << e.what();
  }
}

// kGood with one JSON-pointer edit applied (value null removes the key).
std::string edited(const std::string& pointer, const nlohmann::json& value, bool remove = false) {
  nlohmann::json j = nlohmann::json::parse(kGood);
  if (remove)
    j.at(nlohmann::json::json_pointer(pointer.substr(0, pointer.rfind('/'))))
        .erase(pointer.substr(pointer.rfind('/') + 1));
  else
    j[nlohmann::json::json_pointer(pointer)] = value;
  return j.dump();
}

void bad(const std::string& pointer, const nlohmann::json& value, const std::string& key) {
  expect_scene_error([&] { parse_scene_text(edited(pointer, value), "bad.json"); }, {"bad.json", "'" + key + "'"},
                     pointer + " = " + value.dump());
}

TEST(Scene, GoodSceneParses) {
  SceneDesc s = parse_scene_text(kGood, "good.json");
  EXPECT_EQ(s.name, "good");
  EXPECT_EQ(s.dim, 2);
  EXPECT_EQ(s.solver.scheme, Scheme::apic);
  EXPECT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].E, 1000.0);
  EXPECT_EQ(s.objects[0].material, 0);
  EXPECT_EQ(s.gravity[1], -9.8);
}

TEST(Scene, SetOverrides) {
  SceneDesc s = parse_scene_text(kGood, "good.json", {"materials.0.E=2000", "solver.scheme=pic", "time.end=0.5"});
  EXPECT_EQ(s.materials[0].E, 2000.0);
  EXPECT_EQ(s.solver.scheme, Scheme::pic);
  EXPECT_EQ(s.time.end, 0.5);
}

TEST(Scene, ShippedScenesLoadAndBuild) {
  namespace fs = std::filesystem;
  int count = 0;
  for (const auto& e : fs::directory_iterator(fs::path(APICLAB_SOURCE_DIR) / "assets" / "scenes")) {
    if (e.path().extension() != ".json") continue;
    SCOPED_TRACE(e.path().string());
    SceneDesc s;
    ASSERT_NO_THROW(s = load_scene(e.path().string()));
    EXPECT_EQ(s.name, e.path().stem().string());
    ++count;
  }
  EXPECT_GE(count, 1);
  // The scene the conservation tests use builds particles.
  auto sim = make_simulation(load_scene(std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json"));
  EXPECT_GT(particle_count(*sim), 1000u);
}

TEST(Scene, MissingFile) {
  expect_scene_error([] { load_scene("/nonexistent/dir/nope.json"); }, {"/nonexistent/dir/nope.json"}, "missing file");
}

TEST(Scene, MalformedJson) {
  expect_scene_error([] { parse_scene_text("{\"dim\": 2,\n \"domain\": {", "broken.json"); }, {"broken.json", "JSON"},
                     "truncated");
  expect_scene_error([] { parse_scene_text("{\"dim\": 2,, }", "broken.json"); }, {"broken.json"}, "double comma");
  expect_scene_error([] { parse_scene_text("", "empty.json"); }, {"empty.json"}, "empty");
  expect_scene_error([] { parse_scene_text("[1, 2]", "array.json"); }, {"array.json"}, "top level not an object");
}

TEST(Scene, UnknownKeys) {
  bad("/gravty", {0, -1}, "gravty");                            // top level, misspelled
  bad("/materials/0/Ee", 1000, "materials.0.Ee");              // nested, misspelled
  bad("/domain/dxx", 0.1, "domain.dxx");
  bad("/solver/shceme", "apic", "solver.shceme");
  bad("/objects/0/shape/radus", 0.1, "objects.0.shape.radus");
  bad("/objects/0/sampling/pcc", 4, "objects.0.sampling.pcc");
  bad("/time/dt/nuu", 0.3, "time.dt.nuu");
}

TEST(Scene, UnknownChoices) {
  bad("/solver/scheme", "apicc", "solver.scheme");
  bad("/solver/kernel", "quintic", "solver.kernel");
  bad("/solver/integrator", "rk4", "solver.integrator");
  bad("/materials/0/model", "mooney-rivlin", "materials.0.model");
  bad("/objects/0/shape/type", "blob", "objects.0.shape.type");
  bad("/objects/0/sampling/type", "random", "objects.0.sampling.type");
  bad("/domain/boundary", "bouncy", "domain.boundary");
  bad("/domain/boundary", nlohmann::json{{"x-", "slip"}, {"x+", "glue"}}, "domain.boundary.x+");
  bad("/time/dt/rule", "adaptive", "time.dt.rule");
}

TEST(Scene, InvalidValues) {
  bad("/domain/dx", 0, "domain.dx");
  bad("/domain/dx", -0.1, "domain.dx");
  bad("/materials/0/rho", 0, "materials.0.rho");
  bad("/materials/0/rho", -2, "materials.0.rho");
  bad("/materials/0/E", 0, "materials.0.E");
  bad("/materials/0/E", -1000, "materials.0.E");
  bad("/materials/0/nu", 0.5, "materials.0.nu");
  bad("/materials/0/nu", 0.7, "materials.0.nu");
  bad("/materials/0/nu", -1, "materials.0.nu");
  bad("/materials/0/nu", -1.5, "materials.0.nu");
  bad("/materials/0/E", "stiff", "materials.0.E");
  bad("/dim", 4, "dim");
  bad("/domain/max", {1}, "domain.max");
  bad("/objects/0/material", "steel", "objects.0.material");
  bad("/objects/0/material", 3, "objects.0.material");
  bad("/solver/flip_alpha", 1.5, "solver.flip_alpha");
  bad("/objects/0/shape/radius", -0.1, "objects.0.shape.radius");
  bad("/materials", nlohmann::json::array(), "materials");
  // Required keys.
  expect_scene_error([] { parse_scene_text(edited("/materials/0/E", 0, true), "bad.json"); },
                     {"bad.json", "'materials.0.E'"}, "missing E");
  expect_scene_error([] { parse_scene_text(edited("/domain", 0, true), "bad.json"); }, {"bad.json", "'domain'"},
                     "missing domain");
}

TEST(Scene, ObjectOutsideDomain) {
  bad("/objects/0/shape/center", {0.9, 0.5}, "objects.0.shape");  // radius 0.2 reaches x = 1.1
  bad("/objects/0/shape", nlohmann::json{{"type", "box"}, {"min", {-0.1, 0.2}}, {"max", {0.5, 0.5}}},
      "objects.0.shape");
}

TEST(Scene, SetOnMissingKey) {
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"solver.nope.x=1"}); }, {"good.json", "solver.nope"},
                     "--set solver.nope.x");
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"materials.5.E=1"}); }, {"good.json", "materials.5"},
                     "--set materials.5.E");
  // A new last key reaches the strict parser, which names it.
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"solver.nope=1"}); }, {"good.json", "'solver.nope'"},
                     "--set solver.nope");
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"materials.0.E=-5"}); },
                     {"good.json", "'materials.0.E'"}, "--set negative E");
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"noequals"}); }, {"good.json", "noequals"},
                     "--set without =");
}

TEST(Scene, LoadSceneFromFileNamesFile) {
  namespace fs = std::filesystem;
  fs::path dir = fs::temp_directory_path() / ("apiclab-test-scene-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::path f = dir / "typo.json";
  {
    std::ofstream out(f);
    out << edited("/materials/0/Ee", 5);
  }
  expect_scene_error([&] { load_scene(f.string()); }, {f.string(), "'materials.0.Ee'"}, "file with typo");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace apiclab
