// The sweep viewer's data, headless (app/sweep/open.hpp): a sweep folder made by
// `apiclab sweep tests/sweeps/view.json` (the ctest fixture sweep_view.setup) reopened, every run
// row mapped to the configuration its `run --record` process used, a click's two panes checked
// against those runs' recorded frames and a fresh simulation, and bad folders refused with one
// line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/cli.hpp"
#include "app/lockstep.hpp"
#include "app/sweep/open.hpp"
#include "app/sweep/record.hpp"
#include "sim/scene/parameters.hpp"
#include "sim/simulation.hpp"

namespace apiclab::sweep {
namespace {

namespace fs = std::filesystem;

const std::string kDir = SWEEP_VIEW_DIR;  // written by the fixture (tests/CMakeLists.txt)

std::shared_ptr<const OpenedSweep> opened() {
  static std::shared_ptr<const OpenedSweep> s = open_sweep(kDir);
  return s;
}

// Every value a scene file sets, compared: every numeric registry key (sim/scene/parameters.hpp) at
// every index, the choices, and each object's sampling.
void expect_same_scene(const SceneDesc& a, const SceneDesc& b, const std::string& what) {
  SCOPED_TRACE(what);
  for (const NumericParameter& p : numeric_parameters()) {
    const int n = p.count ? p.count(a) : 1;
    ASSERT_EQ(n, p.count ? p.count(b) : 1) << p.key;
    for (int i = 0; i < n; ++i) {
      if (p.is_set) {
        ASSERT_EQ(p.is_set(a, i), p.is_set(b, i)) << p.key_at(i);
        if (!p.is_set(a, i)) continue;
      }
      EXPECT_EQ(p.get(a, i), p.get(b, i)) << p.key_at(i);
    }
  }
  EXPECT_EQ(a.solver.method, b.solver.method);
  EXPECT_EQ(a.solver.scheme, b.solver.scheme);
  EXPECT_EQ(a.solver.kernel, b.solver.kernel);
  EXPECT_EQ(a.solver.integrator, b.solver.integrator);
  EXPECT_EQ(a.solver.apic_linear_form, b.solver.apic_linear_form);
  EXPECT_EQ(a.time.rule, b.time.rule);
  EXPECT_EQ(a.time.dt, b.time.dt);
  EXPECT_EQ(a.time.land_on_frames, b.time.land_on_frames);
  EXPECT_EQ(a.domain.dx, b.domain.dx);
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    const SamplingDesc &s = a.objects[i].sampling, &t = b.objects[i].sampling;
    EXPECT_EQ(s.type, t.type);
    EXPECT_EQ(s.spacing, t.spacing);
    EXPECT_EQ(s.ppc, t.ppc);
    EXPECT_EQ(s.radius, t.radius);
  }
}

nlohmann::json result_json(const std::string& run_dir) {
  std::ifstream in(fs::path(run_dir) / "result.json");
  return nlohmann::json::parse(in);
}

// The dt of the first step a run's process took (diagnostics.csv row 1, column dt).
double first_dt(const std::string& run_dir) {
  std::ifstream in(fs::path(run_dir) / "diagnostics.csv");
  std::string header, row0, row1;
  std::getline(in, header), std::getline(in, row0), std::getline(in, row1);
  std::stringstream s(row1);
  std::string step, t, dt;
  std::getline(s, step, ','), std::getline(s, t, ','), std::getline(s, dt, ',');
  return std::stod(dt);
}

// runs.csv as written by `apiclab sweep`: id -> the row's fields by column name.
std::map<std::string, std::map<std::string, std::string>> runs_csv() {
  std::ifstream in(fs::path(kDir) / "runs.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::stringstream h(line); std::getline(h, line, ',');) names.push_back(line);
  std::map<std::string, std::map<std::string, std::string>> rows;
  for (std::string row; std::getline(in, row);) {
    std::map<std::string, std::string> f;
    std::stringstream s(row);
    for (std::size_t k = 0; k < names.size() && std::getline(s, line, ','); ++k) f[names[k]] = line;
    rows[f["id"]] = f;
  }
  return rows;
}

TEST(SweepView, EveryRunRowOpensTheConfigurationItsRunUsed) {
  const auto sw = opened();
  const auto rows = runs_csv();
  ASSERT_EQ(rows.size(), sw->plan.runs.size());
  ASSERT_EQ(sw->missing, 0u);
  std::size_t with_dt = 0;
  for (std::size_t i = 0; i < sw->plan.runs.size(); ++i) {
    const PlannedRun& run = sw->plan.runs[i];
    ASSERT_TRUE(rows.count(run.id)) << run.label();
    const std::string dir = run_dir(kDir, run);
    // What the run's process was given, as its record keeps it (record.cpp: o.sets).
    const nlohmann::json rec = result_json(dir);
    cli::RunOptions used;
    used.scene = run.scene_path;
    used.sets = rec["overrides"].get<std::vector<std::string>>();
    used.precision = rec["precision"].get<std::string>();
    const SceneDesc runner = cli::load_scene_with_options(used);
    // What a click opens for this run: its pane (the second, or the only one for a reference).
    const SweepLaunch l = launch_run(*sw, i);
    ASSERT_EQ(l.panes.size(), run.reference == i ? 1u : 2u);
    const gui::PaneConfig& pane = l.panes.back();
    ASSERT_TRUE(pane.scene);
    expect_same_scene(*pane.scene, runner, run.label());
    EXPECT_EQ(cli::precision_of(used), *pane.precision);
    EXPECT_EQ(pane.scheme, runner.solver.scheme);
    // The derived values against runs.csv's columns (6 significant digits there).
    const auto& row = rows.at(run.id);
    EXPECT_NEAR(pane.scene->domain.dx, std::stod(row.at("dx")), 1e-5 * pane.scene->domain.dx);
    EXPECT_EQ(row.at("solver.scheme"), std::string(key_of(pane.scene->solver.scheme)));
    ASSERT_FALSE(row.at("dt").empty()) << "every run of view.json has a dt_factor";
    EXPECT_NEAR(pane.scene->time.dt, std::stod(row.at("dt")), 1e-5 * pane.scene->time.dt);
    EXPECT_EQ(pane.scene->time.rule, DtRule::fixed);
    // And the simulation the pane builds: the run's particle count and first step.
    auto sim = make_simulation(*pane.scene, *pane.precision);
    EXPECT_EQ(long(particle_count(*sim)), rec["particles"].get<long>()) << run.label();
    DiagnosticsRow r;
    sim->step(pane.scene->time.end, &r);
    EXPECT_EQ(r.dt, first_dt(dir)) << run.label();
    ++with_dt;
    // The reference pane is the reference run's configuration.
    const SceneDesc ref = scene_of(sw->plan.runs[run.reference]);
    expect_same_scene(*l.panes.front().scene, ref, "reference of " + run.label());
  }
  EXPECT_EQ(with_dt, 8u);
  // What hovering a run shows: its configuration, outcome, cost and id.
  const std::string hover = run_summary(*sw, 0);
  EXPECT_NE(hover.find(config_text(sw->spec, sw->plan.runs[0])), std::string::npos) << hover;
  EXPECT_NE(hover.find(sw->results[0].outcome), std::string::npos) << hover;
  EXPECT_NE(hover.find("cost "), std::string::npos) << hover;
  // The resolution axis really changed dx, the dt_factor axis really changed dt.
  std::set<double> dxs, dts;
  for (const PlannedRun& r : sw->plan.runs) dxs.insert(r.dx), dts.insert(r.dt);
  EXPECT_EQ(dxs.size(), 2u);
  EXPECT_EQ(dts.size(), 4u);
}

// The positions a run recorded at frame f (frames.bin, at the run's precision) against a pane's
// snapshot, which holds them as floats.
void expect_frame(const metrics::RunFrames& rec, std::size_t f, const Snapshot& s,
                  const std::string& what) {
  SCOPED_TRACE(what + ", frame " + std::to_string(f));
  ASSERT_LT(f, rec.frames.size());
  EXPECT_DOUBLE_EQ(rec.frames[f].t, s.time);
  ASSERT_EQ(rec.frames[f].positions.size(), s.positions.size());
  std::size_t differ = 0;
  for (std::size_t k = 0; k < s.positions.size(); ++k)
    differ += float(rec.frames[f].positions[k]) != s.positions[k];
  EXPECT_EQ(differ, 0u) << "of " << s.positions.size() << " coordinates";
}

TEST(SweepView, AClickOpensTheRunBesideItsReferenceFromTheSameStart) {
  const auto sw = opened();
  // A point of the error-against-cost chart, as the panel maps it: series 0, point 0.
  const SceneCharts& c = sw->charts.front();
  ASSERT_FALSE(c.cost.empty());
  const std::size_t run = c.cost.front().runs.front();
  ASSERT_NE(sw->plan.runs[run].reference, run) << "charts leave the reference out";
  const SweepLaunch l = launch_run(*sw, run);
  ASSERT_EQ(l.panes.size(), 2u);
  gui::SimWorker w;
  w.load(l.scene, l.panes, l.precision);
  w.sync();
  const auto start = w.latest();
  ASSERT_TRUE(start->error.empty()) << start->error;
  ASSERT_EQ(start->panes.size(), 2u);
  const std::size_t shown[2] = {l.reference, l.run};
  std::vector<metrics::RunFrames> recorded;
  for (std::size_t i : shown) recorded.push_back(read_frames(run_dir(kDir, sw->plan.runs[i])));
  for (int k = 0; k < 2; ++k)
    expect_frame(recorded[std::size_t(k)], 0, *start->panes[std::size_t(k)].snapshot,
                 k ? "run" : "reference");
  // Both start from the same initial state where their configurations agree: same scene, same
  // shapes, and the same initial velocity field (a rigid rotation at 0.4 rad/s).
  EXPECT_EQ(start->panes[0].snapshot->time, 0.0);
  EXPECT_EQ(start->panes[1].snapshot->time, 0.0);
  // One frame in lockstep: each pane where its own `run --record` process was at that frame.
  w.step_frame();
  w.sync(1);
  const auto one = w.latest();
  ASSERT_EQ(one->frame, 1);
  for (int k = 0; k < 2; ++k)
    expect_frame(recorded[std::size_t(k)], 1, *one->panes[std::size_t(k)].snapshot,
                 k ? "run" : "reference");
  // And a fresh simulation of each configuration, advanced the same way in this process:
  // positions and velocities identical.
  for (int k = 0; k < 2; ++k) {
    const PlannedRun& p = sw->plan.runs[shown[k]];
    const SceneDesc scene = scene_of(p);
    auto fresh = make_simulation(scene, cli::precision_of(p.options()));
    Lockstep(std::vector<Simulation*>{fresh.get()})
        .advance_to(one->panes[std::size_t(k)].snapshot->time);
    const auto a = fresh->snapshot();
    const Snapshot& b = *one->panes[std::size_t(k)].snapshot;
    EXPECT_EQ(a->step, b.step);
    EXPECT_EQ(a->positions, b.positions);
    EXPECT_EQ(a->velocities, b.velocities);
    EXPECT_GT(b.step, 2) << "a few steps at least";
  }
}

TEST(SweepView, AStabilityCellOpensItsRun) {
  const auto sw = opened();
  const SceneCharts& c = sw->charts.front();
  ASSERT_TRUE(c.stability);
  const StabilityMap& m = *c.stability;
  // Rows: scheme x resolution; columns: dt_factor.
  ASSERT_EQ(m.column_labels.size(), 2u);
  ASSERT_EQ(m.row_labels.size(), 4u);
  const long cell = m.cells[0][1];
  ASSERT_GE(cell, 0);
  const PlannedRun& p = sw->plan.runs[std::size_t(cell)];
  EXPECT_EQ(p.value_text("dt_factor"), m.column_labels[1]);
  const SweepLaunch l = launch_run(*sw, std::size_t(cell));
  EXPECT_EQ(l.run, std::size_t(cell));
  EXPECT_EQ(l.panes.back().scene->time.dt, p.dt);
  EXPECT_EQ(l.panes.back().scene->domain.dx, p.dx);
}

// A copy of the sweep folder to damage.
std::string copy_of_sweep(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("apiclab-sweep-view-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::copy(kDir, dir, fs::copy_options::recursive);
  return dir.string();
}

// The one line open_sweep refuses a folder with.
std::string refusal(const std::string& dir) {
  try {
    open_sweep(dir);
  } catch (const cli::UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(SweepView, BadFoldersAreRefusedWithOneLine) {
  struct Case {
    std::string name, dir, expect;
  };
  std::vector<Case> cases;
  cases.push_back({"missing", "/nonexistent/sweep", "no such folder"});
  const std::string plain = copy_of_sweep("plain");
  fs::remove(fs::path(plain) / "spec.json");
  cases.push_back({"not a sweep", plain, "not a sweep (no spec.json"});
  const std::string unfinished = copy_of_sweep("unfinished");
  fs::remove_all(fs::path(unfinished) / "runs");
  cases.push_back({"no run finished", unfinished, "has finished yet"});
  // Half-written runs: frames cut mid-frame, a result.json cut short.
  const std::string cut = copy_of_sweep("cut");
  const PlannedRun& first = opened()->plan.runs.front();
  const fs::path frames = fs::path(run_dir(cut, first)) / "frames.bin";
  fs::resize_file(frames, fs::file_size(frames) - 7);
  cases.push_back({"truncated frames", cut, "half-written or damaged: "});
  const std::string broken = copy_of_sweep("broken");
  const fs::path result = fs::path(run_dir(broken, first)) / "result.json";
  fs::resize_file(result, fs::file_size(result) / 2);
  cases.push_back({"cut result.json", broken, "malformed JSON"});
  for (const Case& c : cases) {
    const std::string why = refusal(c.dir);
    EXPECT_NE(why.find(c.expect), std::string::npos) << c.name << ": " << why;
    EXPECT_EQ(why.find('\n'), std::string::npos) << c.name << ": " << why;
    EXPECT_NE(why.find(c.dir), std::string::npos) << c.name << " names the folder: " << why;
  }
  for (const std::string& d : {plain, unfinished, cut, broken}) fs::remove_all(d);
}

TEST(SweepView, APartialSweepOpensWithItsMissingRuns) {
  // A killed sweep: one run's record gone, one half-written folder left (never read).
  const std::string dir = copy_of_sweep("partial");
  const PlannedRun& gone = opened()->plan.runs.back();
  fs::rename(run_dir(dir, gone), run_dir(dir, gone) + ".tmp-12345");
  const auto sw = open_sweep(dir);
  EXPECT_EQ(sw->missing, 1u);
  EXPECT_EQ(sw->results.back().outcome, "no_result");
  fs::remove_all(dir);
}

// Rewrites a frames.bin (ASF2, doubles) in the older format: ASF1, positions as floats.
void write_float_frames(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(b.substr(0, 4), "ASF2");
  std::int32_t dim = 0, bytes = 0;
  std::uint64_t n = 0;
  std::memcpy(&dim, &b[4], 4), std::memcpy(&bytes, &b[8], 4), std::memcpy(&n, &b[12], 8);
  ASSERT_EQ(bytes, 8);
  std::string out = "ASF1" + b.substr(4, 4) + b.substr(12, 8) + b.substr(20, 4 * n);
  for (std::size_t at = 20 + 4 * n; at < b.size(); at += 24 + 8 * n * std::size_t(dim)) {
    out += b.substr(at, 24);
    for (std::size_t k = 0; k < n * std::size_t(dim); ++k) {
      double x;
      std::memcpy(&x, &b[at + 24 + 8 * k], 8);
      const float f = float(x);
      out.append(reinterpret_cast<const char*>(&f), 4);
    }
  }
  std::ofstream(path, std::ios::binary) << out;
}

TEST(SweepView, FramesAreKeptAtTheRunsPrecision) {
  // A double run's positions read back bit for bit as its own double dump would give them.
  const PlannedRun& run = opened()->plan.runs.front();
  std::ifstream in(fs::path(run_dir(kDir, run)) / "frames.bin", std::ios::binary);
  char magic[4];
  std::int32_t dim = 0, bytes = 0;
  in.read(magic, 4), in.read(reinterpret_cast<char*>(&dim), 4);
  in.read(reinterpret_cast<char*>(&bytes), 4);
  EXPECT_EQ(std::string(magic, 4), "ASF2");
  EXPECT_EQ(bytes, 8) << "a double run's frames hold doubles";
}

TEST(SweepView, AnOlderFloatRecordIsRefusedNotMixed) {
  const std::string dir = copy_of_sweep("float");
  write_float_frames(fs::path(run_dir(dir, opened()->plan.runs.back())) / "frames.bin");
  const std::string why = refusal(dir);
  EXPECT_NE(why.find("frames.bin: recorded by an older apiclab with positions as 32-bit floats"),
            std::string::npos)
      << why;
  EXPECT_NE(why.find("records those runs again"), std::string::npos) << why;
  EXPECT_EQ(why.find('\n'), std::string::npos) << why;
  fs::remove_all(dir);
}

TEST(SweepView, ARefusedRunOpensWithItsOutcomeAndCause) {
  const std::string dir = copy_of_sweep("refused");
  const std::size_t last = opened()->plan.runs.size() - 1;
  const std::string run = run_dir(dir, opened()->plan.runs[last]);
  fs::remove_all(run);
  write_refusal(run, 2, "apiclab: the scene needs 3 GB, more than the cap");
  const auto sw = open_sweep(dir);
  EXPECT_EQ(sw->missing, 0u);
  EXPECT_EQ(sw->results[last].outcome, "refused");
  EXPECT_EQ(cell_text(sw->results[last]), "refused, exit 2");
  const std::string hover = run_summary(*sw, last);
  EXPECT_NE(hover.find(config_text(sw->spec, *sw->results[last].run)), std::string::npos) << hover;
  EXPECT_NE(hover.find("refused: exit 2: apiclab: the scene needs 3 GB"), std::string::npos)
      << hover;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace apiclab::sweep
