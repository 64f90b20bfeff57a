// Streams a vector into a vertex buffer, the one way every pass of the Renderer uploads.
#pragma once
#include <vector>

#include "render/gl.hpp"

namespace apiclab::render {

template <class T>
inline void upload(GLuint vbo, const std::vector<T>& data) {
  gl::BindBuffer(GL_ARRAY_BUFFER, vbo);
  // Orphan, then fill: the driver need not wait for the previous draw.
  gl::BufferData(GL_ARRAY_BUFFER, GLsizeiptr(data.size() * sizeof(T)), nullptr, GL_STREAM_DRAW);
  gl::BufferData(GL_ARRAY_BUFFER, GLsizeiptr(data.size() * sizeof(T)), data.data(), GL_STREAM_DRAW);
}

}  // namespace apiclab::render
