// `apiclab run SCENE`: headless simulation with diagnostics CSV and optional particle dumps.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/clock.hpp"
#include "app/frame_loop.hpp"
#include "cli.hpp"
#include "commands.hpp"
#include "sim/diagnostics.hpp"
#include "sim/run_summary.hpp"

namespace apiclab::cli {
namespace {

void write_dump(const Simulation& sim, const std::string& dir, int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.csv", frame);
  std::ofstream out(std::filesystem::path(dir) / name);
  if (!out) throw UsageError("cannot write particle dump in '" + dir + "'");
  const TransferControls* particles = sim.transfers();
  if (!particles)
    throw UsageError("--dump: solver method '" + sim.scene().solver.method + "' has no particles");
  particles->write_particles_csv(out);
}

int run(const RunOptions& o) {
  SceneDesc scene = load_scene_with_options(o);
  apply_threads(o.threads);
  // The transfer scheme names an MPM run; a method without schemes (eol, eulerian) names itself.
  const std::string scheme =
      scene.solver.method == "mpm" ? std::string(key_of(scene.solver.scheme)) : scene.solver.method;
  std::string csv = o.csv.empty() ? "apiclab-out/" + scene.name + "-" + scheme + ".csv" : o.csv;
  ensure_writable_file(csv);
  if (!o.dump.empty()) ensure_writable_dir(o.dump);
  std::ofstream out(csv);
  out << diagnostics_header() << '\n';

  auto sim = make_simulation(scene, precision_of(o));
  DiagnosticsRow first = sim->measure();
  first.dt = 0;
  write_diagnostics_row(out, first);
  RunSummary summary(first, sim->total_mass(), DriftRule::domain_extent(scene));
  std::string label = scene.name + " [" + scheme + ", " +
                      std::string(key_of(scene.solver.integrator)) + ", " +
                      std::to_string(particle_count(*sim)) + " particles]";
  Progress progress(label, scene.time.end, o.quiet);
  double start = now_seconds();
  long unconverged = 0;
  Lockstep panes({sim.get()});
  const auto on_row = [&](std::size_t, const DiagnosticsRow& r) {
    write_diagnostics_row(out, r);
    summary.add(r);
    if (!r.converged && unconverged++ == 0)
      std::fprintf(
          stderr,
          "\napiclab: warning: implicit solve did not converge at step %ld, t = %g (residual %g); "
          "continuing (solver.stop_on_nonconvergence stops instead)\n",
          r.step, r.t, r.residual);
    std::ostringstream extra;
    extra << "t=" << r.t << " step " << r.step;
    progress.update(r.t, extra.str());
  };
  run_frame_loop(FrameTimes(scene), panes, on_row, [&](int f) {
    if (sim->failure()) return false;
    if (!o.dump.empty()) write_dump(*sim, o.dump, f);
    return true;
  });
  if (const auto& failure = sim->failure()) {
    out.flush();
    progress.finish("apiclab: " + failure->message + " (diagnostics so far in " + csv + ")");
    return 3;
  }
  double wall = now_seconds() - start;
  std::ostringstream s;
  s.precision(4);
  s << scene.name << ": t = " << sim->time() << " s in " << sim->steps() << " steps, " << wall
    << " s wall, " << double(particle_count(*sim)) * double(sim->steps()) / std::max(wall, 1e-9)
    << " particle-steps/s; dE/E = " << summary.energy_drift()
    << ", dL/L = " << summary.angular_momentum_drift()
    << (summary.angular_momentum_relative() ? "" : " (absolute; L0 = 0)")
    << "\ndiagnostics CSV: " << csv;
  if (unconverged)
    s << "\nwarning: " << unconverged
      << " steps ended with a non-converged implicit solve (see residual)";
  if (!o.dump.empty()) s << "\nparticle dumps: " << o.dump << "/frame_0000.csv ...";
  progress.finish(s.str());
  return 0;
}

}  // namespace

void register_run(CLI::App& root, CommandTable& table) {
  auto opts = std::make_shared<RunOptions>();
  CLI::App* cmd =
      root.add_subcommand("run", "headless simulation; diagnostics CSV, progress on stderr");
  add_run_options(cmd, *opts);
  table.push_back({cmd, [opts] { return run(*opts); }});
}

}  // namespace apiclab::cli
