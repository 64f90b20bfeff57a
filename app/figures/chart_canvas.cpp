#include "app/figures/chart_canvas.hpp"

#include <imgui.h>
#include <imgui_impl_opengl3.h>

#include <stdexcept>

#include "render/context.hpp"
#include "render/gl.hpp"
#include "render/resources.hpp"
#include "render/target.hpp"

namespace apiclab::figures {

struct ChartCanvas::Gl {
  std::unique_ptr<render::OffscreenContext> context;
};

ChartCanvas::ChartCanvas(float font_px) : gl_(std::make_unique<Gl>()) {
  // ImGui's OpenGL3 backend resolves GL through libGL.so.1 (glvnd), which dispatches to the
  // current EGL context; an OSMesa context is invisible to it.
  try {
    gl_->context = render::create_offscreen_context(render::Backend::egl);
  } catch (const render::ContextError& e) {
    throw std::runtime_error(std::string("charts need an EGL context: ") + e.what());
  }
  description_ = gl_->context->description();
  IMGUI_CHECKVERSION();
  imgui_ = ImGui::CreateContext();
  ImGui::SetCurrentContext(imgui_);
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;
  io.LogFilename = nullptr;
  const std::string_view ttf = render::resource("fonts/DejaVuSans.ttf");
  ImFontConfig cfg;
  cfg.FontDataOwnedByAtlas = false;  // the bytes are embedded in the binary
  cfg.OversampleH = 3;
  static const ImWchar ranges[] = {0x0020, 0x00FF,  // Latin-1: ², ·, ×
                                   0x0370, 0x03FF,  // Greek: Δ, α, λ
                                   0x2013, 0x2014,  // dashes
                                   0x2070, 0x209F,  // super- and subscripts
                                   0x2212, 0x2212,  // minus sign
                                   0};
  io.Fonts->AddFontFromMemoryTTF(const_cast<char*>(ttf.data()), int(ttf.size()), font_px, &cfg,
                                 ranges);
  title_font_ = io.Fonts->AddFontFromMemoryTTF(const_cast<char*>(ttf.data()), int(ttf.size()),
                                               font_px * 1.25f, &cfg, ranges);
  ImGui::StyleColorsLight();
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowPadding = ImVec2(0, 0);
  style.WindowBorderSize = 0;
  style.WindowRounding = 0;
  style.AntiAliasedLines = style.AntiAliasedFill = true;
  style.Colors[ImGuiCol_WindowBg] = ImVec4(1, 1, 1, 1);
  if (!ImGui_ImplOpenGL3_Init("#version 330")) {
    ImGui::DestroyContext(imgui_);
    imgui_ = nullptr;
    throw std::runtime_error("ImGui's OpenGL3 backend could not load OpenGL through libGL.so.1");
  }
}

ChartCanvas::~ChartCanvas() {
  if (imgui_) {
    ImGui::SetCurrentContext(imgui_);
    gl_->context->make_current();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui::DestroyContext(imgui_);
  }
}

void ChartCanvas::make_current() { gl_->context->make_current(); }

render::Image ChartCanvas::draw(int width, int height, const std::function<void()>& body) {
  ImGui::SetCurrentContext(imgui_);
  gl_->context->make_current();
  render::RenderTarget target(width, height);
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(float(width), float(height));
  io.DisplayFramebufferScale = ImVec2(1, 1);
  io.DeltaTime = 1.0f / 60;
  io.MousePos = ImVec2(-1e6f, -1e6f);
  // Two frames: ImGui settles a new window's layout on its first.
  for (int pass = 0; pass < 2; ++pass) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(io.DisplaySize);
    ImGui::Begin("##figure", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoSavedSettings |
                     ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoInputs);
    body();
    ImGui::End();
    ImGui::Render();
  }
  target.bind();
  gl::Viewport(0, 0, width, height);
  gl::ClearColor(1, 1, 1, 1);
  gl::Clear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  return target.read();
}

}  // namespace apiclab::figures
