// The grid stores only the active box the particles reach (sim/mpm/grid.hpp): the same
// scene in a tight domain and in one 100× the area (2D) or 20× the volume (3D) allocates the same
// grid and follows the same trajectory bit for bit; a projectile's grid stays the size of its
// box; the memory estimate predicts the allocation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sim/scene/memory_estimate.hpp"
#include "tests/mpm/test_helpers.hpp"

namespace apiclab {
namespace {

const std::string kScenes = std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/";

// The domain grown away from its minimum corner to `factor` × its area (2D) or volume (3D):
// walls at the minimum stay put, and the node lattice (origin = min − 2 dx) is unchanged.
std::vector<std::string> grown(const SceneDesc& s, double factor) {
  std::vector<std::string> sets;
  for (int a = 0; a < s.dim; ++a) {
    const double extent = (s.domain.max[a] - s.domain.min[a]) * std::pow(factor, 1.0 / s.dim);
    sets.push_back("domain.max." + std::to_string(a) + "=" +
                   std::to_string(s.domain.min[a] + extent));
  }
  return sets;
}

std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// Runs the scene tight and grown for `steps` of its own time-step rule; the particle states must
// agree exactly (same blocks, same sort, same sums in the same order), and the grid bytes of the
// grown domain stay within 1.5× of the tight one's (the target; here they are equal).
template <int D>
void same_in_a_larger_domain(const std::string& file, std::vector<std::string> sets, double factor,
                             int steps) {
  const SceneDesc tight_scene = load_scene(kScenes + file, sets);
  const SceneDesc large_scene = load_scene(kScenes + file, plus(sets, grown(tight_scene, factor)));
  double tight_measure = 1, large_measure = 1;
  for (int a = 0; a < D; ++a) {
    tight_measure *= tight_scene.domain.max[a] - tight_scene.domain.min[a];
    large_measure *= large_scene.domain.max[a] - large_scene.domain.min[a];
  }
  ASSERT_NEAR(large_measure / tight_measure, factor, 1e-4 * factor);
  MpmSimulation<double, D> tight(tight_scene), large(large_scene);
  std::size_t tight_bytes = 0, large_bytes = 0;
  for (int s = 0; s < steps; ++s) {
    ASSERT_FALSE(tight.step(1e30, nullptr).has_value()) << "step " << s;
    ASSERT_FALSE(large.step(1e30, nullptr).has_value()) << "step " << s;
    tight_bytes = std::max(tight_bytes, MpmProbe(tight).grid().allocated_bytes());
    large_bytes = std::max(large_bytes, MpmProbe(large).grid().allocated_bytes());
  }
  EXPECT_EQ(tight.time(), large.time());
  const auto &p = MpmProbe(tight).particles(), &q = MpmProbe(large).particles();
  ASSERT_EQ(p.size(), q.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < p.size(); ++k)
    if (p.id[k] != q.id[k] || p.x[k] != q.x[k] || p.v[k] != q.v[k] || p.F[k] != q.F[k] ||
        p.C[k] != q.C[k])
      ++differing;
  EXPECT_EQ(differing, 0u) << "particles whose state differs after " << steps << " steps";
  // What the whole larger domain would take: every node of its lattice.
  double domain_nodes = 1;
  for (int a = 0; a < D; ++a) domain_nodes *= MpmProbe(large).grid().n[a];
  const double bytes_per_node = double(tight_bytes) / double(MpmProbe(tight).grid().size());
  std::printf("%s: grid %.0f kB tight, %.0f kB in %g x the domain (whole domain: %.0f kB)\n",
              file.c_str(), tight_bytes / 1e3, large_bytes / 1e3, factor,
              domain_nodes * bytes_per_node / 1e3);
  EXPECT_GT(tight_bytes, 0u);
  EXPECT_LE(double(large_bytes), 1.5 * double(tight_bytes));
  EXPECT_GT(domain_nodes * bytes_per_node, 10.0 * double(large_bytes));  // the test has teeth
}

// Rotating disk (midpoint: the implicit solve), and explicit with the disk's walls.
TEST(SparseGrid, RotatingDiskIn100xTheAreaIsIdentical) {
  same_in_a_larger_domain<2>("rotating-disk.json", {}, 100, 12);
}
TEST(SparseGrid, ExplicitDiskIn100xTheAreaIsIdentical) {
  same_in_a_larger_domain<2>("rotating-disk.json",
                             {"solver.integrator=symplectic", "time.dt.nu=0.003"}, 100, 40);
}
// Two cubes at a coarse dx under gravity, the lower one near the floor (wall nodes in reach).
TEST(SparseGrid, TwoCubesIn20xTheVolumeAreIdentical) {
  same_in_a_larger_domain<3>("two-cubes.json",
                             {"domain.dx=0.03125", "objects.0.sampling.ppc=1",
                              "objects.1.sampling.ppc=1", "time.dt.value=5e-4"},
                             20, 30);
}

// A ball flying along a domain 32 times its length: the stored box moves with it, so the grid
// never holds more than the box's nodes, a small part of the domain.
TEST(SparseGrid, ProjectileKeepsTheGridTheSizeOfItsBox) {
  const std::string scene = R"({"name": "projectile", "dim": 2,
    "domain": {"min": [0, 0], "max": [16, 0.5], "dx": 0.03125, "boundary": "slip"},
    "gravity": [0, 0], "time": {"end": 1, "fps": 24, "dt": {"rule": "fixed", "value": 1e-3}},
    "solver": {"scheme": "apic", "integrator": "symplectic"},
    "materials": [{"E": 100, "nu": 0.3, "rho": 1}],
    "objects": [{"shape": {"type": "ball", "center": [0.3, 0.25], "radius": 0.1},
                 "material": 0, "sampling": {"type": "ppc", "ppc": 4}, "velocity": [12, 0]}]})";
  MpmSimulation<double, 2> sim(parse_scene_text(scene, "projectile"));
  sim.step_fixed(1e-3);
  const std::size_t first_nodes = MpmProbe(sim).grid().size(),
                    first_bytes = MpmProbe(sim).grid().allocated_bytes();
  std::size_t most_nodes = first_nodes, most_bytes = first_bytes;
  for (int s = 0; s < 1000; ++s) {  // 1 s at 12 length/s along a domain 16 long
    sim.step_fixed(1e-3);
    most_nodes = std::max(most_nodes, MpmProbe(sim).grid().size());
    most_bytes = std::max(most_bytes, MpmProbe(sim).grid().allocated_bytes());
  }
  double centre = 0;
  for (const auto& x : MpmProbe(sim).particles().x)
    centre += x[0] / double(MpmProbe(sim).particles().size());
  EXPECT_NEAR(centre, 0.3 + 12 * 1.001, 0.05);  // it really flew (no walls in the way)
  EXPECT_GT(MpmProbe(sim).grid().lo[0], 300);   // and the box went with it: 12 / dx = 384
  const double domain_nodes = double(MpmProbe(sim).grid().n[0]) * double(MpmProbe(sim).grid().n[1]);
  std::printf("projectile: box %zu..%zu nodes, %zu..%zu bytes; domain %.0f nodes\n", first_nodes,
              most_nodes, first_bytes, most_bytes, domain_nodes);
  // Blocks of 4 cells: the box may gain one block per axis as the ball straddles block edges.
  EXPECT_LE(double(most_nodes), 1.5 * double(first_nodes));
  EXPECT_LE(double(most_bytes), 1.5 * double(first_bytes));
  EXPECT_LT(double(most_nodes), 0.05 * domain_nodes);
}

// The estimate counts the box the first sort stores: equal for boxes, a little above for a disk
// (its bounding square may reach a block its particles do not).
TEST(SparseGrid, EstimateMatchesTheAllocatedBox) {
  struct Case {
    std::string file;
    std::vector<std::string> sets;
  };
  for (const Case& c :
       {Case{"rotating-disk.json", {}}, Case{"rotating-disk.json", {"domain.max.0=10"}},
        Case{"two-cubes.json",
             {"domain.dx=0.03125", "objects.0.sampling.ppc=1", "objects.1.sampling.ppc=1"}}}) {
    SCOPED_TRACE(c.file);
    const SceneDesc scene = load_scene(kScenes + c.file, c.sets);
    const MemoryEstimate e = estimate_memory(scene, Precision::dbl);
    auto sim = make_simulation(scene, Precision::dbl);
    sim->step_fixed(1e-5);
    std::size_t nodes = 0;
    if (scene.dim == 2)
      nodes = MpmProbe(dynamic_cast<MpmSimulation<double, 2>&>(*sim)).grid().size();
    else
      nodes = MpmProbe(dynamic_cast<MpmSimulation<double, 3>&>(*sim)).grid().size();
    EXPECT_GE(e.grid_nodes, double(nodes));
    EXPECT_LE(e.grid_nodes, 1.25 * double(nodes));
  }
}

// A domain a million times the disk's area would have needed ~225 GB as a whole grid: it is no
// longer refused, and runs in the disk's own memory.
TEST(SparseGrid, HugeDomainWithASmallObjectIsNotRefused) {
  const SceneDesc scene =
      load_scene(kScenes + "rotating-disk.json",
                 {"domain.max.0=1000", "domain.max.1=1000", "solver.integrator=symplectic"});
  EXPECT_NO_THROW(check_memory(scene, Precision::dbl));
  EXPECT_LT(estimate_memory(scene, Precision::dbl).bytes(), 2e6);
  MpmSimulation<double, 2> sim(scene);
  for (int s = 0; s < 3; ++s) sim.step_fixed(1e-3);
  EXPECT_LT(MpmProbe(sim).grid().allocated_bytes(), 1000000u);
  EXPECT_TRUE(std::isfinite(sim.measure().total));
}

}  // namespace
}  // namespace apiclab
