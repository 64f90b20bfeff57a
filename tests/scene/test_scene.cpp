// Scene parsing: every shipped scene loads; bad input gives one SceneError line that names the
// file and the offending key (docs/architecture.md, Scenes and Command line); the numeric-parameter
// registry and the GUI's edit path, which must refuse what the reader refuses.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "sim/geometry/obj_mesh.hpp"
#include "sim/geometry/object_overlap.hpp"
#include "sim/mpm/mpm.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"
#include "sim/scene/choice_parameters.hpp"
#include "sim/scene/parameters.hpp"
#include "sim/scene/scene.hpp"
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

// kGood for the Eulerian-on-Lagrangian methods (the keys of their own solver section).
const std::string kGoodEol = [] {
  nlohmann::json j = nlohmann::json::parse(kGood);
  j["solver"] = {{"method", "eol"}};
  return j.dump();
}();

// kGood with the lambda integrator, the one that takes solver.lambda.
const std::string kGoodLambda = [] {
  nlohmann::json j = nlohmann::json::parse(kGood);
  j["solver"]["integrator"] = "lambda";
  j["solver"]["lambda"] = 0.25;
  return j.dump();
}();

// kGood with the plastic model, the one that takes materials.*.yield_stress and flow_rate.
const std::string kGoodPlastic = [] {
  nlohmann::json j = nlohmann::json::parse(kGood);
  j["materials"][0]["model"] = "plastic";
  j["materials"][0]["yield_stress"] = 50;
  return j.dump();
}();

// The scene text whose solver section (or material) takes p's key.
const std::string& good_text_for(const NumericParameter& p) {
  if (p.key == "solver.lambda") return kGoodLambda;
  if (p.key == "materials.*.yield_stress" || p.key == "materials.*.flow_rate") return kGoodPlastic;
  return p.read_by("mpm") ? kGood : kGoodEol;
}

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
    for (const auto& n : needles)
      EXPECT_NE(msg.find(n), std::string::npos) << "'" << n << "' not in: " << msg;
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
  expect_scene_error([&] { parse_scene_text(edited(pointer, value), "bad.json"); },
                     {"bad.json", "'" + key + "'"}, pointer + " = " + value.dump());
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
  SceneDesc s = parse_scene_text(kGood, "good.json",
                                 {"materials.0.E=2000", "solver.scheme=pic", "time.end=0.5"});
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
  auto sim = make_simulation(
      load_scene(std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json"));
  EXPECT_GT(particle_count(*sim), 1000u);
}

TEST(Scene, MissingFile) {
  expect_scene_error([] { load_scene("/nonexistent/dir/nope.json"); },
                     {"/nonexistent/dir/nope.json"}, "missing file");
}

TEST(Scene, MalformedJson) {
  expect_scene_error([] { parse_scene_text("{\"dim\": 2,\n \"domain\": {", "broken.json"); },
                     {"broken.json", "JSON"}, "truncated");
  expect_scene_error([] { parse_scene_text("{\"dim\": 2,, }", "broken.json"); }, {"broken.json"},
                     "double comma");
  expect_scene_error([] { parse_scene_text("", "empty.json"); }, {"empty.json"}, "empty");
  expect_scene_error([] { parse_scene_text("[1, 2]", "array.json"); }, {"array.json"},
                     "top level not an object");
  // Fuzz finding 2 (tests/fuzz_regressions/*/deep-nesting*): 100,000 nested arrays overflowed
  // the stack when the value was dumped into the message; the reader stops at 64 levels.
  const std::string deep = "{\"dim\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  expect_scene_error([&] { parse_scene_text(deep, "deep.json"); }, {"deep.json", "64 levels"},
                     "deep nesting");
  // A long value is quoted cut short: the message stays one readable line.
  std::string ones;
  for (int i = 0; i < 50000; ++i) ones += "1,";
  for (const std::string& wide :
       {"{\"dim\": [" + ones + "1]}",                    // a long array
        "{\"dim\": " + std::string(100000, '1') + "}",   // a long number
        "{\"" + std::string(100000, 'k') + "\": 1}",     // a long key
        "{\"" + std::string(100000, 'k') + "\": [}"}) {  // malformed near a long key
    try {
      parse_scene_text(wide, "wide.json");
      ADD_FAILURE() << "no error for a wide dim";
    } catch (const SceneError& e) {
      EXPECT_LT(std::string(e.what()).size(), 300u) << std::string(e.what()).substr(0, 300);
    }
  }
}

// fuzz_scene (tests/fuzz_regressions/scene/newline-in-key*.json): a key holding the
// JSON escape "\n" decodes to a line break, which the message quoted as it was, on two lines.
// Every text of the input a message quotes has its control characters escaped.
TEST(Scene, InputTextInMessagesStaysOnOneLine) {
  const std::string disk = std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json";
  expect_scene_error([] { parse_scene_text(edited("/a\nb", 1), "k.json"); }, {"'a\\nb'"},
                     "unknown key with a line break");
  expect_scene_error([] { parse_scene_text("{\"a\\nb\\tc\": [}", "k.json"); }, {"a\\nb\\tc"},
                     "malformed JSON near a key with a line break and a tab");
  expect_scene_error([&] { load_scene(disk, {"solver.scheme=\"ap\\nic\""}); }, {"ap\\nic"},
                     "a choice value with a line break");
  expect_scene_error([&] { load_scene(disk, {"name\r\x01=1"}); }, {"\\r\\x01"},
                     "a --set key with a carriage return and a control byte");
  // fuzz_scene: an unknown choice value of thousands of characters was echoed whole.
  try {
    load_scene(disk, {"solver.integrator=" + std::string(5000, 'x')});
    ADD_FAILURE() << "no error for a 5000-character integrator";
  } catch (const SceneError& e) {
    EXPECT_LT(std::string(e.what()).size(), 400u) << e.what();
    EXPECT_NE(std::string(e.what()).find("(5000 characters)"), std::string::npos) << e.what();
  }
}

TEST(Scene, UnknownKeys) {
  bad("/gravty", {0, -1}, "gravty");               // top level, misspelled
  bad("/materials/0/Ee", 1000, "materials.0.Ee");  // nested, misspelled
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
  expect_scene_error([] { parse_scene_text(edited("/domain", 0, true), "bad.json"); },
                     {"bad.json", "'domain'"}, "missing domain");
}

TEST(Scene, ObjectOutsideDomain) {
  bad("/objects/0/shape/center", {0.9, 0.5}, "objects.0.shape");  // radius 0.2 reaches x = 1.1
  bad("/objects/0/shape",
      nlohmann::json{{"type", "box"}, {"min", {-0.1, 0.2}}, {"max", {0.5, 0.5}}},
      "objects.0.shape");
}

TEST(Scene, SetOnMissingKey) {
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"solver.nope.x=1"}); },
                     {"good.json", "solver.nope"}, "--set solver.nope.x");
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"materials.5.E=1"}); },
                     {"good.json", "materials.5"}, "--set materials.5.E");
  // A new last key reaches the strict parser, which names it.
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"solver.nope=1"}); },
                     {"good.json", "'solver.nope'"}, "--set solver.nope");
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"materials.0.E=-5"}); },
                     {"good.json", "'materials.0.E'"}, "--set negative E");
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"noequals"}); },
                     {"good.json", "noequals"}, "--set without =");
}

// Each class of bad input gives one line that names the real cause.
TEST(SceneInput, DuplicateKeysAreRefusedWithTheirPath) {
  const std::string dup =
      std::string(kGood).replace(kGood.find("\"E\": 1000"), 9, "\"E\": 1000, \"E\": 2000");
  expect_scene_error([&] { parse_scene_text(dup, "dup.json"); },
                     {"dup.json", "'materials.0.E'", "twice"}, "duplicate E");
  // Nested in an array of objects: the index is part of the path.
  const std::string dup_top =
      std::string(kGood).replace(kGood.find("\"dim\": 2"), 8, "\"dim\": 2, \"dim\": 3");
  expect_scene_error([&] { parse_scene_text(dup_top, "dup.json"); }, {"'dim'", "twice"},
                     "duplicate dim");
}

TEST(SceneInput, NumbersBeyondADoubleNameTheKeyAndLine) {
  const std::string big =
      std::string(kGood).replace(kGood.find("\"dx\": 0.05"), 10, "\"dx\": 1e400");
  expect_scene_error([&] { parse_scene_text(big, "big.json"); },
                     {"big.json", "'domain.dx'", "1e400", "out of range for a double", "line 3"},
                     "1e400");
  const std::string in_array =
      std::string(kGood).replace(kGood.find("[0, -9.8]"), 9, "[0, -1e999]");
  expect_scene_error([&] { parse_scene_text(in_array, "big.json"); },
                     {"'gravity.1'", "-1e999", "out of range"}, "-1e999 in an array");
}

TEST(SceneInput, MissingRequiredKeysAreNamedInTheScenesTerms) {
  // Named references, not a structured binding: clang 14 (the fuzz and ASan builds) cannot
  // capture a binding in the lambda below.
  for (const auto& entry : std::vector<std::pair<std::string, std::string>>{
           {"/materials/0/E", "materials.0.E"},
           {"/objects/0/shape", "objects.0.shape"},
           {"/objects/0/shape/radius", "objects.0.shape.radius"},
           {"/domain/dx", "domain.dx"},
           {"/objects/0/material", "objects.0.material"}}) {
    const std::string &pointer = entry.first, &key = entry.second;
    expect_scene_error([&] { parse_scene_text(edited(pointer, nullptr, true), "m.json"); },
                       {"m.json", "'" + key + "'", "missing"}, "without " + key);
  }
}

TEST(SceneInput, WrongKindsAreRefused) {
  bad("/dim", 2.5, "dim");
  bad("/dim", 4294967298LL, "dim");  // would wrap to 2 as an int
  bad("/dim", "2", "dim");
  bad("/materials/0/E", "1000", "materials.0.E");
  bad("/materials/0/E", true, "materials.0.E");
  bad("/objects/0/sampling/ppc", 4.5, "objects.0.sampling.ppc");
  bad("/objects/0/velocity", {"fast", 0}, "objects.0.velocity");
  bad("/solver/cg_max_iterations", 2.5, "solver.cg_max_iterations");
  bad("/objects/0/material", 4294967296LL, "objects.0.material");  // would wrap to 0 as an int
  bad("/objects/0/sampling", {{"type", "poisson"}, {"radius", 0.02}, {"seed", -1}},
      "objects.0.sampling.seed");
}

TEST(SceneInput, DegenerateAxesAreRefused) {
  bad("/objects/0/shape/rotation", {{"axis", {0, 0, 0}}, {"degrees", 30}},
      "objects.0.shape.rotation.axis");
  nlohmann::json j = nlohmann::json::parse(kGood);
  j["dim"] = 3;
  j["domain"] = {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}, {"dx", 0.05}};
  j["gravity"] = {0, 0, 0};
  j["objects"][0]["velocity"] = {0, 0, 0};
  for (const std::string type : {"torus", "annulus"}) {
    j["objects"][0]["shape"] = {{"type", type},
                                {"center", {0.5, 0.5, 0.5}},
                                {"inner", 0.1},
                                {"outer", 0.2},
                                {"axis", {0, 0, 0}}};
    if (type == "annulus") j["objects"][0]["shape"]["length"] = 0.2;
    expect_scene_error([&] { parse_scene_text(j.dump(), "axis.json"); },
                       {"axis.json", "'objects.0.shape.axis'", "zero length"}, type);
  }
}

TEST(SceneInput, SetValuesThatAreNotJsonAreShown) {
  for (const std::string value : {"nan", "inf", "-Infinity", "1e400", "[1,", "{\"a\":}"})
    expect_scene_error(
        [&] { parse_scene_text(kGood, "good.json", {"objects.0.velocity=" + value}); },
        {"good.json", "--set objects.0.velocity=" + value, "'" + value + "'", "not valid JSON"},
        value);
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"materials.0.E=abc"}); },
                     {"--set materials.0.E=abc", "must be a number", "\"abc\""}, "bare word");
  // A bare word is still a string where a string goes.
  EXPECT_EQ(parse_scene_text(kGood, "good.json", {"solver.scheme=flip"}).solver.scheme,
            Scheme::flip);
}

TEST(SceneInput, ScenePathsThatAreNotRegularFiles) {
  const std::string dir = ::testing::TempDir() + "apiclab-scene-dir";
  std::filesystem::create_directories(dir);
  expect_scene_error([&] { load_scene(dir); }, {dir, "is a directory"}, "directory");
  const std::string fifo = ::testing::TempDir() + "apiclab-scene.fifo";
  std::filesystem::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  expect_scene_error([&] { load_scene(fifo); }, {fifo, "fifo"}, "fifo");  // must not block
  std::filesystem::remove(fifo);
  expect_scene_error([] { load_scene("/dev/null"); }, {"/dev/null", "character device"}, "device");
}

// A 3D scene that samples the OBJ text `obj`.
void expect_mesh_error(const std::string& obj, const std::vector<std::string>& needles,
                       const std::string& what) {
  const std::string path = ::testing::TempDir() + "apiclab-" + what + ".obj";
  std::ofstream(path) << obj;
  const std::string scene = R"({"dim": 3, "domain": {"min": [-1, -1, -1], "max": [2, 2, 2],
    "dx": 0.1}, "materials": [{"E": 1000, "nu": 0.3, "rho": 1}],
    "objects": [{"shape": {"type": "mesh", "file": ")" +
                            path + R"("}, "material": 0}]})";
  std::vector<std::string> all = needles;
  all.push_back(path);
  expect_scene_error([&] { make_simulation(parse_scene_text(scene, "mesh.json")); }, all, what);
}

TEST(SceneInput, InvalidMeshesAreReportedAsSuch) {
  const std::string v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
  expect_mesh_error(v + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 9\n",
                    {"face 4", "vertex 9", "4 vertices"}, "index");
  expect_mesh_error(v + "f 1 3 2\nf 1 2 4\nf 1 4 3\n", {"not a closed manifold"}, "open");
  expect_mesh_error(v + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nf 2 3 4\n", {"not a closed manifold"},
                    "nonmanifold");
  expect_mesh_error(v, {"no faces"}, "empty");
  expect_mesh_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n", {"no volume"}, "flat");
  // The closed tetrahedron itself is fine.
  const std::string path = ::testing::TempDir() + "apiclab-tetra.obj";
  std::ofstream(path) << v + "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const ObjMesh tetra = load_obj_mesh(path);
  EXPECT_NEAR(tetra.volume(), 1.0 / 6.0, 1e-15);
}

TEST(SceneInput, OverlappingObjectsAreReportedWithTheirParticleCounts) {
  nlohmann::json j = nlohmann::json::parse(kGood);
  // A second disk of radius 0.2 centred 0.2 away: the lens between them is inside both.
  nlohmann::json second = j["objects"][0];
  second["name"] = "other";
  second["shape"]["center"] = {0.7, 0.5};
  j["objects"].push_back(second);
  const SceneDesc s = parse_scene_text(j.dump(), "overlap.json");
  const auto warnings = object_overlaps(s);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("'disk' and 'other' overlap"), std::string::npos) << warnings[0];
  // Lens area of two unit-distance-0.2 circles of radius 0.2: 2r^2 acos(d/2r) - (d/2)
  // sqrt(4r^2 - d^2) = 0.0491; at 4 particles per cell of 0.05^2, about 79 particles.
  const auto count = std::stoi(warnings[0].substr(warnings[0].find("overlap: ") + 9));
  EXPECT_NEAR(count, 79, 10) << warnings[0];
  // Apart: nothing to report.
  j["objects"][1]["shape"]["center"] = {0.5, 0.5};
  j["objects"][0]["shape"]["radius"] = 0.05;
  j["objects"][0]["shape"]["center"] = {0.1, 0.1};
  EXPECT_TRUE(object_overlaps(parse_scene_text(j.dump(), "apart.json")).empty());
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
  expect_scene_error([&] { load_scene(f.string()); }, {f.string(), "'materials.0.Ee'"},
                     "file with typo");
  fs::remove_all(dir);
}

// ---- The numeric-parameter registry (sim/scene/parameters.hpp)
// -----------------------------------

// The message the reader gives for a value outside its range: the one format every path uses.
std::string range_message(const std::string& key, double value, const std::string& file) {
  int index = 0;
  const NumericParameter* p = find_parameter(key, &index);
  if (!p) return "no parameter " + key;
  return parameter_error(*p, index, value, file).value_or("accepted");
}

// The reader's message for kGood (or `text`) with `overrides`, or "accepted".
std::string reader_message(const std::vector<std::string>& overrides,
                           const std::string& text = kGood) {
  try {
    parse_scene_text(text, "good.json", overrides);
    return "accepted";
  } catch (const SceneError& e) {
    return e.what();
  }
}

// A value inside p's range that differs from `current` (for the --set round trip).
double another_valid_value(const NumericParameter& p, double current) {
  if (p.integer) return current + 1;
  const Range& r = p.range;
  if (std::isfinite(r.lo) && std::isfinite(r.hi)) return r.lo + 0.37 * (r.hi - r.lo);
  if (std::isfinite(r.lo)) return current > r.lo ? 2 * current : r.lo + 1;
  return current + 0.25;
}

TEST(Parameters, DeclaredOnceWithLabelUnitHelpAndDefaultInRange) {
  std::set<std::string> keys;
  for (const auto& p : numeric_parameters()) {
    SCOPED_TRACE(std::string(p.key));
    EXPECT_TRUE(keys.insert(std::string(p.key)).second) << "declared twice";
    EXPECT_FALSE(p.label.empty());
    EXPECT_FALSE(p.unit.empty());
    EXPECT_FALSE(p.help.empty());
    // A key with no default when unset (is_set and unset_default) has none to check.
    if (!p.required && !(p.is_set && !p.unset_default.empty())) {
      EXPECT_TRUE(p.range.contains(p.default_value))
          << p.default_value << " not in " << p.range.text();
    }
    int index = -1;
    EXPECT_EQ(find_parameter(p.key_at(3), &index), &p);
    EXPECT_EQ(index, p.key.find('*') == std::string_view::npos ? 0 : 3);
  }
  EXPECT_EQ(find_parameter("materials.x.E"), nullptr);
  EXPECT_EQ(find_parameter("solver.scheme"), nullptr);
  EXPECT_EQ(find_parameter("materials.0.E.x"), nullptr);
}

TEST(Parameters, EveryKeyIsReachableBySetAndReadBack) {
  for (const auto& p : numeric_parameters()) {
    const std::string key = p.key_at(0);
    SCOPED_TRACE(key);
    const std::string& text = good_text_for(p);
    const SceneDesc base = parse_scene_text(text, "good.json");
    const double value = another_valid_value(p, p.get(base, 0));
    ASSERT_NE(value, p.get(base, 0));
    SceneDesc s;
    ASSERT_NO_THROW(s = parse_scene_text(text, "good.json", {key + "=" + format_value(value)}));
    EXPECT_EQ(p.get(s, 0), value);
    // The sweep's setter gives the same scene value.
    SceneDesc applied = base;
    ASSERT_NO_THROW(apply_parameter(applied, key, value));
    EXPECT_EQ(p.get(applied, 0), value);
  }
}

TEST(Parameters, EveryRangeBoundIsRejectedOrAcceptedWithTheOneMessage) {
  int bounds = 0;
  for (const auto& p : numeric_parameters()) {
    const std::string key = p.key_at(0);
    for (const bool lower : {true, false}) {
      const double bound = lower ? p.range.lo : p.range.hi;
      if (!std::isfinite(bound)) continue;
      ++bounds;
      const bool open = lower ? p.range.lo_open : p.range.hi_open;
      const double step = p.integer ? 1 : 1e-3 * std::max(1.0, std::abs(bound));
      const double outside = bound + (lower ? -step : step);
      const double inside =
          p.integer ? bound + (lower ? 1 : -1) : std::nextafter(bound, lower ? 1e300 : -1e300);
      SCOPED_TRACE(key + (lower ? " lower bound " : " upper bound ") + format_value(bound));
      // Outside: rejected by the reader with the registry's message, naming file, key, value,
      // range.
      const std::string msg = reader_message({key + "=" + format_value(outside)}, good_text_for(p));
      EXPECT_EQ(msg, range_message(key, outside, "good.json"));
      for (const std::string& needle :
           {std::string("good.json"), "'" + key + "'", format_value(outside), p.range.text()})
        EXPECT_NE(msg.find(needle), std::string::npos) << "'" << needle << "' not in: " << msg;
      // On the bound: rejected when open, accepted when closed.
      EXPECT_EQ(reader_message({key + "=" + format_value(bound)}, good_text_for(p)),
                open ? range_message(key, bound, "good.json") : "accepted");
      EXPECT_EQ(parameter_error(p, 0, inside, "good.json"), std::nullopt) << format_value(inside);
    }
  }
  EXPECT_GE(bounds, 15);
  // Integer caps reject a fraction through the same check.
  SceneDesc s = parse_scene_text(kGood, "good.json");
  expect_scene_error([&] { apply_parameter(s, "solver.cg_max_iterations", 2.5); },
                     {"good.json", "'solver.cg_max_iterations'", "2.5", "[1, inf)"},
                     "fractional CG cap");
}

// The GUI's edit path (controls.cpp calls apply_parameter, then validate before restarting)
// refuses what the reader refuses, with the reader's message, and keeps the old value.
TEST(Parameters, GuiEditPathRejectsWhatTheReaderRejects) {
  struct Case {
    std::string key;
    double value;
    std::string reader_override;
  };
  const std::string fixed = R"(time.dt={"rule":"fixed","value":0.001})";
  const std::vector<Case> cases = {
      {"materials.0.nu", 0.5, "materials.0.nu=0.5"},
      {"materials.0.E", 0, "materials.0.E=0"},
      {"time.dt.value", 0, R"(time.dt={"rule":"fixed","value":0})"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.key);
    SceneDesc gui = parse_scene_text(kGood, "good.json", {fixed});
    const std::string reader = reader_message({c.reader_override});
    ASSERT_NE(reader, "accepted");
    int index = 0;
    const NumericParameter& p = *find_parameter(c.key, &index);
    const double before = p.get(gui, index);
    try {
      apply_parameter(gui, c.key, c.value);
      ADD_FAILURE() << "the GUI path accepted " << c.key << " = " << c.value;
    } catch (const SceneError& e) {
      EXPECT_EQ(std::string(e.what()), reader);
    }
    EXPECT_EQ(p.get(gui, index), before) << "the old value was not kept";
    // A SceneDesc edited in place (as the GUI did before) is refused by validate alike.
    p.set(gui, index, c.value);
    expect_scene_error([&] { validate(gui); }, {reader}, "validate " + c.key);
  }
  SceneDesc gui = parse_scene_text(kGood, "good.json");
  expect_scene_error([&] { apply_parameter(gui, "materials.3.E", 10); },
                     {"good.json", "materials.3.E"}, "no material 3");
  expect_scene_error([&] { apply_parameter(gui, "solver.scheme", 1); },
                     {"good.json", "solver.scheme"}, "not numeric");
}

// `text` with the numeric key at an index ("materials.0.E", "domain.min.1") set to `value` in the
// JSON itself; a count is written as a JSON integer.
std::string with_number(const std::string& text, const NumericParameter& p, const std::string& key,
                        double value) {
  nlohmann::json j = nlohmann::json::parse(text);
  nlohmann::json* node = &j;
  std::stringstream parts(key);
  for (std::string part; std::getline(parts, part, '.');)
    node = node->is_array() ? &(*node)[std::stoul(part)] : &(*node)[part];
  if (p.integer)
    *node = static_cast<long long>(value);
  else
    *node = value;
  return j.dump();
}

// A value outside p's range, or none when every real is allowed.
std::optional<double> outside_value(const NumericParameter& p) {
  const Range& r = p.range;
  if (std::isfinite(r.lo)) return r.lo - (p.integer ? 1 : 1e-3 * std::max(1.0, std::abs(r.lo)));
  if (std::isfinite(r.hi)) return r.hi + (p.integer ? 1 : 1e-3 * std::max(1.0, std::abs(r.hi)));
  return std::nullopt;
}

// A numeric key, at every index the scene has: read from the scene file itself, set alike by
// --set, and refused out of range with one message from the file, from --set and from the GUI's
// path (apply_parameter). Returns how many values were refused.
int check_numeric_key(const NumericParameter& p) {
  int refused = 0;
  const std::string& text = good_text_for(p);
  const SceneDesc base = parse_scene_text(text, "good.json");
  const int n = p.count ? p.count(base) : 1;
  for (int i = 0; i < n; ++i) {
    const std::string key = p.key_at(i);
    SCOPED_TRACE(key);
    const double value = another_valid_value(p, p.get(base, i));
    EXPECT_NE(value, p.get(base, i));
    SceneDesc file, set;
    EXPECT_NO_THROW(file = parse_scene_text(with_number(text, p, key, value), "good.json"));
    EXPECT_EQ(p.get(file, i), value);
    EXPECT_NO_THROW(set = parse_scene_text(text, "good.json", {key + "=" + format_value(value)}));
    EXPECT_EQ(p.get(set, i), value);
    const std::optional<double> outside = outside_value(p);
    if (!outside) continue;
    ++refused;
    const std::string expected = *parameter_error(p, i, *outside, "good.json");
    EXPECT_EQ(reader_message({}, with_number(text, p, key, *outside)), expected) << "the file";
    EXPECT_EQ(reader_message({key + "=" + format_value(*outside)}, text), expected) << "--set";
    SceneDesc gui = base;
    try {
      apply_parameter(gui, key, *outside);
      ADD_FAILURE() << "the GUI's path accepted " << format_value(*outside);
    } catch (const SceneError& e) {
      EXPECT_EQ(std::string(e.what()), expected) << "the GUI's path";
    }
  }
  return refused;
}

// The scene text whose sections take the word key c (kGood, or kGoodEol for the EoL methods' keys),
// with a collider for colliders.*, and (`companions`) where a key needs them the keys that let
// another word run.
std::string word_text_for(const ChoiceParameter& c, bool companions = true) {
  nlohmann::json j = nlohmann::json::parse(c.read_by("mpm") ? kGood : kGoodEol);
  j["colliders"] = nlohmann::json::parse(
      R"([{"type": "plane", "point": [0, 0.1], "normal": [0, 1], "condition": "sticky"}])");
  // The file's solver keys belong to its method (--set solver.method leaves them out, docs/cli.md).
  if (c.key == "solver.method") j["solver"] = {{"method", "mpm"}};
  // A lattice-filled box, which triangulated sampling takes as well.
  if (companions && c.key == "objects.*.sampling.type") {
    j["objects"][0]["shape"] = {{"type", "box"}, {"min", {0.3, 0.3}}, {"max", {0.7, 0.7}}};
    j["objects"][0]["sampling"] = {{"type", "lattice"}, {"spacing", 0.05}};
  }
  // The walls as an object (a z wall in a 3D scene).
  if (c.key.starts_with("domain.boundary.")) {
    j["domain"]["boundary"] = {{"x-", "slip"}, {"x+", "slip"}};
    if (c.only_3d) {
      j["dim"] = 3;
      j["domain"]["min"] = {0, 0, 0};
      j["domain"]["max"] = {1, 1, 1};
      j["gravity"] = {0, 0, -9.8};
      j["objects"][0]["shape"]["center"] = {0.5, 0.5, 0.5};
      j["objects"][0]["velocity"] = {0.1, 0, 0};
      j["colliders"][0]["point"] = {0, 0.1, 0};
      j["colliders"][0]["normal"] = {0, 1, 0};
    }
  }
  // Anchors hold rows of a triangulated box.
  if (c.key == "objects.*.anchors.rows") {
    j["objects"][0]["shape"] = {{"type", "box"}, {"min", {0.3, 0.3}}, {"max", {0.7, 0.7}}};
    j["objects"][0]["sampling"] = {{"type", "triangulated"}, {"spacing", 0.05}};
    j["objects"][0]["anchors"] = {{"rows", {"top"}}};
  }
  return j.dump();
}

// `text` with the key at index 0 set to `word` in the JSON itself (a switch as a JSON boolean, a
// list key as a list of the one word).
std::string with_word(const std::string& text, const ChoiceParameter& c, const std::string& word) {
  nlohmann::json j = nlohmann::json::parse(text);
  nlohmann::json* node = &j;
  std::stringstream parts(std::string(c.key));
  for (std::string part; std::getline(parts, part, '.');)
    node = node->is_array() ? &(*node)[0] : &(*node)[part];
  if (c.list)
    *node = nlohmann::json::array({word});
  else if (c.is_switch() && (word == "true" || word == "false"))
    *node = word == "true";
  else
    *node = word;
  return j.dump();
}

// A scene as code builds one: one default item in each list (materials, objects, colliders).
SceneDesc one_item_each() {
  SceneDesc s;
  s.materials.emplace_back();
  s.objects.emplace_back();
  s.colliders.emplace_back();
  return s;
}

// A word key: each of its words gives the same outcome from the scene file and from --set (read
// back, or refused with one message, as the fixed rule without its step is), at least one word
// besides the scene's own is read back, an unknown word is refused alike naming the key, and
// the default is the registry's for a key the file leaves out and for a scene built in code.
void check_word_key(const ChoiceParameter& c) {
  const std::string key(c.key_at(0)), text = word_text_for(c);
  SCOPED_TRACE(key);
  const SceneDesc base = parse_scene_text(text, "good.json");
  const auto set = [&](const std::string& word) {
    return key + "=" + (c.list ? "[\"" + word + "\"]" : word);
  };
  int others = 0;
  for (const ChoiceOption& o : c.options) {
    SCOPED_TRACE(o.key);
    const std::string file = reader_message({}, with_word(text, c, o.key));
    EXPECT_EQ(reader_message({set(o.key)}, text), file) << "--set and the file differ";
    if (file != "accepted") continue;
    EXPECT_EQ(c.get(parse_scene_text(with_word(text, c, o.key), "good.json"), 0), o.key);
    EXPECT_EQ(c.get(parse_scene_text(text, "good.json", {set(o.key)}), 0), o.key);
    others += o.key != c.get(base, 0);
  }
  // Another shape, or a box or rod instead of a plane, needs its own keys (center, size, ...).
  if (c.key != "objects.*.shape.type" && c.key != "colliders.*.type" && c.options.size() > 1) {
    EXPECT_GE(others, 1);
  }
  const std::string unknown = reader_message({}, with_word(text, c, "nosuchword"));
  EXPECT_EQ(reader_message({set("nosuchword")}, text), unknown);
  for (const std::string& needle : {"good.json: key '" + key + "'", std::string("nosuchword")})
    EXPECT_NE(unknown.find(needle), std::string::npos) << unknown;
  if (c.default_key.empty()) return;
  nlohmann::json left_out = nlohmann::json::parse(word_text_for(c, false));
  nlohmann::json* section = &left_out;
  std::stringstream parts(std::string(c.key));
  std::vector<std::string> path;
  for (std::string part; std::getline(parts, part, '.');) path.push_back(part);
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    section = section->is_array() ? &(*section)[0] : &(*section)[path[i]];
  section->erase(path.back());
  EXPECT_EQ(c.get(parse_scene_text(left_out.dump(), "good.json"), 0), c.default_key) << "left out";
  EXPECT_EQ(c.get(one_item_each(), 0), c.default_key) << "built in code";
}

// One declaration per parameter: every registry key, numeric or word, is listed in the generated
// key table (docs_generated keeps it equal to `apiclab docs scene-keys`; cli_tests.sh holds `run
// --help` to it), read from the scene file, set alike by --set, and a number refused out of range
// with one message from the file, --set and the GUI's path.
TEST(Parameters, EveryKeyIsReadFromTheFileListedSetAndRefusedAlike) {
  std::ifstream table_file(std::string(APICLAB_SOURCE_DIR) + "/docs/scene-keys.md");
  const std::string table((std::istreambuf_iterator<char>(table_file)),
                          std::istreambuf_iterator<char>());
  ASSERT_FALSE(table.empty());
  int refused = 0;
  for (const auto& p : numeric_parameters()) {
    EXPECT_NE(table.find("| `" + std::string(p.key) + "` |"), std::string::npos) << p.key;
    refused += check_numeric_key(p);
  }
  EXPECT_GE(refused, 25);
  for (const ChoiceParameter& c : choice_parameters()) {
    EXPECT_NE(table.find("| `" + std::string(c.key) + "` |"), std::string::npos) << c.key;
    int index = -1;
    EXPECT_EQ(find_choice(c.key_at(2), &index), &c);
    EXPECT_EQ(index, c.key.find('*') == std::string_view::npos ? 0 : 2);
    check_word_key(c);
  }
}

// The defaults are stated once, in the registry: SceneDesc() starts from them, and a scene that
// leaves a key out keeps them (the two-step rule's dt_max is the one that depends on the scene).
TEST(Parameters, DefaultsComeFromTheRegistryAlone) {
  const SceneDesc fresh, built = one_item_each();  // a list key's default is its item's
  nlohmann::json minimal = nlohmann::json::parse(kGood);
  minimal.erase("time");
  minimal.erase("solver");
  minimal.erase("gravity");
  nlohmann::json minimal_eol = minimal;
  minimal_eol["solver"] = {{"method", "eol"}};
  const SceneDesc mpm = parse_scene_text(minimal.dump(), "minimal.json");
  const SceneDesc eol = parse_scene_text(minimal_eol.dump(), "minimal.json");
  for (const auto& p : numeric_parameters()) {
    SCOPED_TRACE(std::string(p.key));
    if (p.required) continue;
    const SceneDesc& read = p.read_by("mpm") ? mpm : eol;
    if (p.is_set) {
      EXPECT_FALSE(p.is_set(p.count ? built : fresh, 0));  // a list key needs an item
      EXPECT_FALSE(p.is_set(read, 0));
      continue;
    }
    for (int i = 0; i < (p.count ? p.count(read) : 1); ++i) {
      EXPECT_EQ(p.get(built, p.count ? 0 : i), p.default_value) << i;
      EXPECT_EQ(p.get(read, i), p.default_value) << i;
    }
  }
  EXPECT_EQ(parse_scene_text(minimal.dump(), "m.json", {R"(time.dt={"rule":"two-step"})"}).time.dt,
            0.005);
  expect_scene_error(
      [&] { parse_scene_text(minimal.dump(), "m.json", {R"(time.dt={"rule":"fixed"})"}); },
      {"m.json", "'time.dt.value'", "required key is missing"}, "fixed rule without its step");
  // A method reads the keys the registry names it for: eulerian has no object grids.
  expect_scene_error(
      [&] {
        parse_scene_text(kGoodEol, "good.json", {"solver.method=eulerian", "solver.padding=4"});
      },
      {"good.json", "'solver.padding'", "unknown key"}, "eol's key under eulerian");
  EXPECT_EQ(parse_scene_text(kGoodEol, "good.json", {"solver.padding=4"}).solver.eol.padding, 4);
}

TEST(Parameters, LambdaIsOptional) {
  EXPECT_FALSE(parse_scene_text(kGood, "good.json").solver.lambda.has_value());
  EXPECT_EQ(parse_scene_text(kGood, "good.json", {"solver.integrator=midpoint"})
                .solver.integrator_lambda(),
            0.5);
  EXPECT_EQ(parse_scene_text(kGood, "good.json", {"solver.integrator=lambda", "solver.lambda=0.25"})
                .solver.integrator_lambda(),
            0.25);
  bad("/solver/lambda", -0.5, "solver.lambda");  // once a negative value meant "unset"
}

// solver.lambda belongs to the lambda integrator alone. Beside symplectic it used to run the
// λ = 0.25 member under the name symplectic; beside backward Euler it made a hybrid (backward
// Euler's grid update, λ's transfers). Both are refused now, naming both keys; the lambda
// integrator needs its λ.
TEST(Parameters, LambdaOnlyWithTheLambdaIntegrator) {
  for (const char* integrator : {"symplectic", "midpoint", "backward"})
    expect_scene_error(
        [&] {
          parse_scene_text(kGood, "good.json",
                           {std::string("solver.integrator=") + integrator, "solver.lambda=0.25"});
        },
        {"good.json", "'solver.lambda'", "solver.integrator lambda", integrator}, integrator);
  expect_scene_error([] { parse_scene_text(kGood, "good.json", {"solver.integrator=lambda"}); },
                     {"good.json", "'solver.integrator'", "solver.lambda"},
                     "lambda without its value");
  // Each label says the λ it runs.
  EXPECT_EQ(integrator_label(parse_scene_text(kGood, "good.json",
                                              {"solver.integrator=lambda", "solver.lambda=0.3"})
                                 .solver),
            "lambda(0.3)");
  EXPECT_EQ(integrator_label(parse_scene_text(kGood, "good.json").solver), "symplectic");
}

}  // namespace
}  // namespace apiclab
