#include "app/gui/viewer.hpp"

#include "render/gl.hpp"  // before GLFW, which must not pull in the system <GL/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include "app/assets.hpp"
#include "app/clock.hpp"
#include "app/gui/heartbeat.hpp"
#include "app/gui/pane_checkpoint.hpp"
#include "app/gui/scene_view.hpp"
#include "app/gui/viewer_state.hpp"
#include "app/pane_spec.hpp"
#include "render/gl.hpp"
#include "render/image.hpp"
#include "render/palette.hpp"
#include "render/renderer.hpp"
#include "render/target.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"

namespace apiclab::gui {
namespace {

// Set by any input the window gets (GLFW callbacks installed before ImGui's, which chain to
// them), so that the loop redraws after input and skips frames that would show nothing new.
bool input_seen = true;
void install_input_flag(GLFWwindow* window) {
  glfwSetCursorPosCallback(window, [](GLFWwindow*, double, double) { input_seen = true; });
  glfwSetMouseButtonCallback(window, [](GLFWwindow*, int, int, int) { input_seen = true; });
  glfwSetScrollCallback(window, [](GLFWwindow*, double, double) { input_seen = true; });
  glfwSetKeyCallback(window, [](GLFWwindow*, int, int, int, int) { input_seen = true; });
  glfwSetCharCallback(window, [](GLFWwindow*, unsigned) { input_seen = true; });
  glfwSetWindowFocusCallback(window, [](GLFWwindow*, int) { input_seen = true; });
  glfwSetCursorEnterCallback(window, [](GLFWwindow*, int) { input_seen = true; });
  glfwSetFramebufferSizeCallback(window, [](GLFWwindow*, int, int) { input_seen = true; });
}

}  // namespace
namespace {

constexpr float kSidebar = 350;           // control column width, pixels
constexpr float kSceneShare = 0.6f;       // of the height right of the column; plots below
constexpr float kSweepSceneShare = 0.5f;  // the same with a sweep's charts below

void setup_style() {
  ImGui::StyleColorsLight();
  ImGuiStyle& s = ImGui::GetStyle();
  s.WindowRounding = 0;
  s.FrameRounding = 3;
  s.GrabRounding = 3;
  s.WindowBorderSize = 0;
  s.FramePadding = ImVec2(6, 4);
  s.ItemSpacing = ImVec2(8, 6);
  s.Colors[ImGuiCol_WindowBg] = ImVec4(0.955f, 0.96f, 0.965f, 1);
  const char* font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  // Latin and Greek (the labels' α and β, Δ), and typographic punctuation (·, …, −).
  static const ImWchar ranges[] = {0x0020, 0x00FF, 0x0370, 0x03FF, 0x2010,
                                   0x2044, 0x2212, 0x2212, 0};
  if (std::filesystem::exists(font))
    ImGui::GetIO().Fonts->AddFontFromFileTTF(font, 14.5f, nullptr, ranges);
}

void* gl_proc(const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); }

}  // namespace

ImU32 pane_color(std::size_t pane) { return render::packed_abgr(render::palette_color(int(pane))); }

std::string pane_label(const PaneState& p) {
  const std::string before = p.config.label.empty() ? "" : p.config.label + ": ";
  if (!p.config.method.empty() && p.config.method != "mpm")
    return before + render::scheme_label(p.config.method);
  // The registry's spelling ("PolyPIC"), as the command line and the figures write it.
  std::string s = render::scheme_label(key_of(p.config.scheme));
  // XPIC's m, PolyPIC's modes, ASFLIP's α and β (sim/mpm/schemes/scheme_label.hpp): scene-wide
  // numbers, so the last snapshot's hold for the pane's current scheme even right after a switch.
  const SchemeParameters parameters = p.snapshot       ? p.snapshot->scheme_parameters
                                      : p.config.scene ? scheme_parameters_of(*p.config.scene)
                                                       : SchemeParameters{};
  s = before + with_scheme_parameter(s, p.config.scheme, p.config.flip_alpha, parameters);
  return s;
}

void restart(ViewerState& st, SimWorker& worker) {
  worker.load(st.scene, st.panes, st.precision);
  worker.set_noise(st.color == render::ColorMode::noise);
}

void load_scene_file(ViewerState& st, SimWorker& worker, const std::string& path,
                     const std::vector<std::string>& overrides) {
  try {
    st.scene = load_scene(resolve_scene_path(path), overrides);
    st.scene.asset_dirs.push_back(assets_directory());
    if (st.max_memory_gb) st.scene.solver.max_memory_gb = st.max_memory_gb;
    st.scene_path = resolve_scene_path(path);
    st.scene_loaded = true;
    st.load_error.clear();
    st.notice.clear();
    if (st.panes.empty()) {
      PaneConfig pane;
      pane.scheme = st.scene.solver.scheme, pane.flip_alpha = st.scene.solver.flip_alpha;
      st.panes.push_back(pane);
    }
    for (auto& p : st.panes)  // --schemes panes take the scene's (or --flip-alpha's) blend
      if (p.flip_alpha < 0) p.flip_alpha = st.scene.solver.flip_alpha;
    restart(st, worker);
    worker.play(true);
  } catch (const std::exception& e) {  // the window stays up and shows why
    st.load_error = e.what();
  }
}

bool display_available() {
  const char* x = std::getenv("DISPLAY");
  const char* w = std::getenv("WAYLAND_DISPLAY");
  if (!(x && *x) && !(w && *w)) return false;
  glfwSetErrorCallback(nullptr);
  if (!glfwInit()) return false;
  glfwTerminate();
  return true;
}

int run_viewer(const ViewerOptions& opt) {
  glfwSetErrorCallback(
      [](int code, const char* msg) { std::fprintf(stderr, "apiclab: GLFW %d: %s\n", code, msg); });
  // A display server that has just started (xvfb-run on a busy machine) may need a moment.
  bool up = glfwInit();
  for (int i = 0; i < 5 && !up && std::getenv("DISPLAY"); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    up = glfwInit();
  }
  if (!up) {
    std::fprintf(stderr,
                 "apiclab: cannot open a window (no display? set DISPLAY or use xvfb-run); "
                 "headless frames: apiclab render\n");
    return 2;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GL_TRUE);
  // 4x MSAA smooths the arrows on a GPU; a software rasterizer (llvmpipe under Xvfb) pays
  // about 4x per frame for it, so there the window is made again without (APICLAB_MSAA overrides).
  const char* msaa_env = std::getenv("APICLAB_MSAA");
  int samples = msaa_env ? std::atoi(msaa_env) : 4;
  GLFWwindow* window = nullptr;
  for (int attempt = 0; attempt < 2; ++attempt) {
    glfwWindowHint(GLFW_SAMPLES, samples);
    window = glfwCreateWindow(opt.width, opt.height, "apiclab", nullptr, nullptr);
    if (!window) break;
    glfwMakeContextCurrent(window);
    if (std::string err = gl::load(gl_proc); !err.empty()) {
      std::fprintf(stderr, "apiclab: %s\n", err.c_str());
      glfwDestroyWindow(window);
      glfwTerminate();
      return 2;
    }
    const std::string renderer = gl::describe_current_context();
    const bool software = renderer.find("llvmpipe") != std::string::npos ||
                          renderer.find("softpipe") != std::string::npos;
    if (attempt > 0 || msaa_env || !software || samples == 0) break;
    glfwDestroyWindow(window);
    samples = 0;
  }
  if (!window) {
    glfwTerminate();
    std::fprintf(stderr, "apiclab: cannot create an OpenGL 3.3 window\n");
    return 2;
  }
  glfwSwapInterval(1);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // the layout is fixed; no imgui.ini litter
  setup_style();
  install_input_flag(window);  // before ImGui's callbacks, which chain to these
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  int status = 0;
  {
    render::Renderer renderer;
    SimWorker worker;
    ViewerState st;
    st.realtime = opt.realtime && opt.screenshot.empty();
    st.vectors = opt.vectors;
    st.color = render::parse_color_mode(opt.color);
    st.precision = parse_choice(precision_choices(), opt.precision, "precision");
    st.max_memory_gb = opt.max_memory_gb;
    for (auto& key : opt.schemes) {  // checked by the command line (app/cmd_gui.cpp)
      const PaneSpec spec = parse_panes(key).front();
      PaneConfig pane;
      pane.scheme = spec.scheme, pane.flip_alpha = -1.0, pane.method = spec.method;
      st.panes.push_back(pane);
    }
    std::error_code ec;
    for (auto& e : std::filesystem::directory_iterator(scenes_directory(), ec))
      if (e.path().extension() == ".json") st.scene_files.push_back(e.path().string());
    std::sort(st.scene_files.begin(), st.scene_files.end());
    worker.set_realtime(st.realtime);
    if (opt.sweep) {
      show_sweep(st, worker, opt.sweep);
      if (opt.sweep_run >= 0) open_sweep_run(st, worker, std::size_t(opt.sweep_run));
      if (!st.sweep_error.empty()) st.load_error = st.sweep_error;
    } else if (!opt.open_checkpoint.empty()) {
      open_checkpoint(st, worker, opt.open_checkpoint);
    } else {
      load_scene_file(st, worker, opt.scene, opt.overrides);
    }
    if (!st.load_error.empty()) std::fprintf(stderr, "apiclab: %s\n", st.load_error.c_str());
    if (!opt.screenshot.empty() || opt.paused) worker.play(false);

    // --save-checkpoint DIR at the end of --screenshot or --frames: the worker writes them.
    const auto save_checkpoints = [&] {
      if (opt.save_checkpoint.empty()) return;
      save_pane_checkpoints(st, worker, opt.save_checkpoint);
      worker.sync();
      const auto saved = worker.latest();
      if (!saved->error.empty()) {
        std::fprintf(stderr, "apiclab: %s\n", saved->error.c_str());
        status = 2;
      } else {
        std::printf("%s\n", saved->notice.c_str());
      }
    };
    long frame = 0;
    // Screenshots: the frames the worker had done before the first drawn one (a checkpoint's).
    long first_frame = 0;
    if (!opt.screenshot.empty()) worker.sync(), first_frame = worker.latest()->frame;
    double last = now_seconds(), last_drawn = 0;
    int redraws_owed = 0;  // ImGui settles hover and layout over a frame or two after input
    std::shared_ptr<const Published> shown;
    Heartbeat heartbeat(opt.heartbeat);
    while (!glfwWindowShouldClose(window)) {
      const double t0 = now_seconds();
      glfwPollEvents();
      // Screenshots are deterministic: each displayed frame is one more simulated frame.
      if (!opt.screenshot.empty()) {
        worker.step_frame();
        worker.sync(first_frame + frame + 1);
      }
      const auto pub = worker.latest();
      // Draw only what changed: a new published state, input, or 4 times a second (the
      // heartbeat, the readouts). A software rasteriser (Xvfb) otherwise spends a core drawing
      // the same state again, which the solver's panes need.
      if (input_seen) redraws_owed = 3, input_seen = false;
      if (opt.screenshot.empty() && pub == shown && redraws_owed == 0 && t0 - last_drawn < 0.25) {
        glfwWaitEventsTimeout(1.0 / 62);
        heartbeat.beat(frame, now_seconds());  // alive: events answered, nothing new to draw
        continue;
      }
      shown = pub;
      last_drawn = t0;
      if (redraws_owed > 0) --redraws_owed;
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      int fw, fh;
      glfwGetFramebufferSize(window, &fw, &fh);
      const float W = float(fw), H = float(fh);
      st.layout.clear(), st.layout_text.clear();
      ImGui::SetNextWindowPos(ImVec2(0, 0));
      ImGui::SetNextWindowSize(ImVec2(kSidebar, H));
      draw_controls(st, *pub, worker);
      // With a sweep open its charts take a little more of the height, under the panes.
      const float scene_h = std::round(H * (st.sweep ? kSweepSceneShare : kSceneShare));
      ImVec2 below(kSidebar, scene_h), below_size(W - kSidebar, H - scene_h);
      if (st.sweep) {
        const float used = draw_sweep_panel(st, worker, below, below_size);
        below.y += used, below_size.y -= used;
      }
      if (below_size.y > 40) draw_plots(st, *pub, below, below_size);
      renderer.begin_frame(fw, fh, {255, 255, 255, 255});
      const auto rects = draw_scene_panes(renderer, st, *pub, {kSidebar, 0, W - kSidebar, scene_h});
      renderer.end_frame();
      ImGui::Render();
      gl::Viewport(0, 0, fw, fh);
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      ++frame;
      if (!opt.screenshot.empty() && frame >= std::max(opt.frames, 1)) {
        // Where each pane is, for the smoke test only (APICLAB_PRINT_LAYOUT=1): no debug lines
        // on a user's stdout.
        if (const char* e = std::getenv("APICLAB_PRINT_LAYOUT"); e && std::string(e) == "1")
          for (std::size_t k = 0; k < rects.size(); ++k)
            std::printf("pane %zu: %.0f %.0f %.0f %.0f\n", k, rects[k].x, rects[k].y, rects[k].w,
                        rects[k].h);
        if (const char* e = std::getenv("APICLAB_PRINT_LAYOUT"); e && std::string(e) == "1") {
          std::printf("description: %zu of %zu characters, %.0f px\n", st.description_shown,
                      st.scene.description.size(), st.description_px);
          std::printf("window: 0 0 %d %d\n", fw, fh);
          for (const auto& [name, r] : st.layout)
            std::printf("widget %s: %.0f %.0f %.0f %.0f\n", name.c_str(), r.x, r.y, r.z, r.w);
          for (const auto& [name, text] : st.layout_text)
            std::printf("text %s: %s\n", name.c_str(), text.c_str());
        }
        try {
          render::write_png(render::read_window_pixels(fw, fh), opt.screenshot);
          std::printf("screenshot: %s (%dx%d, %ld frames, t = %.4g s)\n", opt.screenshot.c_str(),
                      fw, fh, frame, pub->panes.empty() ? 0.0 : pub->panes[0].snapshot->time);
        } catch (const std::exception& e) {
          std::fprintf(stderr, "apiclab: %s\n", e.what());
          status = 2;
        }
        if (!st.load_error.empty()) status = 2;  // scripts see that the scene did not load
        save_checkpoints();
        glfwSetWindowShouldClose(window, 1);
      }
      if (opt.screenshot.empty() && opt.frames > 0 &&
          frame >= opt.frames) {  // timed run: report, exit
        std::printf(
            "%ld frames, display %.1f fps (%.2f ms/frame, GUI CPU %.2f ms), %.3g sim s/wall s, "
            "%.3g particle-steps/s\n",
            frame, 1000 / st.frame_ms, st.frame_ms, st.frame_cpu_ms,
            pub->sim_seconds_per_wall_second, pub->particle_steps_per_second);
        save_checkpoints();
        glfwSetWindowShouldClose(window, 1);
      }
      const double t1 = now_seconds();
      glfwSwapBuffers(window);
      // Without vsync (e.g. Xvfb) hold about 60 fps so the GUI leaves the cores to the solver.
      const double spent = now_seconds() - t0;
      if (opt.screenshot.empty() && spent < 1.0 / 62) glfwWaitEventsTimeout(1.0 / 62 - spent);
      const double now = now_seconds();
      st.frame_ms =
          st.frame_ms == 0 ? (now - last) * 1000 : 0.9 * st.frame_ms + 0.1 * (now - last) * 1000;
      st.frame_cpu_ms = 0.9 * st.frame_cpu_ms + 0.1 * (t1 - t0) * 1000;
      last = now;
      heartbeat.beat(frame, now);
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return status;
}

}  // namespace apiclab::gui
