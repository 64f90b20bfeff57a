// Offscreen OpenGL 3.3 core contexts for headless rendering: EGL first (device platform for
// GPUs, Mesa's surfaceless platform otherwise), OSMesa as the fallback. Both libraries are
// loaded at run time, so a machine with neither gets one clear line instead of a crash.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

namespace apiclab::render {

enum class Backend { automatic, egl, osmesa };

// "auto" | "egl" | "osmesa"; throws std::invalid_argument naming the valid keys.
Backend parse_backend(std::string_view key);

// No context could be made: the message is one line that says what to install.
struct ContextError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class OffscreenContext {
 public:
  virtual ~OffscreenContext() = default;
  // How the context was made and what draws, e.g.
  // "EGL surfaceless: llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6".
  virtual std::string description() const = 0;
  virtual void make_current() = 0;
  // With Backend::automatic on OSMesa: why EGL was passed over (empty otherwise).
  std::string egl_problem;
};

// Creates a context, makes it current and loads the gl:: functions. Throws ContextError.
// APICLAB_EGL_LIBRARY and APICLAB_OSMESA_LIBRARY name other libraries to load (tests use
// them to play a machine without either).
std::unique_ptr<OffscreenContext> create_offscreen_context(Backend backend);

// The two halves (context.cpp picks); each throws ContextError with its own reason.
std::unique_ptr<OffscreenContext> create_egl_context();
std::unique_ptr<OffscreenContext> create_osmesa_context();

}  // namespace apiclab::render
