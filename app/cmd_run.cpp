// `apiclab run SCENE`: headless simulation with diagnostics CSV and optional particle dumps.
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "app/cli_checks.hpp"
#include "app/clock.hpp"
#include "app/frame_loop.hpp"
#include "app/output_file.hpp"
#include "app/output_owner.hpp"
#include "app/run_outputs.hpp"
#include "app/stop_signal.hpp"
#include "app/sweep/record.hpp"
#include "cli.hpp"
#include "commands.hpp"
#include "sim/measure/diagnostics.hpp"
#include "sim/measure/run_summary.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"

namespace apiclab::cli {
namespace {

// run's own options beyond the common ones.
struct RunCommandOptions {
  RunOptions run;
  std::string summary;  // --summary FILE.json
};

std::string steps_text(long n) { return std::to_string(n) + (n == 1 ? " step" : " steps"); }

// The one line of a run that SIGINT/SIGTERM stopped: where, and which files hold what.
std::string stopped_text(int signal, const Simulation& sim, const std::string& csv,
                         const std::string& dump, int last_frame) {
  std::ostringstream s;
  s << "apiclab: stopped by " << (signal == SIGINT ? "SIGINT" : "SIGTERM") << " at step "
    << sim.steps() << ", t = " << sim.time() << " s; diagnostics in " << csv;
  if (!dump.empty())
    s << ", frames 0.." << last_frame << " in " << dump << " (listed in " << dump << "/frames.csv)";
  return s.str();
}

int run(const RunCommandOptions& command) {
  const RunOptions& o = command.run;
  const double cpu_start = cpu_seconds();
  install_stop_handlers();  // a signal during the set-up stops the run after frame 0
  SceneDesc scene = load_scene_with_options(o);
  check_flip_alpha(o, {scene.solver.scheme});
  const std::vector<DumpFormat> formats = dump_formats_of(o, scene.solver.method == "mpm");
  apply_threads(o.threads);
  // The transfer scheme names an MPM run; a method without schemes (eol, eulerian) names itself.
  const std::string scheme =
      scene.solver.method == "mpm" ? std::string(key_of(scene.solver.scheme)) : scene.solver.method;
  // The scene's name as a file name: a name from a scene file never leaves apiclab-out/.
  const std::string csv =
      o.csv.empty() ? "apiclab-out/" + safe_file_name(scene.name) + "-" + scheme + ".csv" : o.csv;
  const nlohmann::json settings = run_settings(scene, precision_of(o), o.sets);
  OutputClaims claims(settings, o.overwrite);  // before any output: whose files these are
  claims.scene_inputs(scene);
  claims.csv(o.csv.empty() ? "the default CSV" : "--csv", csv);
  if (!command.summary.empty()) claims.summary("--summary", command.summary);
  if (!o.dump.empty()) claims.frames("--dump", o.dump);
  claims.check_and_clear();
  ensure_writable_file(csv);
  if (!command.summary.empty()) ensure_writable_file(command.summary);
  auto sim = make_simulation(scene, precision_of(o));
  if (!o.dump.empty() && !sim->transfers() && formats_need_particles(formats))
    throw UsageError("--dump: solver method '" + scene.solver.method + "' " +
                     dump_without_particles);
  if (!o.dump.empty()) ensure_writable_dir(o.dump);
  ParticleDump dump(o.dump, formats);
  RowFile out(csv);
  out.write_row(std::string(diagnostics_header()) + '\n');
  write_csv_sidecar(csv, settings);
  if (const std::string note = time_step_note(scene); !note.empty() && !o.quiet)
    std::fprintf(stderr, "apiclab: %s\n", note.c_str());

  DiagnosticsRow first = sim->measure();
  first.dt = 0;
  out.write_row(diagnostics_row_text(first));
  RunSummary summary(first, sim->total_mass(), DriftRule::domain_extent(scene));
  std::string label = scene.name + " [" + run_label(scene) + ", " + integrator_label(scene.solver) +
                      ", " + sim->model_size() + "]";
  Progress progress(label, scene.time.end, o.quiet);
  progress.update(0, "starting");
  // A long implicit step reports its Newton iterations, so the line never goes quiet.
  sim->on_solver_iteration([&](int newton, int cg, double residual) {
    std::ostringstream extra;
    extra << "t=" << sim->time() << " step " << sim->steps() + 1 << ": Newton " << newton << ", CG "
          << cg << ", residual " << residual;
    progress.update(sim->time(), extra.str());
  });
  FrameIndex frames;
  if (!o.dump.empty()) {
    frames = FrameIndex(o.dump);
    write_csv_sidecar((std::filesystem::path(o.dump) / "frames.csv").string(), settings);
  }
  double start = now_seconds();
  long unconverged = 0;
  Lockstep panes({sim.get()});
  const auto on_row = [&](std::size_t, const DiagnosticsRow& r) {
    out.write_row(diagnostics_row_text(r));
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
  int last_frame = -1;
  run_frame_loop(FrameTimes(scene, o.max_steps), panes, on_row, [&](int f) {
    if (sim->failure()) return false;
    if (!o.dump.empty()) {
      dump.write(*sim, f);  // the frame's files first, then its row in the index
      frames.add(f, sim->time(), {sim->steps()});  // the frame's real time
    }
    last_frame = f;
    return true;
  });
  sim->on_solver_iteration(nullptr);
  if (const int signal = stop_signal()) {
    progress.finish(stopped_text(signal, *sim, csv, o.dump, last_frame));
    return stop_exit_code(signal);
  }
  double wall = now_seconds() - start;
  if (!command.summary.empty()) {
    const RunCosts costs{wall, cpu_seconds() - cpu_start, particle_count(*sim)};
    nlohmann::json j =
        run_summary_json(scene, settings, summary, sim->time(), costs, sim->failure());
    j["outputs"] = {{"csv", csv},
                    {"dump", o.dump.empty() ? nlohmann::json() : nlohmann::json(o.dump)}};
    write_file_whole(command.summary, j.dump(2) + '\n');
  }
  if (const auto& failure = sim->failure()) {
    progress.finish("apiclab: " + failure->message + " (diagnostics so far in " + csv + ")");
    return 3;
  }
  std::ostringstream s;
  s.precision(4);
  s << scene.name << ": t = " << sim->time() << " s in " << steps_text(sim->steps()) << " ("
    << dt_stats_text(summary.dt()) << "), " << wall << " s wall, ";
  // A grid method (eol, eulerian) has no particles: its rate is steps per second.
  const double particles = double(particle_count(*sim)), per_second = 1 / std::max(wall, 1e-9);
  if (particles > 0)
    s << particles * double(sim->steps()) * per_second << " particle-steps/s";
  else
    s << double(sim->steps()) * per_second << " steps/s";
  s << "; dE/E = " << summary.energy_drift();
  if (summary.angular_momentum_relative())
    s << ", |dL|/|L0| = " << summary.angular_momentum_drift();
  else
    s << ", |dL| = " << summary.angular_momentum_drift() << " kg m^2/s (absolute: L0 is round-off)";
  s << "\ndiagnostics CSV: " << csv << " (settings in " << csv << ".json)";
  if (unconverged)
    s << "\napiclab: warning: " << steps_text(unconverged)
      << " ended with a non-converged implicit solve (see residual)";
  if (!o.dump.empty()) {
    std::string ext;
    for (DumpFormat f : formats) ext += (ext.empty() ? "" : ",") + std::string(extension_of(f));
    // Without particles (EoL) the files are the surfaces (and, with VTK, the grids).
    s << "\ndumps: " << o.dump << (sim->transfers() ? "/frame_0000." : "/frame_0000_surface0.")
      << (formats.size() > 1 ? "{" + ext + "}" : ext) << " ... (real frame times in " << o.dump
      << "/frames.csv";
    if (std::any_of(formats.begin(), formats.end(), is_vtk))
      s << "; ParaView opens " << o.dump << "/series.pvd";
    s << ")";
  }
  if (!command.summary.empty()) s << "\nrun summary: " << command.summary;
  progress.finish(s.str());
  return 0;
}

}  // namespace

void register_run(CLI::App& root, CommandTable& table) {
  auto opts = std::make_shared<RunCommandOptions>();
  CLI::App* cmd =
      root.add_subcommand("run", "headless simulation; diagnostics CSV, progress on stderr");
  add_run_options(cmd, opts->run);
  cmd->add_option("--summary", opts->summary,
                  "write a JSON run summary (settings, steps, dt statistics, costs, drifts, "
                  "failure) to this file [default: none]");
  auto record = std::make_shared<std::string>();
  cmd->add_option("--record", *record,
                  "a sweep run: diagnostics, frames and result.json into this folder, written "
                  "whole or not at all (app/sweep/record.hpp) [default: none]");
  table.push_back({cmd, [opts, record] {
                     return record->empty() ? run(*opts) : sweep::record_run(opts->run, *record);
                   }});
}

}  // namespace apiclab::cli
