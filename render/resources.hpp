// Files embedded into the binary at build time (render/embed.cmake): the GLSL sources from
// shaders/ and the DejaVu Sans font, so that apiclab runs from any directory.
#pragma once
#include <cstddef>
#include <string_view>
#include <vector>

namespace apiclab::render {

struct Resource {
  const char* name;  // "shaders/particles.vert", "fonts/DejaVuSans.ttf"
  const unsigned char* data;
  std::size_t size;  // without the terminating zero byte that follows data
};

const std::vector<Resource>& resources();

// The bytes of one embedded file; throws std::out_of_range naming it if absent.
std::string_view resource(std::string_view name);

}  // namespace apiclab::render
