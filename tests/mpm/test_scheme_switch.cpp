// Switching a live simulation's scheme (GUI panes, SimWorker::set_scheme; the same call
// rewinds a pane) gives back the arrays only the old scheme used: XPIC(m)'s two node arrays and
// PolyPIC's modes ("model no more than a scene needs"). Capacity is checked, not size:
// clear() keeps the memory. And every label names the parameter of a scheme that has one:
// XPIC(3), PolyPIC(9 modes), ASFLIP(α, β), from the scene a simulation runs
// (sim/mpm/schemes/scheme_label.hpp).
#include <gtest/gtest.h>

#include <cstdio>
#include <utility>

#include "sim/mpm/schemes/scheme_label.hpp"
#include "tests/mpm/test_helpers.hpp"

namespace apiclab {
namespace {

template <class T, int D>
std::size_t mode_capacity(const Particles<T, D>& p) {
  std::size_t c = p.modes.capacity();
  for (const auto& m : p.modes) c += m.capacity();
  return c;
}

TEST(SchemeSwitch, XpicToApicFreesItsNodeArrays) {
  MpmSimulation<double, 2> sim(test::disk_symplectic("xpic", {"solver.xpic_order=3"}));
  for (int s = 0; s < 5; ++s) ASSERT_FALSE(sim.step(100.0, nullptr));
  const std::size_t nodes = MpmProbe(sim).grid().size();
  ASSERT_GE(MpmProbe(sim).xpic_capacity(),
            2 * nodes);  // e and the series term, one vector per node
  const std::size_t xpic_bytes = MpmProbe(sim).xpic_capacity() * sizeof(Vec<double, 2>);
  const std::size_t before = MpmProbe(sim).state_bytes();
  sim.set_scheme(Scheme::apic, 1.0);
  EXPECT_EQ(MpmProbe(sim).xpic_capacity(), 0u);
  EXPECT_EQ(before - MpmProbe(sim).state_bytes(), xpic_bytes);  // nothing else moved
  std::printf("[ switch ] xpic(3) -> apic: %zu -> %zu bytes (%zu grid nodes)\n", before,
              MpmProbe(sim).state_bytes(), nodes);
  // APIC runs on without them, and switching back sizes them again on XPIC's next step.
  ASSERT_FALSE(sim.step(100.0, nullptr));
  EXPECT_EQ(MpmProbe(sim).xpic_capacity(), 0u);
  sim.set_scheme(Scheme::xpic, 1.0);
  ASSERT_FALSE(sim.step(100.0, nullptr));
  EXPECT_GE(MpmProbe(sim).xpic_capacity(), 2 * MpmProbe(sim).grid().size());
  // XPIC(1) is PIC: it never needs them.
  MpmProbe(sim).solver().xpic_order = 1;
  sim.set_scheme(Scheme::xpic, 1.0);
  EXPECT_EQ(MpmProbe(sim).xpic_capacity(), 0u);
}

TEST(SchemeSwitch, PolypicToPicFreesItsModes) {
  MpmSimulation<double, 2> sim(test::disk_symplectic("polypic", {"solver.polypic_modes=9"}));
  for (int s = 0; s < 5; ++s) ASSERT_FALSE(sim.step(100.0, nullptr));
  const auto& p = MpmProbe(std::as_const(sim)).particles();
  ASSERT_EQ(p.modes.size(), 6u);  // 9 modes: v_p, C_p's two, and six beyond
  const std::size_t modes = mode_capacity(p);
  ASSERT_GE(modes, 6 * p.size());
  const std::size_t before = MpmProbe(sim).state_bytes();
  sim.set_scheme(Scheme::pic, 1.0);
  EXPECT_EQ(mode_capacity(p), 0u);
  // The particles' six arrays at least (the sort copy holds six more after a sort).
  EXPECT_GE(before - MpmProbe(sim).state_bytes(), 6 * p.size() * sizeof(Vec<double, 2>));
  std::printf("[ switch ] polypic(9 modes) -> pic: %zu -> %zu bytes (%zu particles)\n", before,
              MpmProbe(sim).state_bytes(), p.size());
  ASSERT_FALSE(sim.step(100.0, nullptr));
  EXPECT_EQ(mode_capacity(p), 0u);  // the sort copy does not bring them back
}

// The labels read the scene's numbers, and the snapshot carries them to the renderer and GUI.
TEST(SchemeLabel, NamesTheParameter) {
  const SceneDesc xpic = test::disk_symplectic("xpic", {"solver.xpic_order=3"});
  EXPECT_EQ(run_label(xpic), "xpic(3)");
  EXPECT_EQ(run_label(test::disk_symplectic("polypic")), "polypic(9 modes)");  // 0: all of 2D's
  EXPECT_EQ(run_label(test::disk_symplectic("polypic", {"solver.polypic_modes=1"})),
            "polypic(1 mode)");
  EXPECT_EQ(run_label(test::disk_symplectic("asflip",
                                            {"solver.flip_alpha=0.9", "solver.asflip_beta=0.25"})),
            "asflip(\u03B1=0.9 \u03B2=0.25)");
  EXPECT_EQ(with_scheme_parameter("ASFLIP", Scheme::asflip, 0.9, {2, 9, 0.25}, true),
            "ASFLIP(a=0.9 b=0.25)");  // the GUI's font has no Greek
  EXPECT_EQ(run_label(test::disk_symplectic("flip", {"solver.flip_alpha=0.95"})),
            "flip(\u03B1=0.95)");
  for (const char* plain : {"pic", "flip", "apic", "rpic", "mls", "tpic"})
    EXPECT_EQ(run_label(test::disk_symplectic(plain)), plain);
  SceneDesc eol = xpic;
  eol.solver.method = "eol";
  EXPECT_EQ(run_label(eol), "eol");

  // A pane switched live keeps the scene's numbers: XPIC(3) after APIC, in the snapshot too.
  MpmSimulation<double, 2> sim(test::disk_symplectic("apic", {"solver.xpic_order=3"}));
  sim.set_scheme(Scheme::xpic, 1.0);
  const auto snap = sim.snapshot();
  EXPECT_EQ(snap->scheme, "xpic");
  EXPECT_EQ(snap->scheme_parameters.xpic_order, 3);
  EXPECT_EQ(with_scheme_parameter("XPIC", Scheme::xpic, snap->flip_alpha, snap->scheme_parameters),
            "XPIC(3)");
  EXPECT_EQ(run_label(sim.scene()), "xpic(3)");
}

}  // namespace
}  // namespace apiclab
