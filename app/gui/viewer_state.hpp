// What the GUI thread keeps between frames: user choices, the camera, automatic scales.
// Shared by the viewer's parts (controls, scene panes, plots); never touched by the worker.
#pragma once
#include <imgui.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/sim_worker.hpp"
#include "app/sweep/open.hpp"
#include "render/auto_scale.hpp"
#include "render/camera.hpp"
#include "render/color.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab::gui {

struct ViewerState {
  // Scene and panes; scene is the editable copy restarts are built from.
  std::vector<std::string> scene_files;  // shipped scenes
  std::string scene_path;
  SceneDesc scene;
  bool scene_loaded = false;
  std::string load_error, notice;
  std::vector<PaneConfig> panes;
  Precision precision = Precision::dbl;
  std::optional<double> max_memory_gb;  // gui --max-memory, applied to every scene loaded
  char open_path[512] = "";

  // A sweep folder (app/sweep/open.hpp): its charts under the panes; a click opens a run.
  std::shared_ptr<const sweep::OpenedSweep> sweep;
  std::string sweep_error;  // one line: the last folder that could not be opened, and why
  char sweep_path[512] = "";
  int sweep_scene = 0;       // which scene's charts
  long sweep_run = -1;       // the run whose panes are live (beside its reference)
  bool sweep_plots = false;  // the live plots instead of the sweep's charts

  // Playback.
  bool realtime = true;
  char checkpoint_path[512] = "";  // Save / Load: empty is apiclab-out/SCENE.checkpoint

  // View: one camera linked across panes.
  render::View view;
  std::uint64_t framed_generation = ~std::uint64_t(0);
  render::ColorMode color = render::ColorMode::speed;
  bool vectors = false, grid = false, auto_scale = true;
  bool surface = true, surface_vectors = false;  // object surfaces (EoL panes), arrows on them
  float color_max = 0;    // top of the colormap: shown (auto scale) or set by hand
  float vector_gain = 1;  // multiplies the automatic arrow length
  float particle_scale = 1;
  const Snapshot* scaled_for = nullptr;  // snapshot the scales were last updated from
  render::ScaleState scales;             // render/auto_scale.hpp: shared by all panes

  // Plots: which component each plot shows when several panes share it.
  int energy_component = 2;    // kinetic, potential, total
  int momentum_component = 0;  // x, y, z
  int angular_component = 2;   // x, y, z (2D: z only)

  // The scene description as last drawn: characters shown of all, and its height (pixels).
  std::size_t description_shown = 0;
  float description_px = 0;

  // Where the last frame put its parts (x, y, width, height in pixels), by name: printed with
  // the panes under APICLAB_PRINT_LAYOUT=1 for the layout tests.
  std::map<std::string, ImVec4> layout;
  std::map<std::string, std::string> layout_text;  // what some of them say: pane title strips

  // Frame timing (GUI thread), exponential averages.
  double frame_ms = 0, frame_cpu_ms = 0;
};

// Palette for panes in plots and labels (Okabe & Ito, as the renderer's categories).
ImU32 pane_color(std::size_t pane);
std::string pane_label(const PaneState& p);

// Parts of the window, each in its own file.
void draw_controls(ViewerState& st, const Published& pub, SimWorker& worker);
void draw_plots(ViewerState& st, const Published& pub, ImVec2 pos, ImVec2 size);
// Loads st.scene_path into st.scene and restarts the worker; errors land in st.load_error.
void load_scene_file(ViewerState& st, SimWorker& worker, const std::string& path,
                     const std::vector<std::string>& overrides = {});
void restart(ViewerState& st, SimWorker& worker);

// The sweep panel (app/gui/sweep_panel.cpp) in the area under the panes; returns the height it
// took (all of it with the charts, its header row when the live plots are shown instead).
float draw_sweep_panel(ViewerState& st, SimWorker& worker, ImVec2 pos, ImVec2 size);
// Opens a sweep folder and shows its first scene's reference run; on failure the one-line
// reason lands in st.sweep_error and what was shown stays. Returns whether it opened.
bool open_sweep_folder(ViewerState& st, SimWorker& worker, const std::string& dir);
// What a click on a chart point or a stability cell does: that run's configuration beside its
// reference's, both from t = 0 in lockstep (sweep::launch_run).
void open_sweep_run(ViewerState& st, SimWorker& worker, std::size_t run);
// Adopts an already opened sweep (the command line opened it to check it).
void show_sweep(ViewerState& st, SimWorker& worker,
                std::shared_ptr<const sweep::OpenedSweep> sweep);

}  // namespace apiclab::gui
