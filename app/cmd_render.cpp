// `apiclab render` and `apiclab compare`: headless PNG frames through EGL (OSMesa fallback).
// render draws one simulation; compare advances several schemes in lockstep from the same
// scene and draws them side by side, one diagnostics CSV per scheme.
#include <algorithm>
#include <csignal>
#include <exception>
#include <filesystem>
#include <set>
#include <sstream>

#include "app/frame_loop.hpp"
#include "app/output_owner.hpp"
#include "app/pane_spec.hpp"
#include "app/render_session.hpp"
#include "app/run_outputs.hpp"
#include "app/stop_signal.hpp"
#include "app/video.hpp"
#include "cli.hpp"
#include "commands.hpp"
#include "sim/measure/diagnostics.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"

namespace apiclab::cli {
namespace {

// A diagnostics CSV, written a whole row at a time, with its settings sidecar (NAME.csv.json,
// app/run_outputs.hpp).
RowFile open_csv(const std::string& path, const nlohmann::json& settings, bool ledger) {
  ensure_writable_file(path);
  RowFile out(path);
  out.write_row(diagnostics_header(ledger) + '\n');
  write_csv_sidecar(path, settings);
  return out;
}

// A frame folder's frames.csv with the settings beside it (frames.csv.json): whose frames these
// are (app/output_owner.hpp).
FrameIndex open_frame_index(const std::string& dir, const nlohmann::json& settings,
                            const std::vector<std::string>& panes = {}) {
  FrameIndex index(dir, panes);
  write_csv_sidecar((std::filesystem::path(dir) / "frames.csv").string(), settings);
  return index;
}

// The frame's time (the healthy panes share it; a pane that failed stopped earlier) and each
// pane's step count, as frames.csv records them once the frame's PNG is whole.
std::function<void()> frame_row(FrameIndex& index, int frame, const Lockstep& panes) {
  std::vector<long> steps;
  double t = 0;
  for (std::size_t k = 0; k < panes.size(); ++k) {
    steps.push_back(panes[k].steps());
    t = std::max(t, panes[k].time());
  }
  return [&index, frame, t, steps] { index.add(frame, t, steps); };
}

// When a write fails mid-sequence, the PNG still being written is finished and indexed, so
// frames.csv lists exactly the PNGs present.
struct IndexOnFailure {
  RenderSession& session;
  explicit IndexOnFailure(RenderSession& s) : session(s) {}
  IndexOnFailure(const IndexOnFailure&) = delete;
  IndexOnFailure& operator=(const IndexOnFailure&) = delete;
  ~IndexOnFailure() {
    if (std::uncaught_exceptions() == 0) return;
    try {
      session.flush();
    } catch (const std::exception&) {  // the first failure is the one reported
    }
  }
};

// The one line of a render or compare that SIGINT/SIGTERM stopped: where, and what is where.
std::string render_stopped_text(int signal, int last_frame, double t, const std::string& out,
                                const std::string& csvs) {
  std::ostringstream s;
  s << "apiclab: stopped by " << (signal == SIGINT ? "SIGINT" : "SIGTERM") << " after frame "
    << last_frame << ", t = " << t << " s; frames 0.." << last_frame << " in " << out
    << " (listed in " << out << "/frames.csv), diagnostics in " << csvs;
  return s.str();
}

// A long implicit step shows its Newton and CG iterations on the progress line (`frame` is
// the frame being computed).
void show_solver_progress(Simulation& sim, Progress& progress, const int& frame, int frames) {
  sim.on_solver_iteration([&sim, &progress, &frame, frames](int newton, int cg, double residual) {
    std::ostringstream s;
    s << "frame " << frame << "/" << frames << ", t=" << sim.time() << ": Newton " << newton
      << ", CG " << cg << ", residual " << residual;
    progress.update(frame, s.str());
  });
}

void print_time_step_note(const SceneDesc& scene, bool quiet) {
  if (const std::string note = time_step_note(scene); !note.empty() && !quiet)
    std::fprintf(stderr, "apiclab: %s\n", note.c_str());
}

int render(const RenderOptions& o) {
  install_stop_handlers();  // a signal during the set-up stops after frame 0
  RenderSession session(o);
  const SceneDesc& scene = session.scene;
  // The transfer scheme names an MPM run; a method without schemes (eol, eulerian) names itself.
  const std::string scheme =
      scene.solver.method == "mpm" ? std::string(key_of(scene.solver.scheme)) : scene.solver.method;
  const std::string csv_path = o.run.csv.empty() ? o.out + "/" + scheme + ".csv" : o.run.csv;
  const nlohmann::json settings = run_settings(scene, precision_of(o.run), o.run.sets);
  const bool own_dump = !o.run.dump.empty() && o.run.dump != o.out;  // else one frames.csv
  OutputClaims claims(settings, o.run.overwrite);
  claims.scene_inputs(scene);
  claims.csv(o.run.csv.empty() ? "the default CSV" : "--csv", csv_path);
  claims.frames("--out", o.out);
  if (own_dump) claims.frames("--dump", o.run.dump);
  if (!o.video.empty()) claims.plain("--video", o.video, "ftyp", 4);
  claims.check_and_clear();
  RowFile csv = open_csv(csv_path, settings, scene.solver.ledger);
  if (!o.run.dump.empty()) ensure_writable_dir(o.run.dump);
  ParticleDump dump(o.run.dump, dump_formats_of(o.run, scene.solver.method == "mpm"));
  print_time_step_note(scene, o.run.quiet);
  // The real time of every frame: PNGs in --out, particle dumps in --dump.
  FrameIndex frame_times = open_frame_index(o.out, settings), dump_times;
  if (own_dump) dump_times = open_frame_index(o.run.dump, settings);

  auto sim = make_simulation(scene, precision_of(o.run));
  const bool noise = session.style.color == render::ColorMode::noise;
  const FrameTimes times(scene, o.run.max_steps);
  DiagnosticsRow first = sim->measure();
  first.dt = 0;
  csv.write_row(diagnostics_row_text(first));
  Progress progress(scene.name + " [" + run_label(scene) + ", " + sim->model_size() + "]",
                    times.frames + 1, o.run.quiet);
  int computing = 1;  // the frame being computed, for the solver's progress
  show_solver_progress(*sim, progress, computing, times.frames);
  int status = 0;
  Lockstep panes({sim.get()});
  const auto on_row = [&](std::size_t, const DiagnosticsRow& r) {
    csv.write_row(diagnostics_row_text(r));
  };
  int last_frame = -1;
  const IndexOnFailure index_written(session);
  run_frame_loop(times, panes, on_row, [&](int f) {
    if (!o.run.dump.empty()) {
      if (!sim->transfers() &&
          formats_need_particles(dump_formats_of(o.run, scene.solver.method == "mpm")))
        throw UsageError("--dump: solver method '" + scene.solver.method + "' " +
                         dump_without_particles);
      dump.write(*sim, f);
      dump_times.add(f, sim->time(), {sim->steps()});
    }
    auto snapshot = sim->snapshot();
    if (noise && sim->transfers()) sim->transfers()->fill_velocity_noise(*snapshot);
    session.draw({snapshot.get()}, frame_path(o.out, f), frame_row(frame_times, f, panes));
    last_frame = f;
    progress.update(f + 1, "frame " + std::to_string(f) + "/" + std::to_string(times.frames));
    computing = f + 1;
    if (sim->failure()) {
      session.flush();
      progress.finish("apiclab: " + sim->failure()->message + " (frames up to " +
                      frame_path(o.out, f) + ")");
      status = 3;
      return false;
    }
    return true;
  });
  session.sim_seconds = panes.stepping_seconds();
  session.flush();
  if (const int signal = stop_signal(); signal && status == 0) {
    progress.finish(render_stopped_text(signal, last_frame, sim->time(), o.out, csv_path));
    return stop_exit_code(signal);
  }
  if (status == 0) {
    if (!o.video.empty()) encode_video(session.ffmpeg, o.out, scene.time.fps, o.video);
    progress.finish(scene.name + ": " + session.timing() + "\nframes: " + frame_path(o.out, 0) +
                    " ...\ndiagnostics CSV: " + csv_path +
                    (o.video.empty() ? "" : "\nvideo: " + o.video));
  }
  return status;
}

int compare(const RenderOptions& o) {
  install_stop_handlers();  // a signal during the set-up stops after frame 0
  // The panes, checked before anything runs (app/pane_spec.hpp).
  std::vector<PaneSpec> specs;
  try {
    specs = parse_panes(o.schemes);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (!o.run.scheme.empty()) throw UsageError("compare takes --schemes (a list), not --scheme");
  // Without --dump-format: csv when every pane has particles, else vtk (every method writes it).
  const bool particles =
      std::all_of(specs.begin(), specs.end(), [](const PaneSpec& p) { return p.method == "mpm"; });
  const std::vector<DumpFormat> formats = dump_formats_of(o.run, particles);
  for (const PaneSpec& spec : specs)  // before any output: only MPM panes have particles
    if (!o.run.dump.empty() && spec.method != "mpm" && formats_need_particles(formats))
      throw UsageError("--dump: solver method '" + spec.method + "' (pane '" + spec.key + "') " +
                       dump_without_particles);
  if (!o.run.csv.empty())
    throw UsageError("compare writes one CSV per scheme into --out; drop --csv");
  RenderSession session(o);  // refuses a pane that cannot run with the scene, before any output

  // Each scheme builds its particles from the same scene (deterministic sampling), so all
  // start from the same particles; each starts with its own initial state (APIC's C = ω*).
  struct Pane {
    std::string key;
    std::string
        label;  // the key with its scheme's parameter, "xpic(3)" (sim/mpm/schemes/scheme_label.hpp)
    std::unique_ptr<Simulation> sim;
    RowFile csv;
    bool reported = false;
    std::unique_ptr<ParticleDump> dump;  // --dump DIR/KEY, one folder per pane
    FrameIndex dump_times;
  };
  // Whose files these are, before any output: each pane's CSV and dump folder carry the pane's
  // settings, the --out folder's frames the scene's with the list of panes.
  std::vector<SceneDesc> pane_scenes;
  std::vector<nlohmann::json> pane_settings;
  std::vector<std::string> keys;
  nlohmann::json settings = run_settings(session.scene, precision_of(o.run), o.run.sets);
  for (const PaneSpec& spec : specs) {
    SceneDesc scene = session.scene;
    scene.solver.method = spec.method;
    scene.solver.scheme = spec.scheme;
    pane_scenes.push_back(scene);
    pane_settings.push_back(run_settings(scene, precision_of(o.run), o.run.sets));
    keys.push_back(spec.key);
  }
  settings["panes"] = keys;
  OutputClaims claims(settings, o.run.overwrite);
  claims.scene_inputs(session.scene);
  claims.frames("--out", o.out);
  for (std::size_t k = 0; k < specs.size(); ++k) {
    claims.csv("the CSV", o.out + "/" + keys[k] + ".csv", pane_settings[k]);
    if (!o.run.dump.empty()) claims.frames("--dump", o.run.dump + "/" + keys[k], pane_settings[k]);
  }
  if (!o.video.empty()) claims.plain("--video", o.video, "ftyp", 4);
  claims.check_and_clear();

  std::vector<Pane> panes;
  std::vector<std::string> sizes;  // each pane's model size, once (MPM panes share particles)
  for (std::size_t k = 0; k < specs.size(); ++k) {
    const PaneSpec& spec = specs[k];
    const SceneDesc& scene = pane_scenes[k];
    Pane p;
    p.key = spec.key;
    p.label = spec.method == "mpm" ? run_label(scene) : spec.key;
    p.sim = make_simulation(scene, precision_of(o.run));
    p.csv = open_csv(o.out + "/" + spec.key + ".csv", pane_settings[k], scene.solver.ledger);
    DiagnosticsRow first = p.sim->measure();
    first.dt = 0;
    p.csv.write_row(diagnostics_row_text(first));
    if (!o.run.dump.empty()) {
      if (!p.sim->transfers() && formats_need_particles(formats))
        throw UsageError("--dump: solver method '" + spec.method + "' (pane '" + spec.key + "') " +
                         dump_without_particles);
      const std::string dir = o.run.dump + "/" + spec.key;
      ensure_writable_dir(dir);
      p.dump = std::make_unique<ParticleDump>(dir, formats);
      p.dump_times = open_frame_index(dir, pane_settings[k]);
    }
    if (std::string size = p.sim->model_size();
        std::find(sizes.begin(), sizes.end(), size) == sizes.end())
      sizes.push_back(std::move(size));
    panes.push_back(std::move(p));
  }
  const SceneDesc& scene = session.scene;
  const bool noise = session.style.color == render::ColorMode::noise;
  const FrameTimes times(scene, o.run.max_steps);
  print_time_step_note(scene, o.run.quiet);
  // Panes step in lockstep: one time per frame.
  FrameIndex frame_times = open_frame_index(o.out, settings, keys);
  std::string labels;
  for (const Pane& p : panes) labels += (labels.empty() ? "" : ",") + p.label;
  std::string label = scene.name + " [" + labels;
  for (const std::string& size : sizes) label += ", " + size;
  Progress progress(label + "]", times.frames + 1, o.run.quiet);
  int computing = 1;
  std::vector<Simulation*> sims;
  for (Pane& p : panes) {
    sims.push_back(p.sim.get());
    show_solver_progress(*p.sim, progress, computing, times.frames);
  }
  Lockstep lockstep(std::move(sims));
  std::string failures;
  int failed = 0;
  const auto on_row = [&](std::size_t k, const DiagnosticsRow& r) {
    panes[k].csv.write_row(diagnostics_row_text(r));
  };
  int last_frame = -1;
  const IndexOnFailure index_written(session);
  // Every scheme reaches the frame time before the frame is drawn; a scheme that failed stays
  // frozen at its last state and is labelled so.
  run_frame_loop(times, lockstep, on_row, [&](int f) {
    std::vector<std::shared_ptr<Snapshot>> snapshots;
    std::vector<const Snapshot*> views;
    for (Pane& p : panes) {
      if (p.sim->failure() && !p.reported) {
        p.reported = true;
        ++failed;
        failures += "\n" + p.label + ": " + p.sim->failure()->message;
      }
      if (p.dump) {
        p.dump->write(*p.sim, f);
        p.dump_times.add(f, p.sim->time(), {p.sim->steps()});
      }
      snapshots.push_back(p.sim->snapshot());
      if (noise && p.sim->transfers()) p.sim->transfers()->fill_velocity_noise(*snapshots.back());
      views.push_back(snapshots.back().get());
    }
    session.draw(views, frame_path(o.out, f), frame_row(frame_times, f, lockstep));
    last_frame = f;
    progress.update(f + 1, "frame " + std::to_string(f) + "/" + std::to_string(times.frames));
    computing = f + 1;
    return failed < int(panes.size());  // a frozen pane still shows where it failed
  });
  session.sim_seconds = lockstep.stepping_seconds();
  session.flush();
  std::string csvs;
  for (const Pane& p : panes) csvs += (csvs.empty() ? "" : ", ") + o.out + "/" + p.key + ".csv";
  if (const int signal = stop_signal()) {
    double t = 0;
    for (std::size_t k = 0; k < lockstep.size(); ++k) t = std::max(t, lockstep[k].time());
    progress.finish(render_stopped_text(signal, last_frame, t, o.out, csvs));
    return stop_exit_code(signal);
  }
  if (failed < int(panes.size()) && !o.video.empty())
    encode_video(session.ffmpeg, o.out, scene.time.fps, o.video);
  progress.finish(scene.name + ": " + session.timing() + "\nframes: " + frame_path(o.out, 0) +
                  " ...\ndiagnostics CSVs: " + csvs +
                  (o.video.empty() ? "" : "\nvideo: " + o.video) +
                  (failures.empty() ? "" : "\nblew up (frozen from then on):" + failures));
  return failed > 0 ? 3 : 0;  // as run: any pane that blew up, after all frames and CSVs
}

}  // namespace

void register_render(CLI::App& root, CommandTable& table) {
  auto r = std::make_shared<RenderOptions>();
  CLI::App* cmd = root.add_subcommand(
      "render", "headless PNG frames (DIR/frame_0000.png, ...) through EGL, OSMesa as fallback");
  add_render_options(cmd, *r);
  table.push_back({cmd, [r] { return render(*r); }});

  auto c = std::make_shared<RenderOptions>();
  CLI::App* cmp = root.add_subcommand(
      "compare",
      "schemes side by side from the same initial particles: PNG frames, one CSV per scheme");
  add_render_options(cmp, *c);
  // Refused by compare with a message of its own; left out of compare --help.
  for (const char* name : {"--scheme", "--csv"}) cmp->get_option(name)->group("");
  cmp->add_option("--schemes", c->schemes,
                  "comma-separated panes: MPM schemes (" + choice_keys(scheme_choices()) +
                      "), or solver methods eol and eulerian (mpm:apic for an MPM scheme "
                      "explicitly), e.g. pic,flip,apic or eol,eulerian,mpm:apic [required]")
      ->required();
  table.push_back({cmp, [c] { return compare(*c); }});
}

}  // namespace apiclab::cli
