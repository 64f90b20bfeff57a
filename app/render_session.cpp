#include "app/render_session.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <utility>

#include "app/cli_checks.hpp"
#include "app/clock.hpp"
#include "app/frame_loop.hpp"
#include "app/pane_spec.hpp"
#include "app/particle_frame.hpp"
#include "app/video.hpp"
#include "render/snapshot_stats.hpp"
#include "sim/scene/message_text.hpp"

namespace apiclab::cli {
namespace {

std::pair<int, int> parse_size(const std::string& s) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  std::istringstream in(s);
  if (!(in >> w >> x >> h) || x != 'x' || in >> extra || w < 16 || h < 16 || w > 16384 || h > 16384)
    throw UsageError("invalid --size '" + s + "' (expected WxH, e.g. 1280x720, each 16..16384)");
  return {w, h};
}

// A float as an option value that reads back to the same float.
std::string exact_text(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", double(v));
  return buf;
}

}  // namespace

void add_render_options(CLI::App* cmd, RenderOptions& o, RunOptionSet which) {
  add_run_options(cmd, o.run, which);
  cmd->add_option("--out", o.out,
                  "output directory for frame_0000.png, ... and the CSVs [required]")
      ->required();
  cmd->add_option("--size", o.size, "image size WxH in pixels (default 1280x720)");
  cmd->add_option("--color", o.color,
                  std::string("particle colour: ") + choice_keys(color_mode_choices()) +
                      " (noise: |v_p - PIC velocity|) [default: speed]");
  cmd->add_flag("--vectors", o.vectors, "draw velocity arrows [default: off]");
  cmd->add_option("--vector-scale", o.vector_scale,
                  "arrow length per unit speed (default: automatic)");
  cmd->add_option("--vector-every", o.vector_every,
                  "draw one arrow per N particles (default: automatic)");
  cmd->add_option("--color-max", o.color_max,
                  "speed/noise at the top of the colour scale (default: automatic)");
  cmd->add_option("--particle-scale", o.particle_scale,
                  "multiply the drawn particle radius [allowed: > 0; default: 1]");
  cmd->add_flag("--grid", o.grid, "draw the grid lines [default: off]");
  cmd->add_flag("--no-surface", o.no_surface,
                "leave out the objects' surfaces (solver.method eol, eulerian) [default: drawn]");
  cmd->add_flag("--surface-vectors", o.surface_vectors,
                "draw velocity arrows on the surfaces' vertices (eol, eulerian) [default: off]");
  cmd->add_option("--fit", o.fit,
                  "frame the whole domain, the particles of the first frame (with room around "
                  "them), or auto: the particles of the whole run where they fill under half the "
                  "domain, else the domain: domain|particles|auto [default: auto]");
  cmd->add_flag("--no-legend", o.no_legend,
                "leave out the colour and arrow legend [default: legend shown]");
  cmd->add_option("--backend", o.backend, "offscreen OpenGL: auto|egl|osmesa [default: auto]");
  cmd->add_option("--video", o.video,
                  "also encode the frames into this H.264 video (.mp4, .mkv, .mov or .m4v; needs "
                  "ffmpeg) [default: none]");
}

std::string frame_path(const std::string& dir, int frame, const char* extension) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.%s", frame, extension);
  return (std::filesystem::path(dir) / name).string();
}

RenderSession::RenderSession(const RenderOptions& o) {
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
  style.surface = !o.no_surface;
  style.surface_vectors = o.surface_vectors;
  style.legend = !o.no_legend;
  if (o.fit != "domain" && o.fit != "particles" && o.fit != "auto")
    throw UsageError("unknown --fit '" + o.fit + "' (expected domain|particles|auto)");
  fit_particles = o.fit == "particles";
  fit_auto = o.fit == "auto";
  scene = load_scene_with_options(o.run);
  // compare's panes (its list already checked by compare), or render's one pane: the scene's own.
  const std::vector<PaneSpec> panes =
      o.schemes.empty() ? std::vector<PaneSpec>{{"", scene.solver.method, scene.solver.scheme}}
                        : parse_panes(o.schemes);
  if (const std::string why = pane_conflict(panes, scene.solver); !why.empty())
    throw UsageError(why);
  std::vector<Scheme> schemes;
  for (const PaneSpec& p : panes)
    if (p.method == "mpm" || o.schemes.empty()) schemes.push_back(p.scheme);
  check_flip_alpha(o.run, schemes);
  check_memory_for(scene, precision_of(o.run), int(panes.size()));  // one simulation per pane
  style.time_step = 1 / scene.time.fps;
  style.up_axis = render::up_axis_from_gravity(scene.gravity, scene.dim);
  apply_threads(o.run.threads);
  ensure_writable_dir(o.out);
  if (!o.video.empty()) {
    // ffmpeg picks the container by the extension, after every frame is drawn: checked first.
    const std::string ext = std::filesystem::path(o.video).extension().string();
    if (ext != ".mp4" && ext != ".mkv" && ext != ".mov" && ext != ".m4v")
      throw UsageError("--video " + message_text(o.video) +
                       ": the extension picks the container; give .mp4, .mkv, .mov or .m4v (an "
                       "H.264 video)");
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
  const bool automatic = (render::is_scalar(style.color) && !(style.color_max > 0)) ||
                         ((style.vectors || style.surface_vectors) && !(style.vector_scale > 0));
  // --fit auto frames the bodies over the whole run: the first pass runs for it too, so that
  // the scales it prints reproduce the same frames.
  if (!automatic && !fit_auto) return;
  scales_automatic = automatic;
  std::vector<SceneDesc> pane_scenes;
  for (const PaneSpec& p : panes) {
    pane_scenes.push_back(scene);
    pane_scenes.back().solver.method = p.method;
    pane_scenes.back().solver.scheme = p.scheme;
  }
  fix_scales(pane_scenes, o.run);
}

void RenderSession::fix_scales(const std::vector<SceneDesc>& panes, const RunOptions& run) {
  const double start = now_seconds();
  std::vector<std::unique_ptr<Simulation>> sims;
  std::vector<Simulation*> stepped;
  for (const SceneDesc& s : panes) {
    sims.push_back(make_simulation(s, precision_of(run)));
    stepped.push_back(sims.back().get());
  }
  Lockstep lockstep(stepped);
  const FrameTimes times(scene, run.max_steps);
  Progress progress("scales of " + scene.name + " (first pass)", times.frames + 1, run.quiet);
  const bool noise = style.color == render::ColorMode::noise;
  state.reset();
  state.hold = render::ScaleHold::grow;
  std::vector<std::shared_ptr<Snapshot>> first;  // frame 0: the layout the arrows are sized for
  float radius = 0;
  render::Box3 run_box;  // every pane's particles over the whole run (--fit auto)
  bool run_box_set = false;
  run_frame_loop(times, lockstep, {}, [&](int f) {
    std::vector<std::shared_ptr<Snapshot>> snapshots;
    std::vector<const Snapshot*> views;
    bool all_failed = true;
    for (const auto& sim : sims) {
      snapshots.push_back(sim->snapshot());
      if (noise && sim->transfers()) sim->transfers()->fill_velocity_noise(*snapshots.back());
      views.push_back(snapshots.back().get());
      all_failed = all_failed && sim->failure();
    }
    render::update_scales(state, views);
    for (const Snapshot* v : views) {
      if (v->failure || v->count() == 0) continue;  // a frozen pane's last positions say nothing
      const render::Box3 b = render::particle_box(*v);
      for (int k = 0; k < 3; ++k)
        run_box.min[k] = run_box_set ? std::min(run_box.min[k], b.min[k]) : b.min[k],
        run_box.max[k] = run_box_set ? std::max(run_box.max[k], b.max[k]) : b.max[k];
      run_box_set = true;
    }
    if (f == 0) first = snapshots, radius = state.radius;
    progress.update(f + 1, "frame " + std::to_string(f) + "/" + std::to_string(times.frames));
    return !all_failed;  // the drawing stops there too
  });
  state.radius = radius;  // arrows spaced as on frame 0, in every frame
  state.hold = render::ScaleHold::fixed;
  scale_pass_seconds = now_seconds() - start;
  // --fit auto: the bodies over the whole run, where they fill little of the domain.
  if (fit_auto && run_box_set && !first.empty()) {
    const render::Box3 frame = padded_frame(run_box, *first.front(), 0.1f);
    if (worth_fitting(frame, *first.front())) style.frame = frame;
  }
  if (run.quiet || first.empty() || !scales_automatic) return;
  std::vector<const Snapshot*> views;
  for (const auto& s : first) views.push_back(s.get());
  const auto rects =
      render::figure_scene_rects(*renderer, width, height, int(views.size()), *views[0], style);
  const render::SceneStyle resolved = render::resolve_scene_style(style, views, rects[0], state);
  std::string text = "apiclab: one scale for all " + std::to_string(times.frames + 1) +
                     " frames (a first pass over them): --color-max " +
                     exact_text(resolved.color_max);
  if (style.vectors || style.surface_vectors)
    text += " --vector-scale " + exact_text(resolved.vector_scale);
  progress.finish(text);
}

void RenderSession::draw(const std::vector<const Snapshot*>& panes, const std::string& path,
                         std::function<void()> written) {
  // The first frame's particles frame the whole run, so that the video does not jitter.
  if (fit_particles && !style.frame) style.frame = particle_frame(panes);
  const double t0 = now_seconds();
  target->bind();
  render::draw_figure(*renderer, width, height, panes, style, state);
  auto image = std::make_shared<render::Image>(target->read());
  // The first frame also compiles the shaders (llvmpipe JITs them): timed apart.
  (frames_drawn++ == 0 ? first_draw_seconds : draw_seconds) += now_seconds() - t0;
  flush();
  pending_written = std::move(written);
  pending_png = std::async(std::launch::async, [this, image, path] {
    const double t = now_seconds();
    try {
      render::write_png(*image, path);  // whole or absent: "cannot write PATH: REASON"
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());  // one line, exit 2
    }
    png_seconds += now_seconds() - t;
  });
}

void RenderSession::flush() {
  if (!pending_png.valid()) return;
  const std::function<void()> written = std::exchange(pending_written, nullptr);
  pending_png.get();  // a failed write throws here, and its frame is not indexed
  if (written) written();
}

std::string RenderSession::timing() const {
  std::ostringstream s;
  s.precision(3);
  const double draw = frames_drawn > 1 ? draw_seconds / (frames_drawn - 1) : first_draw_seconds;
  s << frames_drawn << " frames " << width << "x" << height << ": draw " << 1000 * draw
    << " ms/frame (first " << 1000 * first_draw_seconds << " ms), PNG "
    << 1000 * png_seconds / std::max(frames_drawn, 1) << " ms/frame, simulation " << sim_seconds
    << " s";
  if (scale_pass_seconds > 0) s << ", scale pass " << scale_pass_seconds << " s";
  return s.str();
}

}  // namespace apiclab::cli
