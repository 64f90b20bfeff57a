// The loops every command shares: frame times (the last on time.end), the frame loop and the
// lockstep over panes, the run summary's drift rule with its L0 cut-off, and the job runner.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>

#include "app/frame_loop.hpp"
#include "app/gui/view_limits.hpp"
#include "app/jobs.hpp"
#include "app/lockstep.hpp"
#include "app/run_length.hpp"
#include "sim/measure/run_summary.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {
namespace {

SceneDesc disk(const std::vector<std::string>& overrides = {}) {
  return load_scene(std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json",
                    overrides);
}

TEST(FrameTimes, LastFrameIsTimeEnd) {
  SceneDesc s = disk({"time.end=10.54", "time.fps=24"});  // sphere-impact-3d's end: 252.96 frames
  const FrameTimes t(s);
  EXPECT_EQ(t.frames, 253);
  EXPECT_EQ(t.time_of(0), 0);
  EXPECT_EQ(t.time_of(252), 252 / 24.0);
  EXPECT_EQ(t.time_of(253), 10.54);
  const FrameTimes short_end(disk({"time.end=0.01"}));  // less than a frame: one frame, at end
  EXPECT_EQ(short_end.frames, 1);
  EXPECT_EQ(short_end.time_of(1), 0.01);
}

// 0.1 s at 24 fps is 2.4 frames: frames at 1/24 and 2/24, then one at 0.1 (rounding 2.4 to 2
// frames put the second at 0.1 and lost 2/24). A whole number of frames gets no extra one.
TEST(FrameTimes, EveryFrameTimeBeforeTheEndHasItsFrame) {
  const FrameTimes t(disk({"time.end=0.1", "time.fps=24"}));
  EXPECT_EQ(t.frames, 3);
  EXPECT_EQ(t.time_of(1), 1 / 24.0);
  EXPECT_EQ(t.time_of(2), 2 / 24.0);
  EXPECT_EQ(t.time_of(3), 0.1);
  for (const char* end : {"time.end=1", "time.end=0.08333333333333333", "time.end=0.125"}) {
    const FrameTimes whole(disk({end, "time.fps=24"}));
    EXPECT_EQ(whole.frames, int(std::lround(whole.end * 24))) << end;
    EXPECT_EQ(whole.time_of(whole.frames), whole.end) << end;
  }
  EXPECT_EQ(FrameTimes(disk({"time.end=0.135"})).frames, 4);  // 3.24 frames: 3 whole, then 0.135
}

// The run-length caps (app/run_length.hpp): the fewest steps each rule must take, the first
// steps' prediction, and the stop past --max-steps.
TEST(RunLength, FewestStepsAndTheBudgetDuringARun) {
  EXPECT_EQ(fewest_steps(disk({"time.dt={\"rule\":\"fixed\",\"value\":0.001}"})).steps, 2000);
  EXPECT_EQ(fewest_steps(disk()).steps, 48);  // cfl: one step per frame, 2 s at 24 fps
  const SceneDesc stiff =
      disk({"time.dt={\"rule\":\"elastic\",\"nu\":0.5}", "materials.0.E=1e308"});
  EXPECT_GT(fewest_steps(stiff).steps, 1e100);
  EXPECT_THROW(check_run_length(stiff, kDefaultMaxSteps, kDefaultMaxFrames), SceneError);
  EXPECT_NO_THROW(check_run_length(disk(), 48, 48));
  EXPECT_THROW(check_run_length(disk(), 47, 48), SceneError);
  EXPECT_THROW(check_run_length(disk(), 48, 47), SceneError);
  DiagnosticsRow r;
  r.step = 1, r.t = 1e-9, r.dt = 1e-9;  // 2e9 steps to 2 s
  EXPECT_THROW(check_step_budget(r, 2.0, 1e8), SceneError);
  EXPECT_NO_THROW(check_step_budget(r, 2.0, 3e9));
  r.step = kPredictingSteps + 1;  // past the first steps: a short step is no prediction
  EXPECT_NO_THROW(check_step_budget(r, 2.0, 1e8));
  r.step = 101;  // past the cap itself: the run stops
  EXPECT_THROW(check_step_budget(r, 2.0, 100), SceneError);
}

TEST(FrameLoop, VisitsEveryFrameWithEveryPaneAtItsTime) {
  const SceneDesc scene = disk({"time.end=0.135"});
  auto a = make_simulation(scene);
  SceneDesc pic = scene;
  pic.solver.scheme = Scheme::pic;
  auto b = make_simulation(pic);
  Lockstep panes({a.get(), b.get()});
  const FrameTimes times(scene);
  std::vector<int> frames;
  std::vector<long> rows(2, 0);
  run_frame_loop(
      times, panes,
      [&](std::size_t k, const DiagnosticsRow& r) {
        ++rows[k];
        EXPECT_LE(r.t, 0.135);
      },
      [&](int f) {
        frames.push_back(f);
        EXPECT_EQ(a->time(), times.time_of(f));
        EXPECT_EQ(b->time(), times.time_of(f));
        return true;
      });
  EXPECT_EQ(frames, (std::vector<int>{0, 1, 2, 3, 4}));  // 3/24 = 0.125, then 0.135
  EXPECT_EQ(rows[0], a->steps());
  EXPECT_EQ(rows[1], b->steps());
  EXPECT_EQ(a->time(), 0.135);
}

TEST(FrameLoop, StopsWhenTheFrameSaysSo) {
  const SceneDesc scene = disk({"time.end=0.2"});
  auto a = make_simulation(scene);
  Lockstep panes({a.get()});
  int last = -1;
  run_frame_loop(FrameTimes(scene), panes, {}, [&](int f) {
    last = f;
    return f < 2;
  });
  EXPECT_EQ(last, 2);
  EXPECT_EQ(a->time(), 2 / 24.0);
}

// dt = 0.05 blows symplectic Euler up: that pane freezes, the other reaches the target.
TEST(Lockstep, FailedPaneStaysFrozenWhileTheOtherAdvances) {
  SceneDesc s = disk({R"(time.dt={"rule":"fixed","value":0.05})"});
  SceneDesc bad = s, good = s;
  bad.solver.integrator = Integrator::symplectic;
  good.solver.integrator = Integrator::backward;
  auto a = make_simulation(bad), b = make_simulation(good);
  Lockstep panes({a.get(), b.get()});
  panes.advance_to(0.5);
  ASSERT_TRUE(a->failure());
  const long frozen = a->steps();
  EXPECT_FALSE(panes.all_failed());
  EXPECT_TRUE(panes.all_reached(0.5));
  EXPECT_EQ(b->time(), 0.5);
  panes.advance_to(0.6);
  EXPECT_EQ(a->steps(), frozen);
  EXPECT_EQ(b->time(), 0.6);
  EXPECT_EQ(panes.step_round(0.6), 0);  // nothing left to do
}

// Small panes step side by side on two threads (each pane on one thread at a time): the same
// states and rows, bit for bit, as each simulation advanced alone.
TEST(Lockstep, PanesSideBySideMatchEachRunAlone) {
  const SceneDesc scene = disk({"time.end=0.25"});
  std::vector<std::unique_ptr<Simulation>> alone, panes;
  std::vector<std::vector<DiagnosticsRow>> rows_alone(3), rows_panes(3);
  int k = 0;
  for (Scheme scheme : {Scheme::pic, Scheme::flip, Scheme::apic}) {
    SceneDesc s = scene;
    s.solver.scheme = scheme;
    alone.push_back(make_simulation(s));
    panes.push_back(make_simulation(s));
    ASSERT_FALSE(panes.back()->steps_in_parallel());  // the side-by-side path is the one tested
    alone.back()->advance_to(0.25, [&](const DiagnosticsRow& r) { rows_alone[k].push_back(r); });
    ++k;
  }
  const int threads = omp_get_max_threads();
  omp_set_num_threads(2);
  Lockstep lockstep({panes[0].get(), panes[1].get(), panes[2].get()});
  lockstep.advance_to(
      0.25, [&](std::size_t pane, const DiagnosticsRow& r) { rows_panes[pane].push_back(r); });
  omp_set_num_threads(threads);
  for (std::size_t p = 0; p < 3; ++p) {
    ASSERT_EQ(rows_panes[p].size(), rows_alone[p].size());
    for (std::size_t i = 0; i < rows_alone[p].size(); ++i) {
      EXPECT_EQ(rows_panes[p][i].total, rows_alone[p][i].total) << p << " " << i;
      EXPECT_EQ(rows_panes[p][i].L, rows_alone[p][i].L) << p << " " << i;
    }
    std::ostringstream a, b;  // every particle's x, v, F, C to 17 digits
    alone[p]->transfers()->write_particles_csv(a);
    panes[p]->transfers()->write_particles_csv(b);
    EXPECT_EQ(a.str(), b.str()) << "pane " << p;
  }
}

DiagnosticsRow row_with(double kinetic, double total, std::array<double, 3> L, double dt = 0) {
  DiagnosticsRow r;
  r.kinetic = kinetic, r.total = total, r.L = L, r.dt = dt;
  return r;
}

TEST(RunSummary, RelativeDriftsAndTimeSteps) {
  RunSummary s(row_with(2, 4, {0, 0, 10}), 1.0, 2.0);
  s.add(row_with(1, 3.9, {0, 0, 10.5}, 0.02));
  s.add(row_with(1, 3.0, {0, 0.3, 9.6}, 0.01));
  s.add(row_with(1, 3.0, {0, 0.3, 9.6}, 0.04));
  EXPECT_DOUBLE_EQ(s.energy_drift(), -0.25);
  EXPECT_TRUE(s.angular_momentum_relative());
  EXPECT_DOUBLE_EQ(s.angular_momentum_drift(), 0.5 / 10);  // |(0, 0.3, -0.4)| / 10
  EXPECT_EQ(s.steps(), 3);
  const auto dt = s.dt();
  EXPECT_EQ(dt.min, 0.01);
  EXPECT_EQ(dt.median, 0.02);
  EXPECT_EQ(dt.max, 0.04);
}

// A million adaptive steps: min and max exact, the median within 1e-4 relative of the exact
// one, a fixed step's median exact; memory is bins of log Δt, not a list of every step.
TEST(RunSummary, TimeStepStatisticsStayBoundedOverManySteps) {
  RunSummary s(row_with(2, 4, {0, 0, 10}), 1.0, 2.0);
  std::vector<double> all;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(1e-5, 2e-4);
  for (int k = 0; k < 1000000; ++k) {
    const double dt = u(rng);
    all.push_back(dt);
    s.add(row_with(1, 3.9, {0, 0, 10}, dt));
  }
  std::sort(all.begin(), all.end());
  const double exact = 0.5 * (all[all.size() / 2 - 1] + all[all.size() / 2]);
  const auto dt = s.dt();
  EXPECT_EQ(s.steps(), 1000000);
  EXPECT_EQ(dt.min, all.front());
  EXPECT_EQ(dt.max, all.back());
  EXPECT_NEAR(dt.median, exact, 1e-4 * exact);
  RunSummary fixed(row_with(2, 4, {0, 0, 10}), 1.0, 2.0);
  for (int k = 0; k < 1000; ++k) fixed.add(row_with(1, 3.9, {0, 0, 10}, 0.1));
  EXPECT_EQ(fixed.dt().median, 0.1);
}

// L0 at round-off of the momentum scale √(2 K M)·extent counts as zero: |ΔL| is absolute.
TEST(RunSummary, RoundOffL0GivesAbsoluteDrift) {
  const double scale = std::sqrt(2 * 50.0 * 2.0) * 3.0;  // K = 50, M = 2, extent 3
  RunSummary zero(row_with(50, 100, {0, 0, 1e-13 * scale}), 2.0, 3.0);
  zero.add(row_with(50, 100, {0, 0, 2e-6}));
  EXPECT_FALSE(zero.angular_momentum_relative());
  EXPECT_DOUBLE_EQ(zero.angular_momentum_drift(), 2e-6 - 1e-13 * scale);
  RunSummary real(row_with(50, 100, {0, 0, 1e-11 * scale}), 2.0, 3.0);  // above round-off
  EXPECT_TRUE(real.angular_momentum_relative());
  EXPECT_EQ(DriftRule::domain_extent(disk()), 1.0);  // rotating disk: [0, 1]²
}

// E0 at or below the rest round-off ε D Σ m c² counts as zero: dE is absolute, in J.
TEST(RunSummary, RoundOffE0GivesAbsoluteEnergyDrift) {
  const DriftRule rest(row_with(0, 3e-15, {0, 0, 0}), 1.0, 1.0, 1e-12);
  EXPECT_FALSE(rest.energy_relative());
  EXPECT_DOUBLE_EQ(rest.energy(row_with(0, 5e-15, {0, 0, 0})), 2e-15);
  const DriftRule moving(row_with(0, 2e-12, {0, 0, 0}), 1.0, 1.0, 1e-12);
  EXPECT_TRUE(moving.energy_relative());
  EXPECT_DOUBLE_EQ(moving.energy(row_with(0, 3e-12, {0, 0, 0})), 0.5);
  // Exactly zero is absolute even without a round-off scale (no division by a floor).
  EXPECT_FALSE(DriftRule(row_with(0, 0, {0, 0, 0}), 1.0, 1.0).energy_relative());
}

// The rotating disk at rest without gravity, under MPM and EoL: E0 is round-off of the rest
// energy, the drift absolute and within a few round-offs; spinning, it is relative.
TEST(RunSummary, BodyAtRestHasAbsoluteEnergyDriftInBothFamilies) {
  for (const char* method : {"mpm", "eol"}) {
    const std::string m = std::string("solver.method=") + method;
    auto rest = make_simulation(disk({m, "objects.0.angular_velocity=0", "time.end=0.02"}));
    const DiagnosticsRow first = rest->measure();
    RunSummary s(DriftRule::of(*rest, first));
    ASSERT_FALSE(rest->advance_to(0.02, [&](const DiagnosticsRow& r) { s.add(r); })) << method;
    const double round_off = rest->rest_energy_round_off();
    EXPECT_GT(round_off, 0) << method;
    EXPECT_LE(std::abs(first.total), round_off) << method;
    EXPECT_FALSE(s.energy_relative()) << method;
    EXPECT_LE(s.max_energy_drift(), 10 * round_off) << method;
    auto spinning = make_simulation(disk({m}));
    EXPECT_TRUE(DriftRule::of(*spinning, spinning->measure()).energy_relative()) << method;
  }
}

TEST(Jobs, PoolRunsEveryIndexOnceAndRethrows) {
  std::vector<std::atomic<int>> seen(50);
  jobs::run_pool(seen.size(), 3, [&](std::size_t i) { ++seen[i]; });
  for (auto& n : seen) EXPECT_EQ(n.load(), 1);
  std::atomic<int> ran{0};
  EXPECT_THROW(jobs::run_pool(10, 2,
                              [&](std::size_t i) {
                                ++ran;
                                if (i == 3) throw std::runtime_error("three");
                              }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 10);  // the others still ran
}

TEST(Jobs, RunKeepsRowsAndSnapshotsAndNamesBadRuns) {
  jobs::Run a, b, bad;
  a.scene = b.scene = bad.scene = "rotating-disk";
  a.scheme = "apic", b.scheme = "pic", bad.scheme = "no-such-scheme";
  a.t_end = b.t_end = 0.1;
  a.snapshot_times = {0.05, 0.1};
  b.timed = true;
  jobs::execute_all({&a, &b}, 2);
  ASSERT_EQ(a.snapshots.size(), 2u);
  EXPECT_EQ(a.snapshots[0]->time, 0.05);
  EXPECT_EQ(a.snapshots[1]->time, 0.1);
  EXPECT_EQ(a.rows.front().t, 0);
  EXPECT_EQ(a.rows.back().t, 0.1);
  EXPECT_EQ(b.rows.back().t, 0.1);
  EXPECT_GT(b.seconds, 0);
  try {
    jobs::execute_all({&bad}, 1);
    FAIL() << "a bad scheme ran";
  } catch (const jobs::JobError& e) {
    EXPECT_NE(std::string(e.what()).find("rotating-disk (no-such-scheme)"), std::string::npos)
        << e.what();
  }
}

}  // namespace
// The viewer's own numbers stay usable whatever is typed or turned (the GUI soak typed 1e38 into
// "particle size" through ImGui's ctrl+click text field; app/gui/view_limits.hpp).
TEST(GuiViewLimits, TypedValuesAreClampedAndNonFiniteOnesReplaced) {
  using namespace gui;
  EXPECT_EQ(within(1e38f, kParticleScale), kParticleScale.hi);
  EXPECT_EQ(within(-1.0f, kParticleScale), kParticleScale.lo);
  EXPECT_EQ(within(std::nanf(""), kParticleScale), kParticleScale.fallback);
  EXPECT_EQ(within(INFINITY, kVectorGain), kVectorGain.fallback);
  EXPECT_EQ(within(-INFINITY, kColorMax), kColorMax.fallback);
  EXPECT_EQ(within(2.0f, kVectorGain), 2.0f);  // a value in range is kept as typed
}

// 2000 wheel notches each way (0.88 per notch, app/gui/scene_view.cpp): unclamped, the half
// height reaches 0 or inf within about 800, and every projected point becomes NaN.
TEST(GuiViewLimits, ZoomStaysFiniteAndPositive) {
  using namespace gui;
  float in = 1, out = 1;
  for (int notch = 0; notch < 2000; ++notch) {
    in = within(in * 0.88f, kViewSize);
    out = within(out / 0.88f, kViewSize);
  }
  EXPECT_EQ(in, kViewSize.lo);
  EXPECT_EQ(out, kViewSize.hi);
  EXPECT_GT(in, 0.0f);
  EXPECT_TRUE(std::isfinite(out));
}

}  // namespace apiclab
