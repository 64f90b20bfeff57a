// Why the two-ring energy table (README, "The two-ring energy table") puts XPIC(2) below PIC and
// ASFLIP where it does: measured properties of the schemes, not bugs. The table reports the total
// energy at t = 0.01 s, long after the rings have separated; by then it is the kinetic energy of
// each ring's bulk translation (the rebound), and the vibrations the impact left have been damped.
// So it ranks how much translation comes back out of the impact (a restitution), which is not
// the same order as how much energy a scheme dissipates:
// - without contact XPIC(m) keeps more than PIC, more with larger m (Hammerquist and Nairn 2017);
// - through the impact XPIC(2) keeps more total energy than PIC, but more of it is vibration when
//   the rings separate, and that vibration is damped afterwards, so its rebound is slower;
// - ASFLIP without its position correction (β = 0) rebounds faster than FLIP; with β = 1 the
//   rings do not rebound at all (their particles leave the rings' lattice and the two end as one
//   scattered cloud), and what the table shows is that cloud's locked elastic energy.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "tests/mpm/test_helpers.hpp"

namespace apiclab {
namespace {

// ring-collision as the table's figure runs it: symplectic Euler at the elastic limit, ν = 0.3.
SceneDesc rings(const std::string& scheme, std::vector<std::string> extra = {}) {
  extra.insert(extra.begin(),
               {"solver.integrator=symplectic", R"(time.dt={"rule":"elastic","nu":0.3})",
                "solver.scheme=" + scheme});
  return load_scene(std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/ring-collision.json", extra);
}

struct Sample {
  double t = 0, total = 0;
  double bulk = 0;  // Σ over the rings of |Σ m v|² / (2 Σ m): their translation's kinetic energy
  double vibration() const { return total - bulk; }  // internal kinetic + elastic
};

std::vector<Sample> run(const SceneDesc& scene, const std::vector<double>& times) {
  MpmSimulation<double, 2> sim(scene);
  std::vector<Sample> out;
  for (double t : times) {
    DiagnosticsRow row;
    while (sim.time() < t) {
      const auto failure = sim.step(t, &row);
      EXPECT_FALSE(failure) << "failed at t = " << sim.time();
      if (failure) return out;
    }
    const auto& p = MpmProbe(sim).particles();
    std::map<int, std::pair<double, Vec<double, 2>>> rings;  // object → (mass, momentum)
    for (std::size_t q = 0; q < p.size(); ++q) {
      auto& r = rings.try_emplace(p.object[q], 0.0, Vec<double, 2>::Zero()).first->second;
      r.first += p.mass[q];
      r.second += p.mass[q] * p.v[q];
    }
    Sample s;
    s.t = sim.time();
    s.total = row.total;
    for (const auto& [object, r] : rings) s.bulk += r.second.squaredNorm() / (2 * r.first);
    out.push_back(s);
  }
  return out;
}

// Hammerquist and Nairn present XPIC(m) as less dissipative than PIC. On the spinning disk (no
// contact, 0.5 s) it is: PIC loses all but 5e-6 of the energy, XPIC(2) keeps 19 %, XPIC(5) 60 %,
// APIC all of it.
TEST(SchemeEnergy, XpicKeepsMoreThanPicWithoutContact) {
  auto energy = [](const std::string& scheme, std::vector<std::string> extra = {}) {
    MpmSimulation<double, 2> sim(test::disk_symplectic(scheme, std::move(extra)));
    DiagnosticsRow first = sim.measure(), row;
    while (sim.time() < 0.5) EXPECT_FALSE(sim.step(0.5, &row));
    return row.total / first.total;
  };
  const double pic = energy("pic"), x2 = energy("xpic", {"solver.xpic_order=2"}),
               x5 = energy("xpic", {"solver.xpic_order=5"}), apic = energy("apic");
  std::printf(
      "[ energy ] disk, kept after 0.5 s: PIC %.3g, XPIC(2) %.3g, XPIC(5) %.3g, APIC %.6f\n", pic,
      x2, x5, apic);
  EXPECT_LT(pic, 1e-4);
  EXPECT_GT(x2, 0.1);
  EXPECT_GT(x5, x2 + 0.2);
  EXPECT_GT(apic, x5);
}

// The rings meet at t ≈ 0.002 s and are apart by 0.004 s. XPIC(2) holds more energy than PIC at
// every sample through the impact, leaves it with more energy in vibration and less in
// translation, and then both damp the vibration while the translation is kept exactly: at
// 0.01 s the table sees the rebound's translation, and XPIC(2)'s is the slower one.
TEST(SchemeEnergy, XpicBelowPicOnTheRingsIsTheRebound) {
  const std::vector<double> times{0.0025, 0.003, 0.0035, 0.004, 0.005, 0.0075, 0.01};
  const auto pic = run(rings("pic"), times);
  const auto x2 = run(rings("xpic", {"solver.xpic_order=2"}), times);
  ASSERT_EQ(pic.size(), times.size());
  ASSERT_EQ(x2.size(), times.size());
  for (std::size_t k = 0; k < times.size(); ++k)
    std::printf(
        "[ energy ] rings t = %.4f s: PIC total %7.1f bulk %7.1f | XPIC(2) total %7.1f "
        "bulk %7.1f\n",
        times[k], pic[k].total, pic[k].bulk, x2[k].total, x2[k].bulk);
  for (std::size_t k = 0; k < 4; ++k)  // through the impact, t ≤ 0.004 s
    EXPECT_GT(x2[k].total, pic[k].total) << "t = " << times[k];
  // At separation (0.004 s) XPIC(2) carries more vibration and less translation than PIC.
  EXPECT_GT(x2[3].vibration() / x2[3].total, 1.5 * pic[3].vibration() / pic[3].total);
  EXPECT_LT(x2[3].bulk, 0.8 * pic[3].bulk);
  // From 0.005 s on, each ring translates rigidly: its translation is kept to 1e-3 by both.
  for (const auto* s : {&pic, &x2})
    for (std::size_t k = 4; k < times.size(); ++k)
      EXPECT_NEAR((*s)[k].bulk, s->back().bulk, 1e-3 * s->back().bulk) << "t = " << times[k];
  // At 0.01 s the total is the translation to within 5 %: the table measures the rebound.
  EXPECT_LT(pic.back().vibration(), 0.05 * pic.back().total);
  EXPECT_LT(x2.back().vibration(), 0.05 * x2.back().total);
  EXPECT_LT(x2.back().total, pic.back().total);
}

// ASFLIP (α = 1) without the position correction rebounds faster than FLIP (the affine term keeps
// what FLIP's lumped transfer loses); with β = 1 the rings never separate: at 0.01 s they have
// no translation left, and the table's ASFLIP value is the vibration of the joined particles.
TEST(SchemeEnergy, AsflipPositionCorrectionStopsTheRebound) {
  const std::vector<double> times{0.005, 0.01};
  const auto flip = run(rings("flip"), times);
  const auto beta0 = run(rings("asflip", {"solver.asflip_beta=0"}), times);
  const auto beta1 = run(rings("asflip", {"solver.asflip_beta=1"}), times);
  ASSERT_EQ(flip.size(), 2u);
  ASSERT_EQ(beta0.size(), 2u);
  ASSERT_EQ(beta1.size(), 2u);
  std::printf(
      "[ energy ] rings t = 0.01 s: FLIP total %.1f bulk %.1f | ASFLIP beta 0 total %.1f "
      "bulk %.1f | beta 1 total %.1f bulk %.2f\n",
      flip[1].total, flip[1].bulk, beta0[1].total, beta0[1].bulk, beta1[1].total, beta1[1].bulk);
  EXPECT_GT(beta0[1].bulk, 1.3 * flip[1].bulk);
  EXPECT_GT(beta0[1].total, flip[1].total);
  EXPECT_LT(beta1[1].bulk, 0.05 * beta0[1].bulk);         // no rebound
  EXPECT_GT(beta1[1].vibration(), 0.8 * beta1[1].total);  // locked elastic energy
}

}  // namespace
}  // namespace apiclab
