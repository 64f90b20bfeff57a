// `apiclab run SCENE`: headless simulation with diagnostics CSV and optional particle dumps.
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

#include "app/checkpoint.hpp"
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
#include "sim/state_io.hpp"

namespace apiclab::cli {
namespace {

// run's own options beyond the common ones.
struct RunCommandOptions {
  RunOptions run;
  std::string summary;  // --summary FILE.json
  CheckpointOptions checkpoint;
  std::string resume;  // --resume DIR
};

// Options a resume without SCENE may give: the rest come from the checkpoint.
bool resume_may_set(const std::string& option) {
  return option == "--resume" || option == "--threads" || option == "--quiet";
}

// --resume DIR: reads and checks the checkpoint; without SCENE takes the run's options from it
// and goes to the folder the run started in. The thread count defaults to the checkpoint's.
CheckpointFile prepare_resume(RunCommandOptions& c, const CLI::App& cmd) {
  const std::string dir = c.resume;
  CheckpointFile f = read_checkpoint(dir);
  c.resume = std::filesystem::absolute(dir).string();
  const nlohmann::json& h = f.header;
  const int threads = c.run.threads ? c.run.threads : h.value("threads", 0);
  if (c.run.scene.empty()) {
    for (const CLI::Option* opt : cmd.get_options())
      if (opt->count() > 0 && !resume_may_set(opt->get_name()))
        throw UsageError("--resume " + dir + " without SCENE runs the checkpoint's own options: " +
                         "leave out " + opt->get_name() + ", or give SCENE and the same options");
    const bool quiet = c.run.quiet;
    c.run = RunOptions{};
    options_from_json(h.value("options", nlohmann::json()), c.run, c.summary, c.checkpoint);
    c.run.quiet = quiet;
    const std::string cwd = h.value("cwd", "");
    if (::chdir(cwd.c_str()) != 0)
      throw UsageError("checkpoint " + dir + ": cannot enter the folder the run started in, " +
                       cwd);
  }
  c.run.threads = threads;
  return f;
}

// A resumed run's scene, settings and outputs are the checkpoint's, or it is refused.
void check_resume_matches(const CheckpointFile& f, const std::string& dir,
                          const nlohmann::json& settings, const std::string& csv) {
  const nlohmann::json& h = f.header;
  const nlohmann::json theirs = h.value("settings", nlohmann::json());
  if (theirs.value("scene", "") != settings.value("scene", ""))
    throw UsageError("checkpoint " + dir + " belongs to scene '" + theirs.value("scene", "") +
                     "', not '" + settings.value("scene", "") + "'");
  if (const std::string d = settings_difference(theirs, settings); !d.empty())
    throw UsageError("checkpoint " + dir + " was written with other settings: " + d);
  namespace fs = std::filesystem;
  const fs::path their_csv = fs::path(h.value("cwd", "")) / h.value("csv", "");
  if (fs::weakly_canonical(their_csv) != fs::weakly_canonical(fs::absolute(csv)))
    throw UsageError("checkpoint " + dir + " belongs to the run whose CSV is " +
                     their_csv.string() + ", not " + csv);
}

// A file the resumed run continues holds at least the bytes the checkpoint counted.
void check_output_length(const std::string& dir, const std::string& path, std::uint64_t bytes) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec || size < bytes)
    throw UsageError("checkpoint " + dir + ": " + path + " holds " +
                     (ec ? std::string("nothing") : std::to_string(size) + " bytes") +
                     ", fewer than the " + std::to_string(bytes) +
                     " the checkpoint counted: it is not this run's output");
}

// The line a resumed run starts with: where, and whether the end is bit for bit.
std::string resume_text(const CheckpointFile& f, const std::string& dir, int threads) {
  const nlohmann::json& h = f.header;
  std::ostringstream s;
  s << "resuming " << h.value("scene", "") << " from " << dir << " at frame "
    << h.value("frame", -1) << " (step " << h.value("step", 0L) << ", t = " << h.value("t", 0.0)
    << " s)";
  const int theirs = h.value("threads", 0);
  if (theirs == threads)
    s << " with the build and thread count (" << threads
      << ") that wrote it: the outputs end bit for bit as a run never stopped";
  else
    s << " with " << threads << " threads where the checkpoint ran on " << theirs
      << ": the same physics, not the same bits";
  return s.str();
}

std::string steps_text(long n) { return std::to_string(n) + (n == 1 ? " step" : " steps"); }

// The one line of a run that SIGINT/SIGTERM stopped: where, and which files hold what.
std::string stopped_text(int signal, const Simulation& sim, const std::string& csv,
                         const std::string& dump, int last_frame, const std::string& checkpoint) {
  std::ostringstream s;
  s << "apiclab: stopped by " << (signal == SIGINT ? "SIGINT" : "SIGTERM") << " at step "
    << sim.steps() << ", t = " << sim.time() << " s; diagnostics in " << csv;
  if (!dump.empty())
    s << ", frames 0.." << last_frame << " in " << dump << " (listed in " << dump << "/frames.csv)";
  if (!checkpoint.empty())
    s << "; checkpoint in " << checkpoint << " (apiclab run --resume " << checkpoint
      << " continues)";
  return s.str();
}

int run(const RunCommandOptions& given, const CLI::App& cmd) {
  const double cpu_start = cpu_seconds();
  install_stop_handlers();  // a signal during the set-up stops the run after frame 0
  RunCommandOptions command = given;
  std::optional<CheckpointFile> resumed;
  if (!command.resume.empty()) resumed = prepare_resume(command, cmd);
  const RunOptions& o = command.run;
  if (o.scene.empty() && cmd.get_option("scene")->count() == 0)  // "" goes on to its own message
    throw UsageError("scene is required (see apiclab run --help)");
  const std::string run_cwd = std::filesystem::current_path().string();
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
  const std::string checkpoint_dir =
      command.checkpoint.on() ? checkpoint_dir_of(command.checkpoint, csv) : "";
  if (resumed) {
    check_resume_matches(*resumed, command.resume, settings, csv);
  } else {
    OutputClaims claims(settings, o.overwrite);  // before any output: whose files these are
    claims.scene_inputs(scene);
    claims.csv(o.csv.empty() ? "the default CSV" : "--csv", csv);
    if (!command.summary.empty()) claims.summary("--summary", command.summary);
    if (!o.dump.empty()) claims.frames("--dump", o.dump);
    claims.check_and_clear();
    ensure_writable_file(csv);
    if (!command.summary.empty()) ensure_writable_file(command.summary);
  }
  auto sim = make_simulation(scene, precision_of(o));
  if (!o.dump.empty() && !sim->transfers() && formats_need_particles(formats))
    throw UsageError("--dump: solver method '" + scene.solver.method + "' " +
                     dump_without_particles);
  if ((command.checkpoint.on() || resumed) && !sim->checkpoints())
    throw UsageError("solver method '" + scene.solver.method +
                     "' has no checkpoints (--checkpoint-every, --resume)");
  if (!checkpoint_dir.empty()) {
    ensure_writable_dir(checkpoint_dir);
    // A fresh run's checkpoint replaces an earlier one at once: none may outlive its outputs.
    if (!resumed) std::filesystem::remove(checkpoint_path(checkpoint_dir));
  }
  if (!o.dump.empty()) ensure_writable_dir(o.dump);
  ParticleDump dump(o.dump, formats);
  // A resumed run reads its own state past the header: the output indexes first.
  StateReader state(resumed ? resumed->bytes.data() + resumed->state_at : nullptr,
                    resumed ? resumed->state_size : 0);
  RunProgress resumed_at;  // where the checkpoint left the outputs
  const auto refuse_state = [&](const StateError& e) {
    return UsageError("checkpoint " + command.resume + ": " + e.what());
  };
  DiagnosticsRow first = sim->measure();
  first.dt = 0;
  RunSummary summary(DriftRule::of(*sim, first));
  if (resumed) try {
      std::vector<PvdSeries::Entry> series;
      resumed_at = load_run_state(state, summary, series);
      dump.series().restore(std::move(series));
    } catch (const StateError& e) {
      throw refuse_state(e);
    }
  int last_frame = resumed_at.last_frame;
  long unconverged = long(resumed_at.unconverged);
  if (resumed) check_output_length(command.resume, csv, resumed_at.csv_bytes);
  if (resumed && !o.dump.empty())
    check_output_length(command.resume, (std::filesystem::path(o.dump) / "frames.csv").string(),
                        resumed_at.frames_bytes);
  RowFile out = resumed ? RowFile(csv, resumed_at.csv_bytes) : RowFile(csv);
  if (!resumed) {
    out.write_row(diagnostics_header(scene.solver.ledger) + '\n');
    write_csv_sidecar(csv, settings);
  }
  if (const std::string note = time_step_note(scene); !note.empty() && !o.quiet)
    std::fprintf(stderr, "apiclab: %s\n", note.c_str());
  if (!resumed) out.write_row(diagnostics_row_text(first));
  if (resumed) try {
      sim->load_state(state);
    } catch (const StateError& e) {
      throw refuse_state(e);
    }
  const int threads = omp_get_max_threads();
  if (resumed && (!o.quiet || resumed->header.value("threads", 0) != threads))
    std::fprintf(stderr, "apiclab: %s\n", resume_text(*resumed, command.resume, threads).c_str());
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
  if (!o.dump.empty() && resumed) {
    frames = FrameIndex(o.dump, resumed_at.frames_bytes);
  } else if (!o.dump.empty()) {
    frames = FrameIndex(o.dump);
    write_csv_sidecar((std::filesystem::path(o.dump) / "frames.csv").string(), settings);
  }
  double start = now_seconds(), last_checkpoint = start, checkpoint_wall = 0;
  const long long steps_at_start = sim->steps();  // a resumed run's rates count its own steps
  int checkpoints = 0;
  std::optional<CheckpointWriter> checkpoint;
  if (!checkpoint_dir.empty()) checkpoint.emplace(checkpoint_dir);
  // The run's state after its last whole row: output indexes, running diagnostics, the solver;
  // the file is written while the run goes on.
  const auto save_checkpoint = [&] {
    const double begin = now_seconds();
    StateWriter w(checkpoint->state());
    save_run_state(w, {last_frame, out.size(), frames.size(), unconverged}, summary,
                   dump.series().entries());
    sim->save_state(w);
    checkpoint->write(run_header(*sim, settings, csv, run_cwd, last_frame,
                                 options_json(o, command.summary, command.checkpoint)));
    last_checkpoint = now_seconds();
    checkpoint_wall += last_checkpoint - begin;
    ++checkpoints;
  };
  // Waits for the checkpoint being written; its WriteError stops the run.
  const auto finish_checkpoint = [&] {
    const double begin = now_seconds();
    if (checkpoint) checkpoint->finish();
    checkpoint_wall += now_seconds() - begin;
  };
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
    if (checkpoint) checkpoint->check();
    const double seconds = command.checkpoint.every_seconds;
    if (seconds > 0 && !sim->failure() && now_seconds() - last_checkpoint >= seconds)
      save_checkpoint();
  };
  run_frame_loop(
      FrameTimes(scene, o.max_steps), panes, on_row,
      [&](int f) {
        if (sim->failure()) return false;
        if (!o.dump.empty()) {
          dump.write(*sim, f);  // the frame's files first, then its row in the index
          frames.add(f, sim->time(), {sim->steps()});  // the frame's real time
        }
        last_frame = f;
        const int every = command.checkpoint.every_frames;
        if (every > 0 && f > 0 && f % every == 0) save_checkpoint();
        return true;
      },
      resumed ? last_frame : -1);
  sim->on_solver_iteration(nullptr);
  finish_checkpoint();
  if (const int signal = stop_signal()) {
    // Stopped between steps: the state is whole, so a checkpointing run keeps it.
    const bool keep = !checkpoint_dir.empty() && !sim->failure();
    if (keep) save_checkpoint(), finish_checkpoint();
    progress.finish(
        stopped_text(signal, *sim, csv, o.dump, last_frame, keep ? checkpoint_dir : ""));
    return stop_exit_code(signal);
  }
  double wall = now_seconds() - start;
  if (!command.summary.empty()) {
    const RunCosts costs{wall, cpu_seconds() - cpu_start, particle_count(*sim),
                         sim->steps() - steps_at_start};
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
  const double steps_timed = double(sim->steps() - steps_at_start);
  if (particles > 0)
    s << particles * steps_timed * per_second << " particle-steps/s";
  else
    s << steps_timed * per_second << " steps/s";
  if (summary.energy_relative())
    s << "; dE/E = " << summary.energy_drift();
  else
    s << "; dE = " << summary.energy_drift() << " J (absolute: E0 is round-off)";
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
  if (checkpoints > 0)
    s << "\ncheckpoints: " << checkpoints << " written to " << checkpoint_path(checkpoint_dir)
      << ", the run held up " << checkpoint_wall << " s wall by them (apiclab run --resume "
      << checkpoint_dir << " continues from the last)";
  progress.finish(s.str());
  return 0;
}

}  // namespace

void register_run(CLI::App& root, CommandTable& table) {
  auto opts = std::make_shared<RunCommandOptions>();
  CLI::App* cmd =
      root.add_subcommand("run", "headless simulation; diagnostics CSV, progress on stderr");
  add_run_options(cmd, opts->run, RunOptionSet{.scene_required = false});
  cmd->add_option("--summary", opts->summary,
                  "write a JSON run summary (settings, steps, dt statistics, costs, drifts, "
                  "failure) to this file [default: none]");
  auto record = std::make_shared<std::string>();
  cmd->add_option("--record", *record,
                  "a sweep run: diagnostics, frames and result.json into this folder, written "
                  "whole or not at all (app/sweep/record.hpp) [default: none]");
  cmd->add_option("--checkpoint-every", opts->checkpoint.every_frames,
                  "write a checkpoint after every N-th frame into --checkpoint-dir, whole or "
                  "not at all (run --resume DIR continues the run from it) [allowed: integer >= "
                  "1; default: none]")
      ->check(whole_number(1, std::numeric_limits<int>::max()));
  cmd->add_option("--checkpoint-seconds", opts->checkpoint.every_seconds,
                  "write a checkpoint after the first step S wall seconds past the last one "
                  "[allowed: > 0; default: none]")
      ->check(number_above(0));
  cmd->add_option("--checkpoint-dir", opts->checkpoint.dir,
                  "folder of the checkpoint; a SIGINT or SIGTERM writes one there too [default: "
                  "the CSV's path with .checkpoint for .csv]");
  cmd->add_option("--resume", opts->resume,
                  "continue the run whose checkpoint folder DIR is: every output goes on where "
                  "the checkpoint left it; without SCENE the run's own options, with SCENE the "
                  "same ones (else refused) [default: none]");
  table.push_back(
      {cmd, [opts, record, cmd] {
         if (!record->empty() && !opts->resume.empty())
           throw UsageError(
               "--record runs take no --resume: the same command with "
               "--checkpoint-every resumes from the record's checkpoint");
         if (!record->empty() && !opts->checkpoint.dir.empty() && !opts->checkpoint.on())
           throw UsageError("--checkpoint-dir needs --checkpoint-every or --checkpoint-seconds");
         if (!record->empty() && cmd->get_option("scene")->count() == 0)
           throw UsageError("scene is required (see apiclab run --help)");
         return record->empty() ? run(*opts, *cmd)
                                : sweep::record_run(opts->run, *record, opts->checkpoint);
       }});
}

}  // namespace apiclab::cli
