// What `render` and `compare` share: their options, everything checked before a simulation
// starts (size, colours, backend, ffmpeg, the output folder), the offscreen GL objects, and
// drawing one frame of panes with the PNG written while the next frame simulates.
#pragma once
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "cli.hpp"
#include "render/context.hpp"
#include "render/figure.hpp"
#include "render/target.hpp"

namespace apiclab::cli {

struct RenderOptions {
  RunOptions run;
  std::string out, size = "1280x720", color = "speed", backend = "auto", video, schemes;
  std::string fit = "auto";
  bool vectors = false, grid = false, no_legend = false;
  bool no_surface = false, surface_vectors = false;
  double vector_scale = 0, color_max = 0, particle_scale = 1;
  int vector_every = 0;
};

void add_render_options(CLI::App* cmd, RenderOptions& o, RunOptionSet which = {});

// DIR/frame_0007.png (or .csv).
std::string frame_path(const std::string& dir, int frame, const char* extension = "png");

struct RenderSession {
  SceneDesc scene;
  int width = 0, height = 0;
  render::FigureStyle style;
  std::string ffmpeg;
  std::unique_ptr<render::OffscreenContext> context;
  std::unique_ptr<render::RenderTarget> target;
  std::unique_ptr<render::Renderer> renderer;
  render::FigureState state;
  bool fit_particles = false, fit_auto = false;  // --fit particles; --fit auto
  bool scales_automatic = false;                 // the first pass fixes a scale and says it
  std::future<void> pending_png;                 // PNGs are written while the next frame simulates
  std::function<void()> pending_written;  // what follows the pending PNG (its frames.csv row)
  double first_draw_seconds = 0, draw_seconds = 0, png_seconds = 0, sim_seconds = 0;
  double scale_pass_seconds = 0;  // the first pass that fixes the scales (0: none needed)
  int frames_drawn = 0;

  // Checks everything, then, when a scale is automatic or --fit is auto, simulates the panes
  // once through every frame to fix the colour and arrow scales for the whole sequence and the
  // bodies' frame (fix_scales).
  explicit RenderSession(const RenderOptions& o);
  // Draws the panes and writes the PNG in the background; `written` runs on this thread once
  // the PNG is whole (in the next draw or flush), so an index lists only PNGs present.
  void draw(const std::vector<const Snapshot*>& panes, const std::string& path,
            std::function<void()> written = nullptr);
  void flush();  // waits for the last PNG, then runs its `written`
  std::string timing() const;

 private:
  // The first pass: the panes' scenes simulated to every frame time without drawing, the
  // scales grown over all frames and then held fixed; says the scales found on stderr.
  void fix_scales(const std::vector<SceneDesc>& panes, const RunOptions& run);
};

}  // namespace apiclab::cli
