// EGL without a display: a GPU through the device platform when there is one (NVIDIA),
// otherwise Mesa's surfaceless platform (llvmpipe on a CI machine). libEGL is dlopen'ed.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <functional>
#include <vector>

#include "render/context.hpp"
#include "render/gl.hpp"

namespace apiclab::render {
namespace {

struct Egl {
  PFNEGLGETPROCADDRESSPROC GetProcAddress = nullptr;
  PFNEGLGETDISPLAYPROC GetDisplay = nullptr;
  PFNEGLINITIALIZEPROC Initialize = nullptr;
  PFNEGLTERMINATEPROC Terminate = nullptr;
  PFNEGLQUERYSTRINGPROC QueryString = nullptr;
  PFNEGLBINDAPIPROC BindAPI = nullptr;
  PFNEGLCHOOSECONFIGPROC ChooseConfig = nullptr;
  PFNEGLCREATECONTEXTPROC CreateContext = nullptr;
  PFNEGLDESTROYCONTEXTPROC DestroyContext = nullptr;
  PFNEGLCREATEPBUFFERSURFACEPROC CreatePbufferSurface = nullptr;
  PFNEGLDESTROYSURFACEPROC DestroySurface = nullptr;
  PFNEGLMAKECURRENTPROC MakeCurrent = nullptr;
  PFNEGLGETERRORPROC GetError = nullptr;
  PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplayEXT = nullptr;
  PFNEGLQUERYDEVICESEXTPROC QueryDevicesEXT = nullptr;
  PFNEGLQUERYDEVICESTRINGEXTPROC QueryDeviceStringEXT = nullptr;
};

// The one loaded libEGL (never unloaded: drivers register exit handlers).
const Egl& egl_library() {
  static const Egl egl = [] {
    const char* override_name = std::getenv("APICLAB_EGL_LIBRARY");
    const std::string name = override_name ? override_name : "libEGL.so.1";
    void* lib = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib) throw ContextError(name + " not found");
    Egl e;
    auto sym = [&](auto& fn, const char* name) {
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(dlsym(lib, name));
      if (!fn) throw ContextError(std::string("libEGL lacks ") + name);
    };
    sym(e.GetProcAddress, "eglGetProcAddress");
    sym(e.GetDisplay, "eglGetDisplay");
    sym(e.Initialize, "eglInitialize");
    sym(e.Terminate, "eglTerminate");
    sym(e.QueryString, "eglQueryString");
    sym(e.BindAPI, "eglBindAPI");
    sym(e.ChooseConfig, "eglChooseConfig");
    sym(e.CreateContext, "eglCreateContext");
    sym(e.DestroyContext, "eglDestroyContext");
    sym(e.CreatePbufferSurface, "eglCreatePbufferSurface");
    sym(e.DestroySurface, "eglDestroySurface");
    sym(e.MakeCurrent, "eglMakeCurrent");
    sym(e.GetError, "eglGetError");
    auto ext = [&](auto& fn, const char* name) {
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(e.GetProcAddress(name));
    };
    ext(e.GetPlatformDisplayEXT, "eglGetPlatformDisplayEXT");
    ext(e.QueryDevicesEXT, "eglQueryDevicesEXT");
    ext(e.QueryDeviceStringEXT, "eglQueryDeviceStringEXT");
    return e;
  }();
  return egl;
}

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

void* gl_proc(const char* name) {
  return reinterpret_cast<void*>(egl_library().GetProcAddress(name));
}

class EglContext : public OffscreenContext {
 public:
  EglContext(EGLDisplay display, std::string platform) : display_(display) {
    const Egl& egl = egl_library();
    EGLint major = 0, minor = 0;
    if (!egl.Initialize(display_, &major, &minor)) throw error("eglInitialize");
    initialized_ = true;
    if (!egl.BindAPI(EGL_OPENGL_API)) throw error("eglBindAPI(OpenGL)");
    // Pbuffer-capable configs first (needed when surfaceless contexts are not offered).
    EGLConfig config = nullptr;
    EGLint count = 0;
    for (EGLint surface_type : {EGL_PBUFFER_BIT, 0}) {
      const EGLint attributes[] = {EGL_SURFACE_TYPE,
                                   surface_type,
                                   EGL_RENDERABLE_TYPE,
                                   EGL_OPENGL_BIT,
                                   EGL_RED_SIZE,
                                   8,
                                   EGL_GREEN_SIZE,
                                   8,
                                   EGL_BLUE_SIZE,
                                   8,
                                   EGL_NONE};
      if (egl.ChooseConfig(display_, attributes, &config, 1, &count) && count > 0) break;
    }
    if (count == 0) throw ContextError(platform + ": no OpenGL config");
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                         3,
                                         EGL_CONTEXT_MINOR_VERSION,
                                         3,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_NONE};
    context_ = egl.CreateContext(display_, config, EGL_NO_CONTEXT, context_attributes);
    if (context_ == EGL_NO_CONTEXT) throw error(platform + ": OpenGL 3.3 core context");
    if (!has_extension(egl.QueryString(display_, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context")) {
      const EGLint pbuffer_attributes[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};
      surface_ = egl.CreatePbufferSurface(display_, config, pbuffer_attributes);
      if (surface_ == EGL_NO_SURFACE) throw error(platform + ": pbuffer");
    }
    make_current();
    std::string problem = gl::load(gl_proc);
    if (!problem.empty()) throw ContextError(platform + ": " + problem);
    description_ = "EGL " + platform + ": " + gl::describe_current_context();
  }

  ~EglContext() override {
    const Egl& egl = egl_library();
    egl.MakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (surface_ != EGL_NO_SURFACE) egl.DestroySurface(display_, surface_);
    if (context_ != EGL_NO_CONTEXT) egl.DestroyContext(display_, context_);
    if (initialized_) egl.Terminate(display_);
  }

  std::string description() const override { return description_; }

  void make_current() override {
    if (!egl_library().MakeCurrent(display_, surface_, surface_, context_))
      throw error("eglMakeCurrent");
  }

 private:
  ContextError error(const std::string& what) const {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", egl_library().GetError());
    return ContextError(what + " failed (EGL error " + code + ")");
  }

  EGLDisplay display_;
  EGLContext context_ = EGL_NO_CONTEXT;
  EGLSurface surface_ = EGL_NO_SURFACE;
  bool initialized_ = false;
  std::string description_;
};

}  // namespace

std::unique_ptr<OffscreenContext> create_egl_context() {
  const Egl& egl = egl_library();
  const char* client = egl.QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  std::vector<std::function<std::unique_ptr<OffscreenContext>()>> attempts;
  std::string reasons;

  // 1. Hardware devices (NVIDIA's EGL, or Mesa on a DRM GPU); Mesa's software device is
  //    skipped here because the surfaceless platform below is the same thing.
  if (egl.GetPlatformDisplayEXT && egl.QueryDevicesEXT &&
      has_extension(client, "EGL_EXT_platform_device")) {
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (egl.QueryDevicesEXT(16, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        const char* ext =
            egl.QueryDeviceStringEXT ? egl.QueryDeviceStringEXT(devices[i], EGL_EXTENSIONS) : "";
        if (has_extension(ext, "EGL_MESA_device_software")) continue;
        EGLDeviceEXT device = devices[i];
        attempts.push_back([&egl, device, i] {
          EGLDisplay d = egl.GetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
          if (d == EGL_NO_DISPLAY)
            throw ContextError("device " + std::to_string(i) + ": no display");
          return std::make_unique<EglContext>(d, "device " + std::to_string(i));
        });
      }
    }
  }
  // 2. Mesa's surfaceless platform (llvmpipe, or a GPU through its render node).
  if (egl.GetPlatformDisplayEXT && has_extension(client, "EGL_MESA_platform_surfaceless")) {
    attempts.push_back([&egl] {
      EGLDisplay d =
          egl.GetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
      if (d == EGL_NO_DISPLAY) throw ContextError("surfaceless: no display");
      return std::make_unique<EglContext>(d, "surfaceless");
    });
  }
  // 3. Whatever the default display is (EGL_PLATFORM in the environment decides).
  attempts.push_back([&egl] {
    EGLDisplay d = egl.GetDisplay(EGL_DEFAULT_DISPLAY);
    if (d == EGL_NO_DISPLAY) throw ContextError("default display: none");
    return std::make_unique<EglContext>(d, "default display");
  });

  for (auto& attempt : attempts) {
    try {
      return attempt();
    } catch (const ContextError& e) {
      reasons += (reasons.empty() ? "" : "; ") + std::string(e.what());
    }
  }
  throw ContextError(reasons);
}

}  // namespace apiclab::render
