#include "render/context.hpp"

namespace apiclab::render {

Backend parse_backend(std::string_view key) {
  if (key == "auto") return Backend::automatic;
  if (key == "egl") return Backend::egl;
  if (key == "osmesa") return Backend::osmesa;
  throw std::invalid_argument("unknown backend '" + std::string(key) +
                              "' (expected auto|egl|osmesa)");
}

namespace {
constexpr const char* kInstallHint =
    "install libegl1 libegl-mesa0 libgl1-mesa-dri (EGL) or libosmesa6 (OSMesa)";
}

std::unique_ptr<OffscreenContext> create_offscreen_context(Backend backend) {
  if (backend == Backend::egl) {
    try {
      return create_egl_context();
    } catch (const ContextError& e) {
      throw ContextError(std::string("no EGL context: ") + e.what() + "; " + kInstallHint);
    }
  }
  if (backend == Backend::osmesa) {
    try {
      return create_osmesa_context();
    } catch (const ContextError& e) {
      throw ContextError(std::string("no OSMesa context: ") + e.what() + "; " + kInstallHint);
    }
  }
  std::string egl_reason;
  try {
    return create_egl_context();
  } catch (const ContextError& e) {
    egl_reason = e.what();
  }
  try {
    auto context = create_osmesa_context();
    context->egl_problem = egl_reason;
    return context;
  } catch (const ContextError& e) {
    throw ContextError("no offscreen OpenGL (EGL: " + egl_reason + "; OSMesa: " + e.what() + "); " +
                       kInstallHint);
  }
}

}  // namespace apiclab::render
