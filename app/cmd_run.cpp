// `apiclab run SCENE`: headless simulation with diagnostics CSV and optional particle dumps.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli.hpp"
#include "commands.hpp"
#include "sim/diagnostics.hpp"

namespace apiclab::cli {
namespace {

double norm3(const std::array<double, 3>& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

void write_dump(const Simulation& sim, const std::string& dir, int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.csv", frame);
  std::ofstream out(std::filesystem::path(dir) / name);
  if (!out) throw UsageError("cannot write particle dump in '" + dir + "'");
  const TransferControls* particles = sim.transfers();
  if (!particles) throw UsageError("--dump: solver method '" + sim.scene().solver.method + "' has no particles");
  particles->write_particles_csv(out);
}

int run(const RunOptions& o) {
  SceneDesc scene = load_scene_with_options(o);
  apply_threads(o.threads);
  std::string csv = o.csv.empty() ? "apiclab-out/" + scene.name + "-" + std::string(key_of(scene.solver.scheme)) + ".csv" : o.csv;
  ensure_writable_file(csv);
  if (!o.dump.empty()) ensure_writable_dir(o.dump);
  std::ofstream out(csv);
  out << diagnostics_header() << '\n';

  auto sim = make_simulation(scene, precision_of(o));
  const int frames = frame_count(scene);
  const double fps = scene.time.fps;
  DiagnosticsRow first = sim->measure();
  first.dt = 0;
  write_diagnostics_row(out, first);
  if (!o.dump.empty()) write_dump(*sim, o.dump, 0);
  std::string label = scene.name + " [" + std::string(key_of(scene.solver.scheme)) + ", " +
                      std::string(key_of(scene.solver.integrator)) + ", " + std::to_string(particle_count(*sim)) + " particles]";
  Progress progress(label, scene.time.end, o.quiet);
  double start = now_seconds();
  DiagnosticsRow last = first;
  long unconverged = 0;
  for (int f = 1; f <= frames; ++f) {
    double t_frame = f == frames ? scene.time.end : f / fps;
    auto failure = sim->advance_to(t_frame, [&](const DiagnosticsRow& r) {
      write_diagnostics_row(out, r);
      last = r;
      if (!r.converged && unconverged++ == 0)
        std::fprintf(stderr, "\napiclab: warning: implicit solve did not converge at step %ld, t = %g (residual %g); "
                     "continuing (solver.stop_on_nonconvergence stops instead)\n", r.step, r.t, r.residual);
      std::ostringstream extra;
      extra << "t=" << r.t << " step " << r.step;
      progress.update(r.t, extra.str());
    });
    if (failure) {
      out.flush();
      progress.finish("apiclab: " + failure->message + " (diagnostics so far in " + csv + ")");
      return 3;
    }
    if (!o.dump.empty()) write_dump(*sim, o.dump, f);
  }
  double wall = now_seconds() - start;
  double dE = (last.total - first.total) / std::max(std::abs(first.total), 1e-300);
  std::array<double, 3> dL{last.L[0] - first.L[0], last.L[1] - first.L[1], last.L[2] - first.L[2]};
  // |L0| below round-off of the momentum scale √(2 K M)·extent counts as zero: report |ΔL|.
  double extent = 0;
  for (int a = 0; a < scene.dim; ++a) extent = std::max(extent, std::abs(scene.domain.max[a]) + std::abs(scene.domain.min[a]));
  double L_scale = std::sqrt(2 * std::max(first.kinetic, 0.0) * sim->total_mass()) * extent;
  double L0 = norm3(first.L) > 1e-12 * L_scale ? norm3(first.L) : 0.0;
  std::ostringstream s;
  s.precision(4);
  s << scene.name << ": t = " << sim->time() << " s in " << sim->steps() << " steps, " << wall << " s wall, "
    << double(particle_count(*sim)) * double(sim->steps()) / std::max(wall, 1e-9) << " particle-steps/s; dE/E = " << dE
    << ", dL/L = " << (L0 > 0 ? norm3(dL) / L0 : norm3(dL)) << (L0 > 0 ? "" : " (absolute; L0 = 0)")
    << "\ndiagnostics CSV: " << csv;
  if (unconverged) s << "\nwarning: " << unconverged << " steps ended with a non-converged implicit solve (see residual)";
  if (!o.dump.empty()) s << "\nparticle dumps: " << o.dump << "/frame_0000.csv ...";
  progress.finish(s.str());
  return 0;
}

}  // namespace

void register_run(CLI::App& root, CommandTable& table) {
  auto opts = std::make_shared<RunOptions>();
  CLI::App* cmd = root.add_subcommand("run", "headless simulation; diagnostics CSV, progress on stderr");
  add_run_options(cmd, *opts);
  table.push_back({cmd, [opts] { return run(*opts); }});
}

}  // namespace apiclab::cli
