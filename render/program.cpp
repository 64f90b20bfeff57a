#include "render/program.hpp"

#include <stdexcept>

#include "render/gl.hpp"
#include "render/resources.hpp"

namespace apiclab::render {
namespace {

GLuint compile(GLenum type, const std::string& name) {
  std::string_view source = resource(name);
  GLuint shader = gl::CreateShader(type);
  const char* text = source.data();
  GLint length = GLint(source.size());
  gl::ShaderSource(shader, 1, &text, &length);
  gl::CompileShader(shader);
  GLint ok = 0;
  gl::GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    gl::GetShaderInfoLog(shader, sizeof log, nullptr, log);
    gl::DeleteShader(shader);
    throw std::runtime_error("shader " + name + ": " + log);
  }
  return shader;
}

}  // namespace

Program::Program(const std::string& vertex, const std::string& fragment) {
  GLuint vs = compile(GL_VERTEX_SHADER, vertex);
  GLuint fs = compile(GL_FRAGMENT_SHADER, fragment);
  id_ = gl::CreateProgram();
  gl::AttachShader(id_, vs);
  gl::AttachShader(id_, fs);
  gl::LinkProgram(id_);
  gl::DeleteShader(vs);
  gl::DeleteShader(fs);
  GLint ok = 0;
  gl::GetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    gl::GetProgramInfoLog(id_, sizeof log, nullptr, log);
    throw std::runtime_error("program " + vertex + " + " + fragment + ": " + log);
  }
}

Program::~Program() { gl::DeleteProgram(id_); }

void Program::use() const { gl::UseProgram(id_); }
int Program::location(const char* name) const { return gl::GetUniformLocation(id_, name); }
void Program::set(const char* name, int v) const { gl::Uniform1i(location(name), v); }
void Program::set(const char* name, float v) const { gl::Uniform1f(location(name), v); }
void Program::set(const char* name, float x, float y) const { gl::Uniform2f(location(name), x, y); }
void Program::set(const char* name, Vec3 v) const { gl::Uniform3f(location(name), v.x, v.y, v.z); }
void Program::set(const char* name, const Mat4& m) const {
  gl::UniformMatrix4fv(location(name), 1, GL_FALSE, m.m);
}

}  // namespace apiclab::render
