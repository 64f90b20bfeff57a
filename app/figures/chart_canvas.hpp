// Charts drawn offscreen: the GUI's plot widget (app/gui/plot.hpp) on an ImGui frame of a
// fixed size, rendered by ImGui's OpenGL3 backend into an offscreen framebuffer
// (render/context.hpp, render/target.hpp) and read back as an image for a PNG.
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "render/image.hpp"

struct ImGuiContext;
struct ImFont;

namespace apiclab::figures {

class ChartCanvas {
 public:
  // Makes the offscreen context (EGL; the backend loads GL through libglvnd) and an ImGui
  // context with DejaVu Sans at `font_px`. Throws std::runtime_error with one line.
  explicit ChartCanvas(float font_px = 14.0f);
  ~ChartCanvas();
  ChartCanvas(const ChartCanvas&) = delete;
  ChartCanvas& operator=(const ChartCanvas&) = delete;

  // One width x height frame on white: `body` lays out widgets (ImGui::SetCursorScreenPos,
  // gui::plot) in a window that fills it.
  render::Image draw(int width, int height, const std::function<void()>& body);
  std::string description() const { return description_; }
  void make_current();  // the context, for other drawing (render::Renderer)
  ImFont* title_font() const { return title_font_; }  // the same face, larger

 private:
  struct Gl;
  std::unique_ptr<Gl> gl_;
  ImGuiContext* imgui_ = nullptr;
  ImFont* title_font_ = nullptr;
  std::string description_;
};

}  // namespace apiclab::figures
