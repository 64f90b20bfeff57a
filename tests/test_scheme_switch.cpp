// Switching a live simulation's scheme (GUI panes, SimWorker::set_scheme; the same call
// rewinds a pane) gives back the arrays only the old scheme used: XPIC(m)'s two node arrays and
// PolyPIC's modes ("model no more than a scene needs", issue 15). Capacity is checked, not size:
// clear() keeps the memory.
#include <gtest/gtest.h>

#include <cstdio>
#include <utility>

#include "test_helpers.hpp"

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
  const std::size_t nodes = sim.grid().size();
  ASSERT_GE(sim.xpic_capacity(), 2 * nodes);  // e and the series term, one vector per node
  const std::size_t xpic_bytes = sim.xpic_capacity() * sizeof(Vec<double, 2>);
  const std::size_t before = sim.state_bytes();
  sim.set_scheme(Scheme::apic, 1.0);
  EXPECT_EQ(sim.xpic_capacity(), 0u);
  EXPECT_EQ(before - sim.state_bytes(), xpic_bytes);  // nothing else moved
  std::printf("[ switch ] xpic(3) -> apic: %zu -> %zu bytes (%zu grid nodes)\n", before,
              sim.state_bytes(), nodes);
  // APIC runs on without them, and switching back sizes them again on XPIC's next step.
  ASSERT_FALSE(sim.step(100.0, nullptr));
  EXPECT_EQ(sim.xpic_capacity(), 0u);
  sim.set_scheme(Scheme::xpic, 1.0);
  ASSERT_FALSE(sim.step(100.0, nullptr));
  EXPECT_GE(sim.xpic_capacity(), 2 * sim.grid().size());
  // XPIC(1) is PIC: it never needs them.
  sim.solver().xpic_order = 1;
  sim.set_scheme(Scheme::xpic, 1.0);
  EXPECT_EQ(sim.xpic_capacity(), 0u);
}

TEST(SchemeSwitch, PolypicToPicFreesItsModes) {
  MpmSimulation<double, 2> sim(test::disk_symplectic("polypic", {"solver.polypic_modes=9"}));
  for (int s = 0; s < 5; ++s) ASSERT_FALSE(sim.step(100.0, nullptr));
  const auto& p = std::as_const(sim).particles();
  ASSERT_EQ(p.modes.size(), 6u);  // 9 modes: v_p, C_p's two, and six beyond
  const std::size_t modes = mode_capacity(p);
  ASSERT_GE(modes, 6 * p.size());
  const std::size_t before = sim.state_bytes();
  sim.set_scheme(Scheme::pic, 1.0);
  EXPECT_EQ(mode_capacity(p), 0u);
  // The particles' six arrays at least (the sort copy holds six more after a sort).
  EXPECT_GE(before - sim.state_bytes(), 6 * p.size() * sizeof(Vec<double, 2>));
  std::printf("[ switch ] polypic(9 modes) -> pic: %zu -> %zu bytes (%zu particles)\n", before,
              sim.state_bytes(), p.size());
  ASSERT_FALSE(sim.step(100.0, nullptr));
  EXPECT_EQ(mode_capacity(p), 0u);  // the sort copy does not bring them back
}

}  // namespace
}  // namespace apiclab
