// The interactive viewer: a GLFW window with Dear ImGui controls, the renderer's panes side by
// side, and live plots, fed by a SimWorker (docs/architecture.md, "Threads").
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace apiclab::sweep {
struct OpenedSweep;
}

namespace apiclab::gui {

struct ViewerOptions {
  std::string scene = "rotating-disk";  // path or shipped scene name
  std::vector<std::string> schemes;     // one pane per scheme; empty: the scene's
  std::vector<std::string> overrides;   // --set KEY=VALUE, applied to the scene
  std::string precision = "double";
  std::string color = "speed";
  bool vectors = false, realtime = true, paused = false;
  int width = 1600, height = 900;
  std::string screenshot;  // save the window as PNG after `frames` frames, then exit
  int frames = 0;          // without a screenshot: run live this many frames, print timings, exit
  // gui --sweep DIR: the sweep, opened (and so checked) by the command line; sweep_run: the run
  // shown beside its reference at the start (-1: the first scene's reference run alone).
  std::shared_ptr<const sweep::OpenedSweep> sweep;
  long sweep_run = -1;
  // Rewritten after every frame with "FRAME SECONDS" (app/gui/heartbeat.hpp); empty: none.
  std::string heartbeat;
  std::optional<double> max_memory_gb;  // --max-memory: the cap for every scene loaded
  // gui --open-checkpoint DIR: a run's checkpoint as the pane, paused; --save-checkpoint DIR:
  // the panes saved as runs' checkpoints after --screenshot or --frames (pane_checkpoint.hpp).
  std::string open_checkpoint, save_checkpoint;
};

// Opens the window and runs until it closes. Returns the process exit code.
int run_viewer(const ViewerOptions& options);

// Whether a window can be opened here (a display answers).
bool display_available();

}  // namespace apiclab::gui
