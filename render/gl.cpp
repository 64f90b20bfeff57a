#include "render/gl.hpp"

#include <cstdio>

namespace apiclab::gl {

#define APICLAB_GL_DEFINE(name, type) type name = nullptr;
APICLAB_GL_FUNCTIONS(APICLAB_GL_DEFINE)
#undef APICLAB_GL_DEFINE

std::string load(ProcLoader loader) {
  std::string missing;
#define APICLAB_GL_LOAD(name, type)                  \
  name = reinterpret_cast<type>(loader("gl" #name)); \
  if (!name) missing += (missing.empty() ? "gl" : ", gl") + std::string(#name);
  APICLAB_GL_FUNCTIONS(APICLAB_GL_LOAD)
#undef APICLAB_GL_LOAD
  if (!missing.empty()) return "OpenGL functions not found: " + missing;
  GLint major = 0, minor = 0;
  GetIntegerv(GL_MAJOR_VERSION, &major);
  GetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 33) {
    const char* version = reinterpret_cast<const char*>(GetString(GL_VERSION));
    return "OpenGL 3.3 core is needed, the context offers " +
           std::string(version ? version : "no version");
  }
  return {};
}

std::string describe_current_context() {
  auto str = [](GLenum e) {
    const char* s = reinterpret_cast<const char*>(GetString(e));
    return std::string(s ? s : "?");
  };
  return str(GL_RENDERER) + ", OpenGL " + str(GL_VERSION);
}

}  // namespace apiclab::gl
