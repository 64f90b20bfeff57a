// Mesa's off-screen rendering library, the fallback when EGL is missing. libOSMesa is
// dlopen'ed; the context draws into our own framebuffer object, so its buffer is tiny.
#include <dlfcn.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "render/context.hpp"
// clang-format off
#include "render/gl.hpp"  // before osmesa.h: its <GL/gl.h> would hide glcorearb's 1.1 types
#include <GL/osmesa.h>
// clang-format on

namespace apiclab::render {
namespace {

struct OsMesa {
  OSMesaContext (*CreateContextAttribs)(const int*, OSMesaContext) = nullptr;
  GLboolean (*MakeCurrent)(OSMesaContext, void*, GLenum, GLsizei, GLsizei) = nullptr;
  void (*DestroyContext)(OSMesaContext) = nullptr;
  OSMESAproc (*GetProcAddress)(const char*) = nullptr;
};

const OsMesa& osmesa_library() {
  static const OsMesa osmesa = [] {
    void* lib = nullptr;
    const char* override_name = std::getenv("APICLAB_OSMESA_LIBRARY");
    std::vector<std::string> names = {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"};
    if (override_name) names = {override_name};
    for (const std::string& name : names)
      if ((lib = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL))) break;
    if (!lib) throw ContextError(names.front() + " not found");
    OsMesa o;
    auto sym = [&](auto& fn, const char* name) {
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(dlsym(lib, name));
      if (!fn) throw ContextError(std::string("libOSMesa lacks ") + name);
    };
    sym(o.CreateContextAttribs, "OSMesaCreateContextAttribs");
    sym(o.MakeCurrent, "OSMesaMakeCurrent");
    sym(o.DestroyContext, "OSMesaDestroyContext");
    sym(o.GetProcAddress, "OSMesaGetProcAddress");
    return o;
  }();
  return osmesa;
}

void* gl_proc(const char* name) {
  return reinterpret_cast<void*>(osmesa_library().GetProcAddress(name));
}

class OsMesaContext : public OffscreenContext {
 public:
  OsMesaContext() {
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              24,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              3,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              3,
                              0};
    context_ = osmesa_library().CreateContextAttribs(attributes, nullptr);
    if (!context_) throw ContextError("OSMesaCreateContextAttribs(OpenGL 3.3 core) failed");
    make_current();
    std::string problem = gl::load(gl_proc);
    if (!problem.empty()) throw ContextError(problem);
    description_ = "OSMesa: " + gl::describe_current_context();
  }
  ~OsMesaContext() override { osmesa_library().DestroyContext(context_); }

  std::string description() const override { return description_; }
  void make_current() override {
    if (!osmesa_library().MakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, 16, 16))
      throw ContextError("OSMesaMakeCurrent failed");
  }

 private:
  OSMesaContext context_ = nullptr;
  std::vector<unsigned char> buffer_ = std::vector<unsigned char>(16 * 16 * 4);
  std::string description_;
};

}  // namespace

std::unique_ptr<OffscreenContext> create_osmesa_context() {
  return std::make_unique<OsMesaContext>();
}

}  // namespace apiclab::render
