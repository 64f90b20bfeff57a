// A closed triangle mesh read from an OBJ file, checked before use: every coordinate a finite
// number, every face index naming an existing vertex, and the surface closed, manifold and
// consistently oriented (each edge shared by exactly two triangles that run it opposite ways),
// since the inside test counts the winding number and that is meaningless on an open,
// non-manifold or inconsistently oriented surface.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace apiclab {

struct ObjMesh {
  std::vector<std::array<double, 3>> vertices;          // as in the file
  std::vector<std::array<std::uint32_t, 3>> triangles;  // polygons fan-triangulated
  std::vector<std::uint32_t> triangle_lines;            // the file line of each triangle's face
  double volume() const;  // enclosed volume (divergence theorem), >= 0
};

// Reads the `v` and `f` lines (other OBJ statements are skipped). Throws SceneError
// "<path>:<line>: ..." for a bad line, "<path>: ..." for a fault of the whole surface.
ObjMesh load_obj_mesh(const std::string& path);

}  // namespace apiclab
