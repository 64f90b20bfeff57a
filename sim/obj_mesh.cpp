#include "obj_mesh.hpp"

#include <tiny_obj_loader.h>

#include <cmath>
#include <unordered_map>

#include "input_file.hpp"
#include "scene.hpp"

namespace apiclab {

double ObjMesh::volume() const {
  double v6 = 0;
  for (const auto& t : triangles) {
    const auto &a = vertices[t[0]], &b = vertices[t[1]], &c = vertices[t[2]];
    v6 += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
          a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return std::abs(v6) / 6.0;
}

ObjMesh load_obj_mesh(const std::string& path) {
  if (std::string problem = input_file_problem(path, "mesh file"); !problem.empty())
    throw SceneError(path + ": " + problem);
  tinyobj::ObjReader reader;
  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // faces keep their numbers in the file for the messages
  if (!reader.ParseFromFile(path, config)) {
    std::string e = reader.Error();
    while (!e.empty() && (e.back() == '\n' || e.back() == ' ')) e.pop_back();
    for (char& c : e)
      if (c == '\n') c = ' ';
    throw SceneError(path + ": cannot read mesh: " + (e.empty() ? "unknown error" : e));
  }
  ObjMesh mesh;
  const auto& v = reader.GetAttrib().vertices;
  const std::size_t nv = v.size() / 3;
  for (std::size_t i = 0; i < nv; ++i) {
    mesh.vertices.push_back({v[3 * i], v[3 * i + 1], v[3 * i + 2]});
    for (double x : mesh.vertices.back())
      if (!std::isfinite(x))
        throw SceneError(path + ": vertex " + std::to_string(i + 1) + " is not finite");
  }
  std::size_t face = 0;
  for (const auto& shape : reader.GetShapes()) {
    std::size_t offset = 0;
    for (unsigned corners : shape.mesh.num_face_vertices) {
      ++face;
      std::vector<std::uint32_t> ids;
      for (unsigned k = 0; k < corners; ++k) {
        const int vi = shape.mesh.indices[offset + k].vertex_index;
        if (vi < 0 || std::size_t(vi) >= nv)
          throw SceneError(path + ": face " + std::to_string(face) + " uses vertex " +
                           std::to_string(long(vi) + 1) + ", but the file has " +
                           std::to_string(nv) + " vertices");
        ids.push_back(std::uint32_t(vi));
      }
      offset += corners;
      if (corners < 3)
        throw SceneError(path + ": face " + std::to_string(face) + " has " +
                         std::to_string(corners) + " vertices; a face needs at least 3");
      for (unsigned k = 1; k + 1 < corners; ++k)
        mesh.triangles.push_back({ids[0], ids[k], ids[k + 1]});
    }
  }
  if (mesh.triangles.empty()) throw SceneError(path + ": mesh has no faces");
  // Closed and manifold: every undirected edge in exactly two triangles.
  std::unordered_map<std::uint64_t, int> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      std::uint64_t a = t[k], b = t[(k + 1) % 3];
      if (a > b) std::swap(a, b);
      ++edges[a << 32 | b];
    }
  std::size_t bad = 0;
  std::uint64_t first = 0;
  int first_count = 0;
  for (const auto& [key, count] : edges)
    if (count != 2 && bad++ == 0) {
      first = key;
      first_count = count;
    }
  if (bad)
    throw SceneError(path + ": the mesh is not a closed manifold surface: " + std::to_string(bad) +
                     " edges do not join exactly two faces (e.g. vertices " +
                     std::to_string((first >> 32) + 1) + "-" +
                     std::to_string((first & 0xffffffffu) + 1) + " joins " +
                     std::to_string(first_count) + ")");
  std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const auto& t : mesh.triangles)
    for (auto i : t)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], mesh.vertices[i][a]);
        hi[a] = std::max(hi[a], mesh.vertices[i][a]);
      }
  const double box = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
  if (!(box > 0) || !(mesh.volume() > 1e-9 * box))
    throw SceneError(path + ": the mesh encloses no volume (flat or of zero size)");
  return mesh;
}

}  // namespace apiclab
