// What a run hands a person: a fixed --dt taken exactly with frames at or just past
// their times, the GUI's drift series by run's rule (L0 = 0 and L0 at round-off), round-off
// momenta plotted as zero, the settings sidecar and the JSON run summary.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "app/drift_series.hpp"
#include "app/frame_loop.hpp"
#include "app/lockstep.hpp"
#include "app/run_outputs.hpp"
#include "sim/scene/parameters.hpp"

namespace apiclab {
namespace {

SceneDesc disk(const std::vector<std::string>& overrides = {}) {
  return load_scene(std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json",
                    overrides);
}

// --dt 0.03 at 24 fps: the old rule capped it at 1/24 and cut steps to land on frames (0.0208).
TEST(FixedStep, IsHonouredExactlyAndFramesAreTheStepAtOrJustPastTheirTime) {
  const double dt = 0.03;
  SceneDesc s = disk({R"(time.dt={"rule":"fixed","value":0.03})", "time.end=0.2",
                      "solver.integrator=\"midpoint\""});
  auto sim = make_simulation(s);
  Lockstep panes({sim.get()});
  const FrameTimes times(s);
  long rows = 0;
  run_frame_loop(
      times, panes,
      [&](std::size_t, const DiagnosticsRow& r) {
        ++rows;
        EXPECT_EQ(r.dt, dt) << "step " << r.step;  // exactly the given step, every row
      },
      [&](int f) {
        const double t = sim->time();
        EXPECT_GE(t, times.time_of(f) - 1e-12) << "frame " << f;
        EXPECT_LT(t, times.time_of(f) + dt) << "frame " << f << ": more than one step past";
        return true;
      });
  EXPECT_EQ(rows, 7);  // 7 x 0.03 = 0.21: the first step at or past time.end = 0.2
  EXPECT_NEAR(sim->time(), 7 * dt, 1e-12);
  EXPECT_NE(time_step_note(s).find("at or just past"), std::string::npos);
}

// A step that divides the frame interval lands on every frame: the accumulated n·dt is met.
TEST(FixedStep, AWholeNumberOfStepsPerFrameLandsOnFrames) {
  SceneDesc s = disk({R"(time.dt={"rule":"fixed","value":0.004166666666666667})", "time.end=0.25",
                      "solver.integrator=\"midpoint\""});  // 1/240 s: 10 steps a frame
  auto sim = make_simulation(s);
  Lockstep panes({sim.get()});
  const FrameTimes times(s);
  run_frame_loop(times, panes, {}, [&](int f) {
    EXPECT_EQ(sim->time(), times.time_of(f));
    EXPECT_EQ(sim->steps(), 10L * f);
    return true;
  });
  EXPECT_EQ(time_step_note(s), "");
}

// A fixed step longer than a frame is still the step: frames repeat, and the run says so.
TEST(FixedStep, LongerThanAFrameIsStillTheStep) {
  SceneDesc s = disk({R"(time.dt={"rule":"fixed","value":0.1})", "time.end=0.25",
                      "solver.integrator=\"backward\""});
  auto sim = make_simulation(s);
  EXPECT_FALSE(sim->step(1 / 24.0).has_value());
  EXPECT_EQ(sim->time(), 0.1);
  EXPECT_NE(time_step_note(s).find("longer than a frame"), std::string::npos);
  // The opt-in keeps the old landing for a fixed step.
  SceneDesc land = disk({R"(time.dt={"rule":"fixed","value":0.1,"land_on_frames":true})",
                         "solver.integrator=\"backward\""});
  auto landed = make_simulation(land);
  landed->step(1 / 24.0);
  EXPECT_EQ(landed->time(), 1 / 24.0);
}

DiagnosticsRow row_at(double t, double kinetic, double total, std::array<double, 3> L) {
  DiagnosticsRow r;
  r.t = t, r.kinetic = kinetic, r.total = total, r.L = L;
  return r;
}

// Two cubes at rest (L0 = 0, K0 = 0): the plot used to be empty, energy drift included.
TEST(DriftPlot, BodyAtRestPlotsEnergyAndAbsoluteL) {
  const std::vector<DiagnosticsRow> rows = {row_at(0, 0, -5, {0, 0, 0}),
                                            row_at(0.1, 1, -5.001, {0, 0, 1e-3}),
                                            row_at(0.2, 2, -4.99, {0, 0, 2e-3})};
  const auto row = [&](std::size_t i) -> const DiagnosticsRow& { return rows[i]; };
  const DriftRule rule(rows[0], 2.0, 1.0);
  const MomentumRoundOff round_off = momentum_round_off(row, rows.size(), 2.0, 1.0);
  EXPECT_NEAR(round_off.p, 1e-12 * std::sqrt(2 * 2 * 2.0), 1e-25);  // √(2 K_max M)
  const DriftPlot d = drift_plot(rule, row, rows.size(), round_off.L);
  EXPECT_FALSE(d.momentum_relative);
  EXPECT_NE(d.momentum_label.find("kg m^2/s"), std::string::npos);
  EXPECT_NE(d.title.find("absolute"), std::string::npos);
  ASSERT_EQ(d.energy.size(), 2u);  // row 0, the reference, is left out
  ASSERT_EQ(d.momentum.size(), 2u);
  EXPECT_EQ(d.t[0], 0.1);
  for (double e : d.energy) EXPECT_GT(e, 0) << "a log axis would leave it out";
  EXPECT_NEAR(d.energy[0], 0.001 / 5, 1e-15);  // -5.001 - (-5) in double
  EXPECT_NEAR(d.energy[1], 0.01 / 5, 1e-15);
  EXPECT_DOUBLE_EQ(d.momentum[1], 2e-3);
  // Before the first step: the initial row alone, at the floors.
  const DriftPlot start = drift_plot(rule, row, 1, round_off.L);
  ASSERT_EQ(start.energy.size(), 1u);
  EXPECT_EQ(start.energy[0], kRelativeDriftFloor);
  EXPECT_EQ(start.momentum[0], round_off.L);
}

// A symmetric impact (ring-collision): L0 is round-off of the momentum scale, so a ratio to it
// would be meaningless. |ΔL| is absolute, and changes of round-off size sit on the floor.
TEST(DriftPlot, RoundOffL0GivesAbsoluteLabelledDrift) {
  const double mass = 2, extent = 3, K = 50;
  const double scale = std::sqrt(2 * K * mass) * extent;  // 30 kg m²/s
  const std::vector<DiagnosticsRow> rows = {row_at(0, K, 100, {0, 0, 3e-15}),
                                            row_at(0.1, K, 100, {0, 0, 3e-15 + 2e-16}),
                                            row_at(0.2, K, 100, {0, 0, 4e-6})};
  const auto row = [&](std::size_t i) -> const DiagnosticsRow& { return rows[i]; };
  const DriftRule rule(rows[0], mass, extent);
  const MomentumRoundOff round_off = momentum_round_off(row, rows.size(), mass, extent);
  EXPECT_DOUBLE_EQ(round_off.L, 1e-12 * scale);
  const DriftPlot d = drift_plot(rule, row, rows.size(), round_off.L);
  EXPECT_FALSE(d.momentum_relative);
  EXPECT_EQ(d.momentum[0], round_off.L);  // 2e-16: round-off, not a drift of 7 %
  EXPECT_NEAR(d.momentum[1], 4e-6, 1e-14);
  // A real L0 keeps the relative ratio and its label.
  const std::vector<DiagnosticsRow> spinning = {row_at(0, K, 100, {0, 0, 10}),
                                                row_at(0.1, K, 100, {0, 0, 10.01})};
  const auto srow = [&](std::size_t i) -> const DiagnosticsRow& { return spinning[i]; };
  const DriftPlot r = drift_plot(DriftRule(spinning[0], mass, extent), srow, 2, round_off.L);
  EXPECT_TRUE(r.momentum_relative);
  EXPECT_EQ(r.momentum_label, "|dL|/|L0|");
  EXPECT_NEAR(r.momentum[0], 1e-3, 1e-12);
}

TEST(DriftPlot, RoundOffMomentaArePlottedAsZero) {
  EXPECT_EQ(plotted_momentum(3e-17, 1e-12), 0.0);
  EXPECT_EQ(plotted_momentum(-3e-17, 1e-12), 0.0);
  EXPECT_EQ(plotted_momentum(2e-9, 1e-12), 2e-9);
}

// The sidecar next to a CSV: every setting, and enough to repeat the run (registry keys).
TEST(RunOutputs, SidecarHoldsEverySetting) {
  const SceneDesc s = disk({"materials.0.E=2000"});
  const nlohmann::json settings = run_settings(s, Precision::single, {"materials.0.E=2000"});
  EXPECT_EQ(settings["scene"], "rotating-disk");
  EXPECT_EQ(settings["precision"], "float");
  EXPECT_EQ(settings["solver"]["scheme"], std::string(key_of(s.solver.scheme)));
  EXPECT_EQ(settings["parameters"]["materials.0.E"], 2000.0);
  EXPECT_EQ(settings["parameters"]["domain.dx"], s.domain.dx);
  // The keys an MPM run reads; the EoL family's are left out.
  for (const NumericParameter& p : numeric_parameters())
    if (!p.count && (!p.is_set || p.is_set(s, 0))) {
      EXPECT_EQ(settings["parameters"].contains(std::string(p.key)), p.read_by("mpm")) << p.key;
    }
  // A count is an integer, not 2.0.
  EXPECT_TRUE(settings["parameters"]["solver.xpic_order"].is_number_integer());
  const auto dir = std::filesystem::temp_directory_path() /
                   ("apiclab-test-outputs-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string csv = (dir / "x.csv").string();
  write_csv_sidecar(csv, settings);
  std::ifstream in(csv + ".json");
  const nlohmann::json back = nlohmann::json::parse(in);
  EXPECT_EQ(back["csv"], "x.csv");
  EXPECT_TRUE(back["apiclab_version"].is_string());
  EXPECT_EQ(back["settings"], settings);
  std::filesystem::remove_all(dir);
}

// The summary's fields, from a real short run and from a failure.
TEST(RunOutputs, SummaryJsonFields) {
  const SceneDesc s = disk({"time.end=0.1"});
  auto sim = make_simulation(s);
  DiagnosticsRow first = sim->measure();
  RunSummary summary(first, sim->total_mass(), DriftRule::domain_extent(s));
  sim->advance_to(0.1, [&](const DiagnosticsRow& r) { summary.add(r); });
  const nlohmann::json j =
      run_summary_json(s, run_settings(s, Precision::dbl, {}), summary, sim->time(),
                       {2.0, 3.5, 1000, sim->steps()}, std::nullopt);
  EXPECT_EQ(j["steps"], sim->steps());
  EXPECT_EQ(j["t_final"], 0.1);
  EXPECT_LE(j["dt"]["min"].get<double>(), j["dt"]["median"].get<double>());
  EXPECT_LE(j["dt"]["median"].get<double>(), j["dt"]["max"].get<double>());
  EXPECT_EQ(j["wall_seconds"], 2.0);
  EXPECT_EQ(j["cpu_seconds"], 3.5);
  EXPECT_DOUBLE_EQ(j["particle_steps_per_second"].get<double>(), 1000.0 * sim->steps() / 2.0);
  EXPECT_EQ(j["energy_drift"]["final"], summary.energy_drift());
  EXPECT_GE(j["energy_drift"]["max_abs"].get<double>(), std::abs(summary.energy_drift()));
  EXPECT_EQ(j["angular_momentum_drift"]["kind"], "relative");  // the disk spins: L0 is real
  EXPECT_TRUE(j["failure"].is_null());
  EXPECT_TRUE(j.contains("apiclab_version"));
  const Failure f{12, 0.5, "kinetic + elastic energy", "simulation blew up at step 12"};
  const nlohmann::json bad = run_summary_json(s, nlohmann::json::object(), summary, 0.5, {}, f);
  EXPECT_EQ(bad["failure"]["step"], 12);
  EXPECT_EQ(bad["failure"]["t"], 0.5);
  EXPECT_EQ(bad["failure"]["quantity"], "kinetic + elastic energy");
}

}  // namespace
}  // namespace apiclab
