#include "fuzz_targets.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <vector>

#include "sim/geometry/sampling.hpp"
#include "sim/scene/memory_estimate.hpp"
#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"

namespace apiclab::fuzz {
namespace {

// The app refuses a scene whose memory estimate exceeds the machine
// (sim/scene/memory_estimate.hpp); the fuzzer's cap is far lower so that an input asking for 1e12
// particles must be refused by the estimate, never by the allocator (libFuzzer's -rss_limit_mb
// catches an estimate too low).
constexpr double kCapGb = 0.05;

std::string source_dir() { return APICLAB_SOURCE_DIR; }

// The thread's current input: a tag the input itself holds may be quoted back (fuzz_scene found
// "[json.exception" typed into a description and echoed as the text last read).
thread_local std::string_view current_input;

// A clean error is one readable line without a library's own tag.
Outcome clean(const std::exception& e) {
  const std::string what = e.what();
  const bool tag = what.find("[json.exception") != std::string::npos &&
                   current_input.find("json.exception") == std::string_view::npos;
  if (what.empty() || what.find('\n') != std::string::npos || tag || what.size() > 2000)
    throw FuzzFinding("unclean error message: " + what.substr(0, 2000));
  return what;
}

// Builds the solver under the fuzz memory cap and takes one step, as `apiclab run` would.
Outcome build(SceneDesc scene) {
  scene.solver.max_memory_gb = std::min(scene.solver.max_memory_gb.value_or(kCapGb), kCapGb);
  check_memory(scene, Precision::dbl);
  auto sim = make_simulation(scene, Precision::dbl);
  // An implicit step's Newton-CG runs for seconds under the sanitizers: a timeout, not a finding.
  if (scene.solver.integrator == Integrator::symplectic) sim->step(scene.time.end);
  return "ok";
}

template <class F>
Outcome guarded(const std::uint8_t* data, std::size_t size, F&& f) {
  current_input = {reinterpret_cast<const char*>(data), size};
  try {
    return f();
  } catch (const SceneError& e) {
    return clean(e);
  } catch (const FuzzFinding&) {
    throw;
  } catch (const std::exception& e) {
    throw FuzzFinding(std::string("not a SceneError: ") + e.what());
  }
}

// Shipped scenes whose one-step build takes longer than the fuzzer's budget for an input under
// the sanitizers: eol-bunny-3d samples a 75,408-triangle mesh's distance (12 s of CPU under ASan,
// 0.3 s in Release), so its mutations time out on a loaded machine. Its mesh is fuzzed by
// fuzz_obj, and tests/fuzz/fuzz_test.sh leaves it out of fuzz_scene's seeds too. eol-two-balls-3d's
// first step (two balls, 1/80 m object grids, viscous forces) ran past the 30 s budget under ASan;
// its keys are those of eol-two-balls, which stays.
bool too_slow_to_fuzz(const std::filesystem::path& scene) {
  return scene.filename() == "eol-bunny-3d.json" || scene.filename() == "eol-two-balls-3d.json";
}

std::vector<std::string> shipped_scenes() {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(source_dir() + "/assets/scenes"))
    if (e.path().extension() == ".json" && !too_slow_to_fuzz(e.path()))
      names.push_back(e.path().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

Outcome scene_text(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // Beside the shipped scenes, so "meshes/bunny.obj" resolves as it does for them.
  const std::string source = source_dir() + "/assets/scenes/fuzz.json";
  return guarded(data, size, [&] { return build(parse_scene_text(text, source)); });
}

Outcome set_overrides(const std::uint8_t* data, std::size_t size) {
  static const std::vector<std::string> scenes = shipped_scenes();
  if (size == 0 || scenes.empty()) return "ok";
  const std::string& path = scenes[data[0] % scenes.size()];
  // The first line's first byte picks the scene; each later line is one assignment.
  std::size_t i = 0;
  while (i < size && data[i] != '\n') ++i;
  std::vector<std::string> sets;
  std::string line;
  for (++i; i < size; ++i) {
    if (data[i] == '\n') {
      sets.push_back(line);
      line.clear();
    } else {
      line += char(data[i]);
    }
  }
  if (!line.empty()) sets.push_back(line);
  return guarded(data, size, [&] { return build(load_scene(path, sets)); });
}

Outcome obj_mesh(const std::uint8_t* data, std::size_t size) {
  // The OBJ reader reads files: one per process, rewritten for each input.
  static const std::string path = (std::filesystem::temp_directory_path() /
                                   ("apiclab_fuzz_" + std::to_string(getpid()) + ".obj"))
                                      .string();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  return guarded(data, size, [&]() -> Outcome {
    ShapeDesc shape;
    shape.type = ShapeType::mesh;
    shape.file = path;
    const MeshSolid solid(path, shape);
    // A domain around the mesh, 16 cells across its longest side, so sampling runs on any size.
    const Vec3d lo = solid.lower(), hi = solid.upper();
    double extent = 0;
    for (int a = 0; a < 3; ++a) extent = std::max(extent, hi[a] - lo[a]);
    char json[1024];
    std::snprintf(json, sizeof json,
                  R"({"name": "obj", "dim": 3,
 "domain": {"min": [%.17g, %.17g, %.17g], "max": [%.17g, %.17g, %.17g], "dx": %.17g},
 "time": {"end": 0.001, "fps": 1000, "dt": {"rule": "fixed", "value": 1e-4}},
 "materials": [{"name": "m", "model": "fixed-corotated", "E": 1000, "nu": 0.3, "rho": 1}],
 "objects": [{"name": "o", "shape": {"type": "mesh", "file": "%s"}, "material": "m",
              "sampling": {"type": "ppc", "ppc": 1}}]})",
                  lo[0] - 0.25 * extent, lo[1] - 0.25 * extent, lo[2] - 0.25 * extent,
                  hi[0] + 0.25 * extent, hi[1] + 0.25 * extent, hi[2] + 0.25 * extent, extent / 16,
                  path.c_str());
    return build(parse_scene_text(json, path + ".json"));
  });
}

Target target_named(const std::string& name) {
  if (name == "scene") return scene_text;
  if (name == "set") return set_overrides;
  if (name == "obj") return obj_mesh;
  return nullptr;
}

}  // namespace apiclab::fuzz
