// `apiclab render` and `apiclab compare`: headless PNG frames through EGL (OSMesa fallback).
// render draws one simulation; compare advances several schemes in lockstep from the same
// scene and draws them side by side, one diagnostics CSV per scheme.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <set>
#include <sstream>

#include "cli.hpp"
#include "commands.hpp"
#include "render/context.hpp"
#include "render/figure.hpp"
#include "render/target.hpp"
#include "sim/diagnostics.hpp"

extern char** environ;

namespace apiclab::cli {
namespace {

struct RenderOptions {
  RunOptions run;
  std::string out, size = "1280x720", color = "speed", backend = "auto", video, schemes;
  std::string fit = "domain";
  bool vectors = false, grid = false, no_legend = false;
  double vector_scale = 0, color_max = 0, particle_scale = 1;
  int vector_every = 0;
};

void add_render_options(CLI::App* cmd, RenderOptions& o) {
  add_run_options(cmd, o.run);
  cmd->add_option("--out", o.out, "output directory for frame_0000.png, ... and the CSVs")
      ->required();
  cmd->add_option("--size", o.size, "image size WxH in pixels (default 1280x720)");
  cmd->add_option("--color", o.color,
                  std::string("particle colour: ") + choice_keys(color_mode_choices()) +
                      " (noise: |v_p - PIC velocity|) [default: speed]");
  cmd->add_flag("--vectors", o.vectors, "draw velocity arrows");
  cmd->add_option("--vector-scale", o.vector_scale,
                  "arrow length per unit speed (default: automatic)");
  cmd->add_option("--vector-every", o.vector_every,
                  "draw one arrow per N particles (default: automatic)");
  cmd->add_option("--color-max", o.color_max,
                  "speed/noise at the top of the colour scale (default: automatic)");
  cmd->add_option("--particle-scale", o.particle_scale, "multiply the drawn particle radius");
  cmd->add_flag("--grid", o.grid, "draw the grid lines");
  cmd->add_option("--fit", o.fit,
                  "frame the whole domain, or the particles of the first frame (with room "
                  "around them): domain|particles");
  cmd->add_flag("--no-legend", o.no_legend, "leave out the colour and arrow legend");
  cmd->add_option("--backend", o.backend, "offscreen OpenGL: auto|egl|osmesa");
  cmd->add_option("--video", o.video, "also encode the frames into this MP4 file (needs ffmpeg)");
}

std::pair<int, int> parse_size(const std::string& s) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  std::istringstream in(s);
  if (!(in >> w >> x >> h) || x != 'x' || in >> extra || w < 16 || h < 16 || w > 16384 || h > 16384)
    throw UsageError("invalid --size '" + s + "' (expected WxH, e.g. 1280x720, each 16..16384)");
  return {w, h};
}

// The full path of an executable on PATH, or empty.
std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    std::string candidate = (dir.empty() ? "." : dir) + "/" + name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

// Runs a program without a shell; returns its exit status (-1 when it could not start).
int run_program(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void encode_video(const std::string& ffmpeg, const std::string& dir, double fps,
                  const std::string& file) {
  const int status =
      run_program({ffmpeg, "-y", "-loglevel", "error", "-framerate", std::to_string(fps), "-i",
                   dir + "/frame_%04d.png", "-c:v", "libx264", "-pix_fmt", "yuv420p", "-vf",
                   "pad=ceil(iw/2)*2:ceil(ih/2)*2", file});
  if (status != 0)
    throw UsageError("ffmpeg failed (exit " + std::to_string(status) + ") encoding " + file);
}

std::string frame_path(const std::string& dir, int frame, const char* extension = "png") {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.%s", frame, extension);
  return (std::filesystem::path(dir) / name).string();
}

// Everything checked before any simulation starts, and the objects both commands share.
struct Session {
  SceneDesc scene;
  int width = 0, height = 0;
  render::FigureStyle style;
  std::string ffmpeg;
  std::unique_ptr<render::OffscreenContext> context;
  std::unique_ptr<render::RenderTarget> target;
  std::unique_ptr<render::Renderer> renderer;
  render::FigureState state;
  bool fit_particles = false;
  std::future<void> pending_png;  // PNGs are written while the next frame simulates
  double first_draw_seconds = 0, draw_seconds = 0, png_seconds = 0, sim_seconds = 0;
  int frames_drawn = 0;

  explicit Session(const RenderOptions& o) {
    std::tie(width, height) = parse_size(o.size);
    render::Backend backend;
    try {
      style.color = render::parse_color_mode(o.color);
      backend = render::parse_backend(o.backend);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    if (o.vector_scale < 0 || o.color_max < 0 || o.vector_every < 0 || o.particle_scale <= 0)
      throw UsageError(
          "--vector-scale, --vector-every, --color-max and --particle-scale must be positive");
    style.vectors = o.vectors;
    style.vector_scale = float(o.vector_scale);
    style.vector_every = o.vector_every;
    style.color_max = float(o.color_max);
    style.particle_scale = float(o.particle_scale);
    style.grid = o.grid;
    style.legend = !o.no_legend;
    if (o.fit != "domain" && o.fit != "particles")
      throw UsageError("unknown --fit '" + o.fit + "' (expected domain|particles)");
    fit_particles = o.fit == "particles";
    scene = load_scene_with_options(o.run);
    style.time_step = 1 / scene.time.fps;
    style.up_axis = render::up_axis_from_gravity(scene.gravity, scene.dim);
    apply_threads(o.run.threads);
    ensure_writable_dir(o.out);
    if (!o.video.empty()) {
      ffmpeg = find_on_path("ffmpeg");
      if (ffmpeg.empty())
        throw UsageError("--video needs ffmpeg, which is not installed (apt-get install ffmpeg)");
      ensure_writable_file(o.video);
    }
    try {
      context = render::create_offscreen_context(backend);
    } catch (const render::ContextError& e) {
      throw UsageError(e.what());
    }
    if (!o.run.quiet)
      std::fprintf(
          stderr, "apiclab: rendering with %s%s\n", context->description().c_str(),
          context->egl_problem.empty() ? "" : (" (EGL: " + context->egl_problem + ")").c_str());
    target = std::make_unique<render::RenderTarget>(width, height);
    renderer = std::make_unique<render::Renderer>();
  }

  // Draws the panes and writes the PNG in the background.
  void draw(const std::vector<const Snapshot*>& panes, const std::string& path) {
    if (fit_particles && !style.frame) style.frame = particle_frame(panes);
    const double t0 = now_seconds();
    target->bind();
    render::draw_figure(*renderer, width, height, panes, style, state);
    auto image = std::make_shared<render::Image>(target->read());
    // The first frame also compiles the shaders (llvmpipe JITs them): timed apart.
    (frames_drawn++ == 0 ? first_draw_seconds : draw_seconds) += now_seconds() - t0;
    flush();
    pending_png = std::async(std::launch::async, [this, image, path] {
      const double t = now_seconds();
      render::write_png(*image, path);
      png_seconds += now_seconds() - t;
    });
  }
  // The first frame's particles with a quarter of their extent (and two cells) around them,
  // inside the domain; kept for the whole run so that the video does not jitter.
  static render::Box3 particle_frame(const std::vector<const Snapshot*>& panes) {
    render::Box3 b = render::particle_box(*panes.front());
    for (const Snapshot* p : panes) {
      const render::Box3 q = render::particle_box(*p);
      for (int k = 0; k < 3; ++k)
        b.min[k] = std::min(b.min[k], q.min[k]), b.max[k] = std::max(b.max[k], q.max[k]);
    }
    const render::Box3 domain = render::domain_box(*panes.front());
    const render::Vec3 size = b.size();
    const float room = 0.25f * std::max({size.x, size.y, size.z}) + 2 * float(panes.front()->dx);
    for (int k = 0; k < panes.front()->dim; ++k) {
      b.min[k] = std::max(b.min[k] - room, domain.min[k]);
      b.max[k] = std::min(b.max[k] + room, domain.max[k]);
    }
    return b;
  }
  void flush() {
    if (pending_png.valid()) pending_png.get();
  }
  std::string timing() const {
    std::ostringstream s;
    s.precision(3);
    const double draw = frames_drawn > 1 ? draw_seconds / (frames_drawn - 1) : first_draw_seconds;
    s << frames_drawn << " frames " << width << "x" << height << ": draw " << 1000 * draw
      << " ms/frame (first " << 1000 * first_draw_seconds << " ms), PNG "
      << 1000 * png_seconds / std::max(frames_drawn, 1) << " ms/frame, simulation " << sim_seconds
      << " s";
    return s.str();
  }
};

std::ofstream open_csv(const std::string& path) {
  ensure_writable_file(path);
  std::ofstream out(path);
  out << diagnostics_header() << '\n';
  return out;
}

int render(const RenderOptions& o) {
  Session session(o);
  const SceneDesc& scene = session.scene;
  const std::string scheme(key_of(scene.solver.scheme));
  const std::string csv_path = o.run.csv.empty() ? o.out + "/" + scheme + ".csv" : o.run.csv;
  std::ofstream csv = open_csv(csv_path);
  if (!o.run.dump.empty()) ensure_writable_dir(o.run.dump);

  auto sim = make_simulation(scene, precision_of(o.run));
  const bool noise = session.style.color == render::ColorMode::noise;
  const int frames = frame_count(scene);
  DiagnosticsRow first = sim->measure();
  first.dt = 0;
  write_diagnostics_row(csv, first);
  Progress progress(
      scene.name + " [" + scheme + ", " + std::to_string(particle_count(*sim)) + " particles]",
      frames + 1, o.run.quiet);
  int status = 0;
  for (int f = 0; f <= frames; ++f) {
    if (f > 0) {
      const double t0 = now_seconds();
      const double t_frame = f == frames ? scene.time.end : f / scene.time.fps;
      sim->advance_to(t_frame, [&](const DiagnosticsRow& r) { write_diagnostics_row(csv, r); });
      session.sim_seconds += now_seconds() - t0;
    }
    if (!o.run.dump.empty()) {
      std::ofstream dump(frame_path(o.run.dump, f, "csv"));
      if (!sim->transfers()) throw UsageError("--dump: solver method '" + scene.solver.method + "' has no particles");
      sim->transfers()->write_particles_csv(dump);
    }
    auto snapshot = sim->snapshot();
    if (noise && sim->transfers()) sim->transfers()->fill_velocity_noise(*snapshot);
    session.draw({snapshot.get()}, frame_path(o.out, f));
    progress.update(f + 1, "frame " + std::to_string(f) + "/" + std::to_string(frames));
    if (sim->failure()) {
      session.flush();
      progress.finish("apiclab: " + sim->failure()->message + " (frames up to " +
                      frame_path(o.out, f) + ")");
      status = 3;
      break;
    }
  }
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
  // The schemes, checked before anything runs.
  std::vector<Scheme> schemes;
  std::set<std::string> seen;
  std::istringstream list(o.schemes);
  for (std::string key; std::getline(list, key, ',');) {
    if (!seen.insert(key).second)
      throw UsageError("scheme '" + key + "' is listed twice in --schemes");
    try {
      schemes.push_back(parse_choice(scheme_choices(), key, "scheme"));
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  if (schemes.empty()) throw UsageError("--schemes needs at least one scheme, e.g. pic,flip,apic");
  if (!o.run.scheme.empty()) throw UsageError("compare takes --schemes (a list), not --scheme");
  if (!o.run.dump.empty()) throw UsageError("compare does not take --dump; use run or render");
  if (!o.run.csv.empty())
    throw UsageError("compare writes one CSV per scheme into --out; drop --csv");
  Session session(o);

  // Each scheme builds its particles from the same scene (deterministic sampling), so all
  // start from the same particles; each starts with its own initial state (APIC's C = ω*).
  struct Pane {
    std::string key;
    std::unique_ptr<Simulation> sim;
    std::ofstream csv;
    bool reported = false;
  };
  std::vector<Pane> panes;
  std::size_t particles = 0;
  for (Scheme scheme : schemes) {
    SceneDesc scene = session.scene;
    scene.solver.scheme = scheme;
    Pane p{std::string(key_of(scheme)), make_simulation(scene, precision_of(o.run)),
           open_csv(o.out + "/" + std::string(key_of(scheme)) + ".csv")};
    DiagnosticsRow first = p.sim->measure();
    first.dt = 0;
    write_diagnostics_row(p.csv, first);
    particles = particle_count(*p.sim);
    panes.push_back(std::move(p));
  }
  const SceneDesc& scene = session.scene;
  const bool noise = session.style.color == render::ColorMode::noise;
  const int frames = frame_count(scene);
  Progress progress(
      scene.name + " [" + o.schemes + ", " + std::to_string(particles) + " particles]", frames + 1,
      o.run.quiet);
  std::string failures;
  int failed = 0;
  for (int f = 0; f <= frames; ++f) {
    std::vector<std::shared_ptr<Snapshot>> snapshots;
    std::vector<const Snapshot*> views;
    for (Pane& p : panes) {
      // Lockstep: every scheme reaches the frame time before the frame is drawn; a scheme
      // that failed stays frozen at its last state and is labelled so.
      if (f > 0 && !p.sim->failure()) {
        const double t0 = now_seconds();
        const double t_frame = f == frames ? scene.time.end : f / scene.time.fps;
        p.sim->advance_to(t_frame,
                          [&](const DiagnosticsRow& r) { write_diagnostics_row(p.csv, r); });
        session.sim_seconds += now_seconds() - t0;
      }
      if (p.sim->failure() && !p.reported) {
        p.reported = true;
        ++failed;
        failures += "\n" + p.key + ": " + p.sim->failure()->message;
      }
      snapshots.push_back(p.sim->snapshot());
      if (noise && p.sim->transfers()) p.sim->transfers()->fill_velocity_noise(*snapshots.back());
      views.push_back(snapshots.back().get());
    }
    session.draw(views, frame_path(o.out, f));
    progress.update(f + 1, "frame " + std::to_string(f) + "/" + std::to_string(frames));
    if (failed == int(panes.size())) break;
  }
  session.flush();
  if (failed < int(panes.size()) && !o.video.empty())
    encode_video(session.ffmpeg, o.out, scene.time.fps, o.video);
  std::string csvs;
  for (const Pane& p : panes) csvs += (csvs.empty() ? "" : ", ") + o.out + "/" + p.key + ".csv";
  progress.finish(scene.name + ": " + session.timing() + "\nframes: " + frame_path(o.out, 0) +
                  " ...\ndiagnostics CSVs: " + csvs +
                  (o.video.empty() ? "" : "\nvideo: " + o.video) +
                  (failures.empty() ? "" : "\nstopped early:" + failures));
  return failed == int(panes.size()) ? 3 : 0;
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
  cmp->add_option("--schemes", c->schemes, "comma-separated schemes, e.g. pic,flip,apic")
      ->required();
  table.push_back({cmp, [c] { return compare(*c); }});
}

}  // namespace apiclab::cli
