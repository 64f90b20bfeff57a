// The interactive viewer: a GLFW window with Dear ImGui controls, the renderer's panes side by
// side, and live plots, fed by a SimWorker (docs/architecture.md, "Threads").
#pragma once
#include <optional>
#include <string>
#include <vector>

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
  // Rewritten after every frame with "FRAME SECONDS" (app/gui/heartbeat.hpp); empty: none.
  std::string heartbeat;
  std::optional<double> max_memory_gb;  // --max-memory: the cap for every scene loaded
};

// Opens the window and runs until it closes. Returns the process exit code.
int run_viewer(const ViewerOptions& options);

// Whether a window can be opened here (a display answers).
bool display_available();

}  // namespace apiclab::gui
