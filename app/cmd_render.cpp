// `apiclab render` and `apiclab compare`: headless PNG frames through EGL (OSMesa fallback).
// render draws one simulation; compare advances several schemes in lockstep from the same
// scene and draws them side by side, one diagnostics CSV per scheme.
#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include "app/frame_loop.hpp"
#include "app/pane_spec.hpp"
#include "app/render_session.hpp"
#include "app/run_outputs.hpp"
#include "app/video.hpp"
#include "cli.hpp"
#include "commands.hpp"
#include "sim/diagnostics.hpp"
#include "sim/scheme_label.hpp"

namespace apiclab::cli {
namespace {

// A diagnostics CSV with its settings sidecar (NAME.csv.json, app/run_outputs.hpp).
std::ofstream open_csv(const std::string& path, const SceneDesc& scene, const RenderOptions& o) {
  ensure_writable_file(path);
  std::ofstream out(path);
  out << diagnostics_header() << '\n';
  write_csv_sidecar(path, run_settings(scene, precision_of(o.run), o.run.sets));
  return out;
}

// The frame's time (the healthy panes share it; a pane that failed stopped earlier) and each
// pane's step count.
void add_frame(FrameIndex& index, int frame, const Lockstep& panes) {
  std::vector<long> steps;
  double t = 0;
  for (std::size_t k = 0; k < panes.size(); ++k) {
    steps.push_back(panes[k].steps());
    t = std::max(t, panes[k].time());
  }
  index.add(frame, t, steps);
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
  RenderSession session(o);
  const SceneDesc& scene = session.scene;
  // The transfer scheme names an MPM run; a method without schemes (eol, eulerian) names itself.
  const std::string scheme =
      scene.solver.method == "mpm" ? std::string(key_of(scene.solver.scheme)) : scene.solver.method;
  const std::string csv_path = o.run.csv.empty() ? o.out + "/" + scheme + ".csv" : o.run.csv;
  std::ofstream csv = open_csv(csv_path, scene, o);
  if (!o.run.dump.empty()) ensure_writable_dir(o.run.dump);
  ParticleDump dump(o.run.dump, dump_formats_of(o.run));
  print_time_step_note(scene, o.run.quiet);
  // The real time of every frame: PNGs in --out, particle dumps in --dump.
  FrameIndex frame_times(o.out), dump_times;
  if (!o.run.dump.empty() && o.run.dump != o.out) dump_times = FrameIndex(o.run.dump);

  auto sim = make_simulation(scene, precision_of(o.run));
  const bool noise = session.style.color == render::ColorMode::noise;
  const FrameTimes times(scene, o.run.max_steps);
  DiagnosticsRow first = sim->measure();
  first.dt = 0;
  write_diagnostics_row(csv, first);
  Progress progress(scene.name + " [" + run_label(scene) + ", " + sim->model_size() + "]",
                    times.frames + 1, o.run.quiet);
  int computing = 1;  // the frame being computed, for the solver's progress
  show_solver_progress(*sim, progress, computing, times.frames);
  int status = 0;
  Lockstep panes({sim.get()});
  const auto on_row = [&](std::size_t, const DiagnosticsRow& r) { write_diagnostics_row(csv, r); };
  run_frame_loop(times, panes, on_row, [&](int f) {
    if (!o.run.dump.empty()) {
      if (!sim->transfers() && formats_need_particles(dump_formats_of(o.run)))
        throw UsageError("--dump: solver method '" + scene.solver.method + "' " +
                         dump_without_particles);
      dump.write(*sim, f);
      dump_times.add(f, sim->time(), {sim->steps()});
    }
    frame_times.add(f, sim->time(), {sim->steps()});
    auto snapshot = sim->snapshot();
    if (noise && sim->transfers()) sim->transfers()->fill_velocity_noise(*snapshot);
    session.draw({snapshot.get()}, frame_path(o.out, f));
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
  if (status == 0) {
    if (!o.video.empty()) encode_video(session.ffmpeg, o.out, scene.time.fps, o.video);
    progress.finish(scene.name + ": " + session.timing() + "\nframes: " + frame_path(o.out, 0) +
                    " ...\ndiagnostics CSV: " + csv_path +
                    (o.video.empty() ? "" : "\nvideo: " + o.video));
  }
  return status;
}

int compare(const RenderOptions& o) {
  // The panes, checked before anything runs (app/pane_spec.hpp).
  std::vector<PaneSpec> specs;
  try {
    specs = parse_panes(o.schemes);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (!o.run.scheme.empty()) throw UsageError("compare takes --schemes (a list), not --scheme");
  const std::vector<DumpFormat> formats = dump_formats_of(o.run);
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
    std::string label;  // the key with its scheme's parameter, "xpic(3)" (sim/scheme_label.hpp)
    std::unique_ptr<Simulation> sim;
    std::ofstream csv;
    bool reported = false;
    std::unique_ptr<ParticleDump> dump;  // --dump DIR/KEY, one folder per pane
    FrameIndex dump_times;
  };
  std::vector<Pane> panes;
  std::vector<std::string> sizes;  // each pane's model size, once (MPM panes share particles)
  for (const PaneSpec& spec : specs) {
    SceneDesc scene = session.scene;
    scene.solver.method = spec.method;
    scene.solver.scheme = spec.scheme;
    Pane p;
    p.key = spec.key;
    p.label = spec.method == "mpm" ? run_label(scene) : spec.key;
    p.sim = make_simulation(scene, precision_of(o.run));
    p.csv = open_csv(o.out + "/" + spec.key + ".csv", scene, o);
    DiagnosticsRow first = p.sim->measure();
    first.dt = 0;
    write_diagnostics_row(p.csv, first);
    if (!o.run.dump.empty()) {
      if (!p.sim->transfers() && formats_need_particles(formats))
        throw UsageError("--dump: solver method '" + spec.method + "' (pane '" + spec.key + "') " +
                         dump_without_particles);
      const std::string dir = o.run.dump + "/" + spec.key;
      ensure_writable_dir(dir);
      p.dump = std::make_unique<ParticleDump>(dir, formats);
      p.dump_times = FrameIndex(dir);
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
  std::vector<std::string> keys;
  for (const Pane& p : panes) keys.push_back(p.key);
  FrameIndex frame_times(o.out, keys);  // panes step in lockstep: one time per frame
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
    write_diagnostics_row(panes[k].csv, r);
  };
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
    session.draw(views, frame_path(o.out, f));
    add_frame(frame_times, f, lockstep);
    progress.update(f + 1, "frame " + std::to_string(f) + "/" + std::to_string(times.frames));
    computing = f + 1;
    return failed < int(panes.size());  // a frozen pane still shows where it failed
  });
  session.sim_seconds = lockstep.stepping_seconds();
  session.flush();
  if (failed < int(panes.size()) && !o.video.empty())
    encode_video(session.ffmpeg, o.out, scene.time.fps, o.video);
  std::string csvs;
  for (const Pane& p : panes) csvs += (csvs.empty() ? "" : ", ") + o.out + "/" + p.key + ".csv";
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
