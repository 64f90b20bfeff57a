// The GUI's simulation thread, headless: frames land on the commands' frame times and the last
// on time.end, panes share every frame time, scheme switching keeps the state, reset restores
// it exactly, a blow-up freezes only its pane, bad scenes leave the running one alone, and the
// snapshot handoff survives a reader and a command storm (run under TSAN: gui_tests.cmake).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>
#include <thread>

#include "app/frame_loop.hpp"
#include "app/sim_worker.hpp"
#include "sim/scene/memory_estimate.hpp"
#include "sim/scene/registry.hpp"
#include "sim/scene/scene.hpp"
#include "sim/state_io.hpp"

namespace apiclab::gui {
namespace {

// A pane of `scheme` with the scene's kernel, `integrator` (empty: the scene's) and `method`.
PaneConfig pane(Scheme scheme, std::optional<Integrator> integrator = {}, std::string method = "") {
  PaneConfig p;
  p.scheme = scheme;
  p.integrator = integrator;
  p.method = std::move(method);
  return p;
}

SceneDesc disk(const std::vector<std::string>& overrides = {}) {
  return load_scene(std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json",
                    overrides);
}

std::shared_ptr<const Published> loaded(SimWorker& w, std::vector<PaneConfig> panes,
                                        const std::vector<std::string>& overrides = {}) {
  w.load(disk(overrides), std::move(panes));
  w.sync();
  return w.latest();
}

std::shared_ptr<const Published> run_frames(SimWorker& w, int n) {
  const long start = w.latest()->frame;
  for (int k = 0; k < n; ++k) w.step_frame();
  w.sync(start + n);
  return w.latest();
}

TEST(GuiWorker, SchemeSwitchKeepsParticlesPositionsAndTime) {
  SimWorker w;
  loaded(w, {pane(Scheme::apic)});
  const auto before = run_frames(w, 3);
  ASSERT_EQ(before->frame, 3);
  const Snapshot& a = *before->panes[0].snapshot;
  EXPECT_GT(a.time, 0);
  w.set_scheme(0, Scheme::flip, 0.95);
  w.sync();
  const auto after = w.latest();
  const Snapshot& b = *after->panes[0].snapshot;
  EXPECT_EQ(b.scheme, "flip");
  EXPECT_EQ(b.flip_alpha, 0.95);
  EXPECT_EQ(b.count(), a.count());
  EXPECT_EQ(b.time, a.time);
  EXPECT_EQ(b.step, a.step);
  EXPECT_EQ(b.positions, a.positions);
  EXPECT_EQ(after->panes[0].history.size(), before->panes[0].history.size());
  // And it runs on from there under the new scheme.
  const auto later = run_frames(w, 2);
  EXPECT_GT(later->panes[0].snapshot->time, a.time);
  EXPECT_EQ(later->panes[0].snapshot->count(), a.count());
}

TEST(GuiWorker, ResetRestoresTheInitialStateExactly) {
  SimWorker w;
  const auto initial = loaded(w, {pane(Scheme::pic), pane(Scheme::apic)});
  run_frames(w, 4);
  w.set_scheme(1, Scheme::rpic, 1.0);
  w.play(true);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  w.reset();
  w.sync();
  const auto again = w.latest();
  ASSERT_EQ(again->panes.size(), 2u);
  EXPECT_EQ(again->frame, 0);
  EXPECT_FALSE(again->playing);
  EXPECT_GT(again->generation, initial->generation);
  for (std::size_t k = 0; k < 2; ++k) {
    const Snapshot& a = *initial->panes[k].snapshot;
    const Snapshot& b = *again->panes[k].snapshot;
    EXPECT_EQ(b.time, 0);
    EXPECT_EQ(b.step, 0);
    EXPECT_EQ(b.positions, a.positions);
    EXPECT_EQ(b.velocities, a.velocities);
    ASSERT_EQ(again->panes[k].history.size(), 1u);
    EXPECT_EQ(again->panes[k].history[0].total, initial->panes[k].history[0].total);
    EXPECT_EQ(again->panes[k].history[0].L, initial->panes[k].history[0].L);
  }
  EXPECT_EQ(again->panes[0].snapshot->scheme, "pic");
  EXPECT_EQ(again->panes[1].snapshot->scheme, "rpic");  // the chosen scheme survives reset
}

// A pane's state handed out by with_pane (a checkpoint's) and restored by load_restored in
// another worker: paused at the same frame, it goes on exactly as the first.
TEST(GuiWorker, RestoredPaneGoesOnAsTheSavedOne) {
  SimWorker a, b;
  loaded(a, {pane(Scheme::apic)}, {"time.end=0.5"});
  run_frames(a, 3);
  auto state = std::make_shared<std::string>();
  long frame = -1;
  DiagnosticsRow last;
  a.with_pane(0, [&](const PaneView& v) {
    StateWriter out(*state);
    v.sim.save_state(out);
    frame = v.frame, last = v.history.back();
    return std::string("saved");
  });
  a.sync();
  EXPECT_EQ(a.latest()->notice, "saved");
  ASSERT_EQ(frame, 3);
  b.load_restored(disk({"time.end=0.5"}), pane(Scheme::apic), Precision::dbl, [&](Simulation& sim) {
    StateReader in(state->data(), state->size());
    sim.load_state(in);
    Restored r;
    r.frame = frame, r.last = last;
    return r;
  });
  b.sync();
  const auto restored = b.latest();
  ASSERT_TRUE(restored->error.empty()) << restored->error;
  EXPECT_EQ(restored->frame, 3);
  EXPECT_FALSE(restored->playing);
  EXPECT_EQ(restored->panes[0].snapshot->positions, a.latest()->panes[0].snapshot->positions);
  ASSERT_EQ(restored->panes[0].history.size(), 1u);
  const auto x = run_frames(a, 2), y = run_frames(b, 2);
  EXPECT_EQ(y->frame, 5);
  EXPECT_EQ(y->panes[0].snapshot->time, x->panes[0].snapshot->time);
  EXPECT_EQ(y->panes[0].snapshot->positions, x->panes[0].snapshot->positions);
  EXPECT_EQ(y->panes[0].snapshot->velocities, x->panes[0].snapshot->velocities);
}

// Every pane at every frame time, the commands' frame times, each pane's snapshot from its
// own simulation (its scheme, the time of its last diagnostics row).
TEST(GuiWorker, PanesAdvanceInLockstepToFrameTimes) {
  SimWorker w;
  const std::vector<Scheme> schemes{Scheme::pic, Scheme::flip, Scheme::apic};
  const auto start = loaded(w, {pane(schemes[0]), pane(schemes[1]), pane(schemes[2])});
  const FrameTimes times(*start->scene);
  for (int f = 1; f <= 4; ++f) {
    const auto p = run_frames(w, 1);
    ASSERT_EQ(p->frame, f);
    ASSERT_EQ(p->panes.size(), schemes.size());
    for (std::size_t k = 0; k < schemes.size(); ++k) {
      const PaneState& pane = p->panes[k];
      EXPECT_EQ(pane.snapshot->time, times.time_of(f)) << "pane " << k << ", frame " << f;
      EXPECT_EQ(pane.snapshot->scheme, key_of(schemes[k]));
      EXPECT_EQ(pane.history.back().t, pane.snapshot->time);
      EXPECT_EQ(pane.history.back().step, pane.snapshot->step);
    }
  }
}

// A scene whose end is not a whole frame: the GUI reaches time.end like run and render do
// (3.24 frames at 24 fps: frames at 1/24, 2/24 and then 0.135, not 3/24), then stops.
TEST(GuiWorker, LastFrameLandsOnTimeEnd) {
  SimWorker w;
  const auto start = loaded(w, {pane(Scheme::apic), pane(Scheme::pic)}, {"time.end=0.135"});
  const FrameTimes times(*start->scene);
  ASSERT_EQ(times.frames, 4);       // 3.24 frames: 3/24, then 0.135
  const auto p = run_frames(w, 6);  // more frames than the scene has
  EXPECT_EQ(p->frame, 4);
  EXPECT_FALSE(p->busy);
  for (const PaneState& pane : p->panes) {
    EXPECT_EQ(pane.snapshot->time, 0.135);
    EXPECT_EQ(pane.history.back().t, 0.135);
  }
  w.play(true);  // at the end, play does not run past it
  w.sync(times.frames + 1);
  EXPECT_EQ(w.latest()->panes[0].snapshot->time, 0.135);
  EXPECT_FALSE(w.latest()->playing);
}

// dt = 0.05 is far past the explicit limit: symplectic Euler blows up within a few steps,
// backward Euler does not; the failed pane freezes while the other reaches every frame time.
TEST(GuiWorker, BlowUpFreezesOnlyItsPane) {
  SimWorker w;
  loaded(w, {pane(Scheme::apic, Integrator::symplectic), pane(Scheme::apic, Integrator::backward)},
         {R"(time.dt={"rule":"fixed","value":0.05,"land_on_frames":true})"});
  const auto p = run_frames(w, 6);
  ASSERT_EQ(p->panes.size(), 2u);
  ASSERT_TRUE(p->panes[0].failure) << "symplectic Euler at dt = 0.05 did not blow up";
  const Failure& f = *p->panes[0].failure;
  EXPECT_FALSE(f.quantity.empty());
  EXPECT_EQ(p->panes[0].snapshot->step, f.step);  // frozen where it failed
  EXPECT_FALSE(p->panes[1].failure);
  EXPECT_NEAR(p->panes[1].snapshot->time, 6.0 / p->scene->time.fps, 1e-12);
  const auto more = run_frames(w, 2);  // and it keeps going
  EXPECT_NEAR(more->panes[1].snapshot->time, 8.0 / more->scene->time.fps, 1e-12);
  EXPECT_EQ(more->panes[0].snapshot->step, f.step);
}

TEST(GuiWorker, SceneThatCannotBeBuiltKeepsTheRunningOne) {
  SimWorker w;
  const auto ok = loaded(w, {pane(Scheme::apic)});
  SceneDesc broken = disk();
  broken.objects[0].shape.type = ShapeType::mesh;
  broken.objects[0].shape.file = "/nonexistent/mesh.obj";
  w.load(broken, {pane(Scheme::apic)});
  w.sync();
  const auto p = w.latest();
  EXPECT_FALSE(p->error.empty());
  ASSERT_EQ(p->panes.size(), 1u);
  EXPECT_EQ(p->panes[0].snapshot->positions, ok->panes[0].snapshot->positions);
  const auto more = run_frames(w, 1);  // still runs
  EXPECT_EQ(more->frame, 1);
}

// Four panes keep eight simulations; the whole set is checked against the memory cap before the
// first is built (the soak's scene switches reached 2.9 GB; each simulation alone fit the cap,
// so the set was only stopped, if at all, by the machine's memory running low).
TEST(GuiWorker, PanesAreCheckedForMemoryAsAWhole) {
  SimWorker w;
  const auto ok = loaded(w, {pane(Scheme::apic)});
  SceneDesc scene = disk();
  const double one = estimate_memory(scene, Precision::dbl).bytes();
  scene.solver.max_memory_gb = 3 * one / 1e9;  // one simulation fits, eight do not
  std::vector<PaneConfig> four(4, pane(Scheme::apic));
  w.load(scene, four);
  w.sync();
  const auto p = w.latest();
  EXPECT_NE(p->error.find("8 simulations at once"), std::string::npos) << p->error;
  ASSERT_EQ(p->panes.size(), 1u);  // the running pane stays
  EXPECT_EQ(p->panes[0].snapshot->positions, ok->panes[0].snapshot->positions);
  scene.solver.max_memory_gb = 9 * one / 1e9;  // eight fit
  w.load(scene, four);
  w.sync();
  EXPECT_TRUE(w.latest()->error.empty()) << w.latest()->error;
  EXPECT_EQ(w.latest()->panes.size(), 4u);
}

// A reader that walks every published value while commands rain in: the handoff must be
// race-free (TSAN) and every value consistent.
// `gui --schemes apic,eol,eulerian`: an MPM pane beside EoL panes, all from the one EoL scene,
// in lockstep (each pane's method overrides the scene's solver.method).
TEST(GuiWorker, PanesMixMethodsFromOneScene) {
  SimWorker w;
  w.load(load_scene(std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/eol-spin.json",
                    {"time.end=0.3"}),
         {pane(Scheme::apic, {}, "mpm"), pane(Scheme::apic, {}, "eol"),
          pane(Scheme::apic, {}, "eulerian"), pane(Scheme::apic)});
  w.sync();
  const auto p = run_frames(w, 2);
  ASSERT_EQ(p->error, "");
  ASSERT_EQ(p->panes.size(), 4u);
  EXPECT_EQ(p->panes[0].config.method, "mpm");
  EXPECT_EQ(p->panes[1].config.method, "eol");
  EXPECT_EQ(p->panes[2].config.method, "eulerian");
  EXPECT_EQ(p->panes[3].config.method, "eol");  // none given: the scene's
  EXPECT_EQ(p->panes[0].snapshot->scheme, "apic");
  EXPECT_NE(p->panes[1].snapshot->scheme, "apic");
  for (const PaneState& s : p->panes) {
    EXPECT_FALSE(s.failure);
    EXPECT_EQ(s.snapshot->time, p->panes[0].snapshot->time);
    EXPECT_GT(s.snapshot->time, 0);
  }
}

TEST(GuiWorker, HandoffUnderLoad) {
  SimWorker w;
  w.set_realtime(false);
  loaded(w, {pane(Scheme::pic), pane(Scheme::flip), pane(Scheme::apic)});
  w.set_noise(true);
  w.play(true);
  std::mt19937 rng(7);
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  long max_frame = 0, last_frame = 0;
  std::uint64_t last_generation = 0;
  std::size_t count = 0;
  while (std::chrono::steady_clock::now() < end) {
    const auto p = w.latest();
    ASSERT_EQ(p->panes.size(), 3u);
    for (auto& pane : p->panes) {
      const Snapshot& s = *pane.snapshot;
      // Each value is one pane's, whole: its scheme, its history up to its snapshot.
      ASSERT_EQ(s.scheme, key_of(pane.config.scheme));
      ASSERT_EQ(pane.history.back().step, s.step);
      ASSERT_EQ(pane.history.back().t, s.time);
      if (count == 0) count = s.count();
      ASSERT_EQ(s.count(), count);
      for (float x : s.positions) ASSERT_TRUE(std::isfinite(x));
      for (std::size_t i = 0; i < pane.history.size(); i += 7)
        ASSERT_TRUE(std::isfinite(pane.history[i].total));
    }
    // Frames only count up, except through a reset, which bumps the generation.
    ASSERT_TRUE(p->frame >= last_frame || p->generation > last_generation)
        << "frame " << p->frame << " after " << last_frame;
    last_frame = p->frame, last_generation = p->generation;
    max_frame = std::max(max_frame, p->frame);
    std::this_thread::sleep_for(std::chrono::microseconds(500));  // a GUI frame, fast
    switch (rng() % 60) {
      case 0:
        w.set_scheme(rng() % 3, Scheme(rng() % 4), 0.9);
        break;
      case 1:
        w.play(false);
        break;
      case 2:
        w.play(true);
        break;
      case 3:
        w.step_frame();
        break;
      case 4:
        if (rng() % 10 == 0) w.reset(), w.play(true);
        break;
      case 5:
        w.set_realtime(rng() % 2 == 0);
        break;
      default:
        break;
    }
  }
  w.sync();
  EXPECT_GT(max_frame, 0);
}

}  // namespace
}  // namespace apiclab::gui
