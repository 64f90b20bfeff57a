#include "sim/geometry/obj_mesh.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string_view>

#include "sim/scene/input_file.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {
namespace {

// A token of the file, quoted for a one-line message: control bytes shown as '?', long ones cut.
std::string quoted(std::string_view token) {
  std::string s = "'";
  for (std::size_t i = 0; i < token.size() && i < 40; ++i)
    s += (static_cast<unsigned char>(token[i]) < 0x20 || token[i] == 0x7f) ? '?' : token[i];
  return s + (token.size() > 40 ? "...'" : "'");
}

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::vector<std::string_view> tokens_of(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !blank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// Signed volume ×6 of the triangles with coordinates moved to `origin` and divided by `unit`
// per axis: no overflow for huge meshes, no cancellation far from the origin.
double scaled_volume6(const ObjMesh& m, const std::array<double, 3>& origin,
                      const std::array<double, 3>& unit) {
  double v6 = 0;
  for (const auto& t : m.triangles) {
    std::array<std::array<double, 3>, 3> p;
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) p[k][a] = (m.vertices[t[k]][a] - origin[a]) / unit[a];
    const auto &a = p[0], &b = p[1], &c = p[2];
    v6 += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
          a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return v6;
}

void bounds(const ObjMesh& m, std::array<double, 3>& lo, std::array<double, 3>& hi) {
  lo = m.vertices[m.triangles[0][0]];
  hi = lo;
  for (const auto& t : m.triangles)
    for (auto i : t)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], m.vertices[i][a]);
        hi[a] = std::max(hi[a], m.vertices[i][a]);
      }
}

}  // namespace

double ObjMesh::volume() const {
  if (triangles.empty()) return 0;
  std::array<double, 3> lo, hi, mid, unit{1, 1, 1};
  bounds(*this, lo, hi);
  for (int a = 0; a < 3; ++a) {
    mid[a] = 0.5 * lo[a] + 0.5 * hi[a];
    if (hi[a] > lo[a]) unit[a] = hi[a] - lo[a];
  }
  return std::abs(scaled_volume6(*this, mid, unit)) / 6.0 * unit[0] * unit[1] * unit[2];
}

// Our own reader of the two statements a solid needs, in double with the line of each fault
// (tinyobjloader takes "nan" and "inf" as 0, reads float, where 1e300 is inf, names no line).
ObjMesh load_obj_mesh(const std::string& path) {
  if (std::string problem = input_file_problem(path, "mesh file"); !problem.empty())
    throw SceneError(path + ": " + problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot read mesh file");
  ObjMesh mesh;
  struct Ahead {  // a face index past the vertices read so far, checked at the end
    long long index;
    std::uint32_t line;
    std::size_t face;
  };
  std::vector<Ahead> ahead;
  std::vector<std::uint32_t> polygon;  // the resolved corners of one face
  std::string text;
  std::uint32_t line_no = 0;
  std::size_t faces = 0;
  auto at = [&](std::uint32_t line) { return path + ":" + std::to_string(line) + ": "; };
  while (std::getline(in, text)) {
    ++line_no;
    const auto tok = tokens_of(text);
    if (tok.empty()) continue;
    if (tok[0] == "v") {
      const std::size_t n = mesh.vertices.size() + 1;
      if (tok.size() < 4)
        throw SceneError(at(line_no) + "vertex " + std::to_string(n) + " has " +
                         std::to_string(tok.size() - 1) + " coordinates; a vertex needs x y z");
      std::array<double, 3> x{};
      for (int a = 0; a < 3; ++a) {
        std::string_view s = tok[std::size_t(a) + 1];
        if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x[std::size_t(a)]);
        const std::string what = "vertex " + std::to_string(n) + " coordinate " +
                                 std::string(1, "xyz"[a]) + " " + quoted(tok[std::size_t(a) + 1]);
        if (ec == std::errc::result_out_of_range)
          throw SceneError(at(line_no) + what + " is beyond the range of a double");
        if (ec != std::errc() || end != s.data() + s.size())
          throw SceneError(at(line_no) + what + " is not a number");
        if (!std::isfinite(x[std::size_t(a)]))
          throw SceneError(at(line_no) + what + " is not a finite number");
      }
      mesh.vertices.push_back(x);
    } else if (tok[0] == "f") {
      ++faces;
      const std::string face = "face " + std::to_string(faces);
      if (tok.size() < 4)
        throw SceneError(at(line_no) + face + " has " + std::to_string(tok.size() - 1) +
                         " vertices; a face needs at least 3");
      polygon.clear();
      for (std::size_t k = 1; k < tok.size(); ++k) {
        const std::string_view s = tok[k].substr(0, tok[k].find('/'));  // v, v/vt, v//vn, v/vt/vn
        long long i = 0;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), i);
        if (ec != std::errc() || end != s.data() + s.size())
          throw SceneError(at(line_no) + face + ": " + quoted(tok[k]) + " is not a vertex index");
        if (i == 0)
          throw SceneError(at(line_no) + face +
                           " uses vertex index 0; OBJ numbers vertices from 1 (or from -1 "
                           "backwards)");
        const long long have = static_cast<long long>(mesh.vertices.size());
        if (i < -have)
          throw SceneError(at(line_no) + face + " uses vertex " + std::to_string(i) +
                           ", but only " + std::to_string(have) + " vertices precede it");
        if (i > have) ahead.push_back({i, line_no, faces});
        polygon.push_back(std::uint32_t(i > 0 ? i - 1 : have + i));
      }
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
        mesh.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
        mesh.triangle_lines.push_back(line_no);
      }
    }
    // Other statements (vt, vn, o, g, s, usemtl, mtllib, l, p, comments) play no part in a solid.
  }
  if (in.bad()) throw SceneError(path + ": cannot read mesh file");
  const std::size_t nv = mesh.vertices.size();
  for (const Ahead& a : ahead)
    if (std::size_t(a.index) > nv)
      throw SceneError(at(a.line) + "face " + std::to_string(a.face) + " uses vertex " +
                       std::to_string(a.index) + ", but the file has " + std::to_string(nv) +
                       " vertices");
  if (mesh.triangles.empty()) throw SceneError(path + ": mesh has no faces");

  // Closed, manifold and consistently oriented: every edge u-v in exactly two triangles, one
  // running u→v and the other v→u. Sorted directed edges (less memory than a hash map).
  struct Edge {
    std::uint64_t key;  // min << 32 | max
    std::uint32_t triangle;
    bool forward;  // runs min → max
  };
  std::vector<Edge> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = mesh.triangles[t][std::size_t(k)],
                          b = mesh.triangles[t][std::size_t((k + 1) % 3)];
      edges.push_back({std::min(a, b) << 32 | std::max(a, b), t, a < b});
    }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.key < y.key; });
  std::size_t bad = 0, first_bad = 0, first_count = 0, flipped = edges.size();
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i != 2 || (edges[i].key >> 32) == (edges[i].key & 0xffffffffu)) {
      if (bad++ == 0) {
        first_bad = i;
        first_count = j - i;
      }
    } else if (edges[i].forward == edges[i + 1].forward && flipped == edges.size()) {
      flipped = i;
    }
    i = j;
  }
  auto vertex_pair = [](std::uint64_t key) {
    return std::to_string((key >> 32) + 1) + " and " + std::to_string((key & 0xffffffffu) + 1);
  };
  if (bad)
    throw SceneError(path + ": the mesh is not a closed manifold surface: " + std::to_string(bad) +
                     " edges do not join exactly two faces (e.g. the edge between vertices " +
                     vertex_pair(edges[first_bad].key) + ", line " +
                     std::to_string(mesh.triangle_lines[edges[first_bad].triangle]) + ", joins " +
                     std::to_string(first_count) + ")");
  if (flipped != edges.size()) {
    const std::uint32_t l1 = mesh.triangle_lines[edges[flipped].triangle],
                        l2 = mesh.triangle_lines[edges[flipped + 1].triangle];
    throw SceneError(path + ": the faces are not consistently oriented: the faces on lines " +
                     std::to_string(std::min(l1, l2)) + " and " + std::to_string(std::max(l1, l2)) +
                     " run their shared edge (vertices " + vertex_pair(edges[flipped].key) +
                     ") the same way; list every face's vertices in the same turning sense");
  }
  std::vector<Edge>().swap(edges);

  std::array<double, 3> lo, hi, mid, unit;
  bounds(mesh, lo, hi);
  for (int a = 0; a < 3; ++a) {
    unit[a] = hi[a] - lo[a];
    mid[a] = 0.5 * lo[a] + 0.5 * hi[a];
    if (!std::isfinite(unit[a]))
      throw SceneError(path + ": the mesh is too large: its extent on axis " +
                       std::string(1, "xyz"[a]) + " exceeds the range of a double");
    if (!(unit[a] > 0))
      throw SceneError(path + ": the mesh encloses no volume (flat: zero extent on axis " +
                       std::string(1, "xyz"[a]) + ")");
  }
  // Volume over the bounding box's, in coordinates scaled to the box.
  if (!(std::abs(scaled_volume6(mesh, mid, unit)) / 6.0 > 1e-9))
    throw SceneError(path + ": the mesh encloses no volume (flat or of zero size)");
  return mesh;
}

}  // namespace apiclab
