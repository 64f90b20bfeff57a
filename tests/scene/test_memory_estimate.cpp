// The memory guard (sim/scene/memory_estimate.hpp): the estimate is measured against the resident
// memory a real scene takes, and a scene whose estimate exceeds the cap is refused at once.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <string>

#include "sim/math.hpp"
#include "sim/scene/memory_estimate.hpp"
#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"

namespace apiclab {
namespace {

// VmRSS of this process in bytes (ctest runs each test in a process of its own).
double resident_bytes() {
  std::ifstream in("/proc/self/status");
  std::string name;
  double kb = 0;
  while (in >> name) {
    if (name == "VmRSS:") {
      in >> kb;
      return kb * 1024;
    }
    std::getline(in, name);
  }
  return 0;
}

// A 3D elastic block: 69^3 grid nodes, 32^3 x 8 = 262,144 particles, a few hundred MB.
std::string block_scene(double dx, const std::string& solver_extra = "") {
  return R"({"name": "block", "dim": 3,
    "domain": {"min": [0, 0, 0], "max": [1, 1, 1], "dx": )" +
         std::to_string(dx) + R"(},
    "gravity": [0, -9.8, 0],
    "time": {"end": 1, "fps": 24, "dt": {"rule": "fixed", "value": 1e-4}},
    "solver": {"scheme": "apic")" +
         solver_extra + R"(},
    "materials": [{"E": 1000, "nu": 0.3, "rho": 1}],
    "objects": [{"shape": {"type": "box", "min": [0.25, 0.25, 0.25], "max": [0.75, 0.75, 0.75]},
                 "material": 0, "sampling": {"type": "ppc", "ppc": 8}}]})";
}

TEST(MemoryEstimate, WithinTwiceTheMeasuredResidentGrowth) {
  const SceneDesc scene = parse_scene_text(block_scene(1.0 / 64), "block");
  const MemoryEstimate e = estimate_memory(scene, Precision::dbl);
  EXPECT_NEAR(e.particles, 262144, 1);  // (0.5 / (dx / 2))^3
  // The grid stores the active box only (sim/mpm/grid.hpp): the block spans domain nodes 18..50
  // (two ghost nodes below 0), blocks of 4 cells 4..12, widened to nodes [14, 55) per axis.
  EXPECT_NEAR(e.grid_nodes, 41.0 * 41 * 41, 1);
  const double before = resident_bytes();
  auto sim = make_simulation(scene, Precision::dbl);
  for (int s = 0; s < 2; ++s) sim->step_fixed(1e-4);  // the first step sizes the caches
  const double grown = resident_bytes() - before;
  std::printf("estimate %.1f MB, resident growth %.1f MB\n", e.bytes() / 1e6, grown / 1e6);
  EXPECT_GT(grown, 0.5 * e.bytes());
  EXPECT_LT(grown, 2.0 * e.bytes());
}

TEST(MemoryEstimate, TypoDxIsRefusedAtOnceWithTheEstimate) {
  const SceneDesc scene = parse_scene_text(block_scene(1e-6), "typo.json");
  const auto t0 = std::chrono::steady_clock::now();
  try {
    auto sim = make_simulation(scene, Precision::dbl);
    ADD_FAILURE() << "a 1e18-node grid was not refused";
  } catch (const SceneError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("typo.json: needs about"), std::string::npos) << msg;
    EXPECT_NE(msg.find("grid nodes"), std::string::npos) << msg;
    EXPECT_NE(msg.find("available memory"), std::string::npos) << msg;
    EXPECT_NE(msg.find("--max-memory"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 0.5);
}

TEST(MemoryEstimate, SceneKeySetsTheCap) {
  // 1 MB is far below the block's few hundred MB; 1e300 GB lifts the cap (--max-memory none).
  const SceneDesc capped =
      parse_scene_text(block_scene(1.0 / 16, R"(, "max_memory_gb": 0.001)"), "capped.json");
  EXPECT_THROW(check_memory(capped, Precision::dbl), SceneError);
  const SceneDesc lifted =
      parse_scene_text(block_scene(1.0 / 16, R"(, "max_memory_gb": 1e300)"), "lifted.json");
  EXPECT_NO_THROW(check_memory(lifted, Precision::dbl));
  // Float halves the per-node and per-particle arrays of reals.
  const MemoryEstimate d = estimate_memory(lifted, Precision::dbl);
  const MemoryEstimate f = estimate_memory(lifted, Precision::single);
  EXPECT_LT(f.bytes(), 0.7 * d.bytes());
  EXPECT_GT(f.bytes(), 0.4 * d.bytes());
}

TEST(MemoryEstimate, RoundTripProbe) {
  EXPECT_NEAR(estimate_roundtrip_memory(64).grid_nodes, 64 * 64, 0);
  // The probed scheme's own state: PolyPIC's 6 extra modes (2D, all 9: 1, x, y and 6 more) and
  // their sort copy per particle, XPIC(m > 1)'s two node arrays.
  const auto apic = estimate_roundtrip_memory(64);
  EXPECT_DOUBLE_EQ(
      estimate_roundtrip_memory(64, Scheme::polypic).bytes_per_particle - apic.bytes_per_particle,
      2.0 * 6 * sizeof(Vec<double, 2>));
  EXPECT_DOUBLE_EQ(estimate_roundtrip_memory(64, Scheme::xpic).bytes_per_node - apic.bytes_per_node,
                   2.0 * sizeof(Vec<double, 2>));
  EXPECT_DOUBLE_EQ(estimate_roundtrip_memory(64, Scheme::xpic, 1).bytes_per_node,
                   apic.bytes_per_node);
  EXPECT_THROW(check_memory(estimate_roundtrip_memory(1 << 20), 8e9, "roundtrip"), SceneError);
}

// Fuzz finding 1 (tests/fuzz_regressions/scene/eol-tiny-cell.json): the EoL family's grids were
// not estimated, so solver.cell = 1e-5 allocated 1.6e9 nodes until std::bad_alloc.
TEST(MemoryEstimate, EolGridsAreCounted) {
  const std::string eol = std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/eol-drop.json";
  SceneDesc s = load_scene(eol, {"solver.cell=1e-5"});
  s.solver.max_memory_gb = 1;  // the MPM key; the cap applies to every family
  EXPECT_GT(estimate_memory(s, Precision::dbl).grid_nodes, 1e9);
  EXPECT_THROW(check_memory(s, Precision::dbl), SceneError);
  EXPECT_THROW(make_simulation(s), SceneError);
  s = load_scene(eol, {"solver.grid_extent=1000"});
  s.solver.max_memory_gb = 1;
  EXPECT_THROW(make_simulation(s), SceneError);
  // The shipped scene's own grid: the disk's 0.4 m over 0.025 m cells plus 3 cells each side.
  s = load_scene(eol);
  EXPECT_NEAR(estimate_memory(s, Precision::dbl).grid_nodes, 23 * 23, 0);
  s = load_scene(eol, {"solver.method=eulerian"});
  EXPECT_NEAR(estimate_memory(s, Precision::dbl).grid_nodes, 81 * 61, 0);
  // The baseline keeps one world grid per object.
  s = load_scene(std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/eol-two-disks.json",
                 {"solver.method=eulerian"});
  EXPECT_NEAR(estimate_memory(s, Precision::dbl).grid_nodes, 2 * 65 * 33, 0);
}

TEST(MemoryEstimate, AvailableMemoryIsRead) {
  const auto available = available_memory_bytes();
  ASSERT_TRUE(available.has_value());
  EXPECT_GT(*available, 1e6);
}

}  // namespace
}  // namespace apiclab
