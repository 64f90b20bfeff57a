// A linked GLSL program built from embedded sources, with uniform setters by name.
#pragma once
#include <string>

#include "render/math.hpp"

namespace apiclab::render {

class Program {
 public:
  // Names of embedded files, e.g. "shaders/fill.vert"; throws std::runtime_error with the
  // compiler's log on failure.
  Program(const std::string& vertex, const std::string& fragment);
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  void use() const;
  void set(const char* name, int value) const;
  void set(const char* name, float value) const;
  void set(const char* name, float x, float y) const;
  void set(const char* name, Vec3 v) const;
  void set(const char* name, const Mat4& m) const;

 private:
  int location(const char* name) const;
  unsigned id_ = 0;
};

}  // namespace apiclab::render
