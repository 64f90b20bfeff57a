// A closed triangle mesh read from an OBJ file (tinyobjloader), checked before use: every face
// index names an existing vertex, every vertex is finite, and the surface is closed and
// manifold (each edge shared by exactly two triangles), since the inside test counts ray
// crossings and is meaningless on an open or non-manifold surface.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace apiclab {

struct ObjMesh {
  std::vector<std::array<double, 3>> vertices;          // as in the file
  std::vector<std::array<std::uint32_t, 3>> triangles;  // polygons fan-triangulated
  double volume() const;  // enclosed volume (divergence theorem), >= 0
};

// Throws SceneError "<path>: ..." naming the face or edge at fault.
ObjMesh load_obj_mesh(const std::string& path);

}  // namespace apiclab
