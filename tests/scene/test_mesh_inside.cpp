// The mesh sampler's inside test (sim/geometry/mesh_inside.hpp, MeshSolid) and the OBJ reader's
// checks (sim/geometry/obj_mesh.hpp): lattice counts of cubes and octahedra whose edges, vertices
// and faces lie on the lattice's rays and sites, against counts taken independently from the
// shapes' own inequalities; overlapping and nested components; the one-line messages of bad files;
// the time and memory of a large mesh.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "sim/geometry/mesh_inside.hpp"
#include "sim/geometry/obj_mesh.hpp"
#include "sim/geometry/sampling.hpp"
#include "sim/scene/memory_estimate.hpp"
#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define APICLAB_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define APICLAB_SANITIZED 1
#endif
#endif

namespace apiclab {
namespace {

using V3 = std::array<double, 3>;
using Face = std::vector<int>;  // 1-based, as written

// OBJ files in a folder of this process's own (ctest runs each test in a process), removed
// with it.
struct Scratch {
  std::filesystem::path dir;
  Scratch()
      : dir(std::filesystem::temp_directory_path() /
            ("apiclab_mesh_inside_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir);
  }
  ~Scratch() {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (dir / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
};

std::string obj_text(const std::vector<V3>& v, const std::vector<Face>& f) {
  std::ostringstream s;
  s.precision(17);
  for (const V3& x : v) s << "v " << x[0] << " " << x[1] << " " << x[2] << "\n";
  for (const Face& face : f) {
    s << "f";
    for (int i : face) s << " " << i;
    s << "\n";
  }
  return s.str();
}

// The box [lo, hi] as 12 outward triangles (each face split along a diagonal), vertices
// numbered from `base` + 1; `flip` reverses every face.
void add_cube(std::vector<V3>& v, std::vector<Face>& f, const V3& lo, const V3& hi,
              bool flip = false) {
  const int base = int(v.size());
  for (int k = 0; k < 8; ++k)
    v.push_back({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads)
    for (const Face& t : {Face{q[0], q[1], q[2]}, Face{q[0], q[2], q[3]}})
      f.push_back(flip ? Face{base + t[0] + 1, base + t[2] + 1, base + t[1] + 1}
                       : Face{base + t[0] + 1, base + t[1] + 1, base + t[2] + 1});
}

std::string cube_obj(const V3& lo, const V3& hi, bool flip = false) {
  std::vector<V3> v;
  std::vector<Face> f;
  add_cube(v, f, lo, hi, flip);
  return obj_text(v, f);
}

// A 3D scene in [0, 1]³ sampling `obj` on the lattice of spacing dx (ppc 1): site k at
// (k + ½) dx.
SceneDesc mesh_scene(const std::string& obj, double dx, const std::string& shape_extra = "") {
  char json[1024];
  std::snprintf(json, sizeof json, R"({"dim": 3,
    "domain": {"min": [0, 0, 0], "max": [1, 1, 1], "dx": %.17g},
    "materials": [{"E": 1000, "nu": 0.3, "rho": 1}],
    "objects": [{"shape": {"type": "mesh", "file": "%s"%s}, "material": 0,
                 "sampling": {"type": "ppc", "ppc": 1}}]})",
                dx, obj.c_str(), shape_extra.c_str());
  return parse_scene_text(json, "mesh-inside.json");
}

std::size_t sampled(const std::string& obj, double dx) {
  return sample_object(mesh_scene(obj, dx), 0).positions.size();
}

// The lattice sites of [0, 1]³ (as the sampler places them) for which `in` holds.
std::size_t lattice_count(double dx, const std::function<bool(const V3&)>& in) {
  const long n = std::lround(1 / dx);
  std::size_t count = 0;
  for (long k = 0; k < n; ++k)
    for (long j = 0; j < n; ++j)
      for (long i = 0; i < n; ++i)
        if (in({(i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dx})) ++count;
  return count;
}

bool strictly_in_box(const V3& x, const V3& lo, const V3& hi) {
  for (int a = 0; a < 3; ++a)
    if (!(x[a] > lo[a] && x[a] < hi[a])) return false;
  return true;
}
bool in_closed_box(const V3& x, const V3& lo, const V3& hi) {
  for (int a = 0; a < 3; ++a)
    if (!(x[a] >= lo[a] && x[a] <= hi[a])) return false;
  return true;
}

// The report's cube: [0.2, 0.8]³ on the 0.05 lattice. Its face diagonals run through the
// sites' columns (x = y), which a ray-parity count in floating point miscounted (1,608 sites).
TEST(MeshInside, CubeOnRoundCoordinatesFillsEveryLatticeSiteInside) {
  Scratch s;
  const V3 lo{0.2, 0.2, 0.2}, hi{0.8, 0.8, 0.8};
  const std::size_t expected =
      lattice_count(0.05, [&](const V3& x) { return strictly_in_box(x, lo, hi); });
  EXPECT_EQ(expected, 1728u);  // 12 sites a side: 0.225 ... 0.775
  const std::string cube = s.write("cube.obj", cube_obj(lo, hi)),
                    flipped = s.write("flipped.obj", cube_obj(lo, hi, true));
  EXPECT_EQ(sampled(cube, 0.05), expected);
  EXPECT_EQ(sampled(flipped, 0.05), expected);
  // The volumes the memory estimate counts particles by.
  ShapeDesc shape;
  shape.type = ShapeType::mesh;
  shape.scale = 0.5;
  for (const std::string& path : {cube, flipped}) {
    EXPECT_NEAR(load_obj_mesh(path).volume(), 0.216, 1e-15) << path;
    EXPECT_NEAR(MeshSolid(path, shape).volume(), 0.216 / 8, 1e-15) << path;
  }
}

// A cube whose corners are lattice sites: its faces hold sites (on the surface: inside, as the
// analytic box's closed test), its edges and corners lie on the sites' rows and columns.
TEST(MeshInside, CubeOnTheLatticeCountsItsSurfaceSitesAsInside) {
  Scratch s;
  const double dx = 0.125;  // sites at 0.0625 + 0.125 k, exact
  const V3 lo{0.1875, 0.1875, 0.3125}, hi{0.8125, 0.6875, 0.8125};  // sites 1..6, 1..5, 2..6
  const std::size_t expected =
      lattice_count(dx, [&](const V3& x) { return in_closed_box(x, lo, hi); });
  EXPECT_EQ(expected, 6u * 5u * 5u);
  EXPECT_EQ(sampled(s.write("aligned.obj", cube_obj(lo, hi)), dx), expected);
  EXPECT_EQ(sampled(s.write("aligned-flipped.obj", cube_obj(lo, hi, true)), dx), expected);
}

// An octahedron |x − c|₁ ≤ r with its six vertices on lattice sites: rays along the lattice
// axes from the sites below a vertex meet it, and its faces hold sites.
TEST(MeshInside, OctahedronWithVerticesOnTheLattice) {
  Scratch s;
  const double dx = 0.0625;  // sites at 0.03125 + 0.0625 k, exact
  const V3 c{0.53125, 0.46875, 0.53125};
  const double r = 0.25;  // four spacings
  const std::vector<V3> v{{c[0] + r, c[1], c[2]}, {c[0] - r, c[1], c[2]}, {c[0], c[1] + r, c[2]},
                          {c[0], c[1] - r, c[2]}, {c[0], c[1], c[2] + r}, {c[0], c[1], c[2] - r}};
  // Outward: (+x, +y, +z) = (1, 3, 5) counterclockwise seen from outside, and so on.
  std::vector<Face> f;
  for (int sx : {0, 1})
    for (int sy : {0, 1})
      for (int sz : {0, 1}) {
        const int a = 1 + sx, b = 3 + sy, cc = 5 + sz;
        const bool odd = (sx + sy + sz) % 2 == 1;
        f.push_back(odd ? Face{a, cc, b} : Face{a, b, cc});
      }
  const std::string path = s.write("octahedron.obj", obj_text(v, f));
  EXPECT_NEAR(load_obj_mesh(path).volume(), 4.0 / 3.0 * r * r * r, 1e-15);
  const std::size_t expected = lattice_count(dx, [&](const V3& x) {
    return std::abs(x[0] - c[0]) + std::abs(x[1] - c[1]) + std::abs(x[2] - c[2]) <= r;
  });
  EXPECT_EQ(expected, 129u);  // the octahedral number for 4 spacings: (2n+1)(2n²+2n+3)/3
  EXPECT_EQ(sampled(path, dx), expected);
}

// A segment through a vertex: the apex sits on the first segment cast from the origin, which
// must then be turned (not counted twice or missed) and still find the origin inside.
TEST(MeshInside, SegmentThroughAVertexIsTurned) {
  const MeshWinding::Vec3d d = MeshWinding::direction(0);
  ASSERT_EQ(d[2], 1.0);
  // z from −1 to 1: the segment reaches 4 (d0, d1, 1) and meets the apex a quarter of the way.
  const std::vector<MeshWinding::Vec3d> v{{1, 0, 0},  {-1, 0, 0},        {0, 1, 0},
                                          {0, -1, 0}, {d[0], d[1], 1.0}, {0, 0, -1}};
  std::vector<std::array<std::uint32_t, 3>> t;
  for (std::uint32_t sx : {0u, 1u})
    for (std::uint32_t sy : {0u, 1u})
      for (std::uint32_t sz : {0u, 1u}) {
        const std::uint32_t a = sx, b = 2 + sy, c = 4 + sz;
        t.push_back((sx + sy + sz) % 2 ? std::array<std::uint32_t, 3>{a, c, b}
                                       : std::array<std::uint32_t, 3>{a, b, c});
      }
  const MeshWinding w(v, t, {-1, -1, -1}, {1, 1, 1});
  const MeshWinding::Result r = w.winding({0, 0, 0});
  EXPECT_FALSE(r.on_surface);
  EXPECT_EQ(r.winding, 1);
  EXPECT_GE(r.segments, 2);                          // the first one grazed the apex
  EXPECT_TRUE(w.winding({1, 0, 0}).on_surface);      // a vertex
  EXPECT_TRUE(w.winding({0.5, 0.5, 0}).on_surface);  // an edge
  EXPECT_EQ(w.winding({0.9, 0.9, 0}).winding, 0);    // in the box, outside the solid
}

// A lattice's rows walked site to site (MeshSolid::inside_run, the sampler's way) give the
// answers of one query per site, on and off the surface, through edges and vertices.
TEST(MeshInside, WalkingARowAgreesWithQueryingEachSite) {
  Scratch s;
  std::vector<V3> v;
  std::vector<Face> f;
  add_cube(v, f, {0.125, 0.125, 0.125}, {0.625, 0.625, 0.625});
  add_cube(v, f, {0.375, 0.25, 0.375}, {0.875, 0.75, 0.875});
  add_cube(v, f, {0.25, 0.25, 0.25}, {0.5, 0.5, 0.5}, true);
  ShapeDesc shape;
  shape.type = ShapeType::mesh;
  const MeshSolid mesh(s.write("three.obj", obj_text(v, f)), shape);
  std::size_t sites = 0, inside = 0;
  for (double h : {0.0625, 0.03125, 0.05})  // sites on the faces and edges, and off them
    for (double z = 0; z <= 1; z += h)
      for (double y = 0; y <= 1; y += h) {
        std::vector<Vec3d> row;
        for (double x = 0; x <= 1; x += h) row.push_back({x, y, z});
        std::vector<char> in;
        mesh.inside_run(row, in);
        ASSERT_EQ(in.size(), row.size());
        for (std::size_t i = 0; i < row.size(); ++i) {
          ASSERT_EQ(bool(in[i]), mesh.inside(row[i])) << row[i][0] << " " << y << " " << z;
          inside += in[i];
        }
        sites += row.size();
      }
  EXPECT_GT(inside, sites / 10);
}

// Two overlapping cubes in one file fill their union (winding number 2 where they overlap);
// a cube inside another facing in cuts a cavity; facing out, it adds nothing.
TEST(MeshInside, OverlappingComponentsFillTheirUnionAndInwardOnesCutCavities) {
  Scratch s;
  const double dx = 0.05;
  const V3 alo{0.2, 0.2, 0.2}, ahi{0.6, 0.6, 0.6}, blo{0.4, 0.35, 0.3}, bhi{0.8, 0.75, 0.7};
  std::vector<V3> v;
  std::vector<Face> f;
  add_cube(v, f, alo, ahi);
  add_cube(v, f, blo, bhi);
  const std::size_t a =
      lattice_count(dx, [&](const V3& x) { return strictly_in_box(x, alo, ahi); });
  const std::size_t both = lattice_count(dx, [&](const V3& x) {
    return strictly_in_box(x, alo, ahi) && strictly_in_box(x, blo, bhi);
  });
  const std::size_t either = lattice_count(dx, [&](const V3& x) {
    return strictly_in_box(x, alo, ahi) || strictly_in_box(x, blo, bhi);
  });
  ASSERT_GT(both, 0u);
  EXPECT_EQ(sampled(s.write("union.obj", obj_text(v, f)), dx), either);

  const V3 clo{0.3, 0.3, 0.3}, chi{0.5, 0.5, 0.5};
  const std::size_t cavity =
      lattice_count(dx, [&](const V3& x) { return strictly_in_box(x, clo, chi); });
  std::vector<V3> v2;
  std::vector<Face> f2;
  add_cube(v2, f2, alo, ahi);
  add_cube(v2, f2, clo, chi, true);
  EXPECT_EQ(sampled(s.write("cavity.obj", obj_text(v2, f2)), dx), a - cavity);
  std::vector<V3> v3;
  std::vector<Face> f3;
  add_cube(v3, f3, alo, ahi);
  add_cube(v3, f3, clo, chi);
  EXPECT_EQ(sampled(s.write("nested.obj", obj_text(v3, f3)), dx), a);
}

// The message of sampling `obj` in a scene whose domain holds the unit cube.
std::string mesh_error(const Scratch& s, const std::string& name, const std::string& obj) {
  const std::string path = s.write(name, obj);
  try {
    make_simulation(mesh_scene(path, 0.1));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

void expect_message(const std::string& msg, const std::vector<std::string>& needles) {
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  for (const std::string& n : needles)
    EXPECT_NE(msg.find(n), std::string::npos) << n << " in " << msg;
}

TEST(MeshInside, BadFilesGetTheirOwnOneLineMessages) {
  Scratch s;
  const std::string cube = cube_obj({0.2, 0.2, 0.2}, {0.8, 0.8, 0.8});
  auto with_vertex = [&](const std::string& line) {  // the cube, vertex 2 replaced on line 2
    std::string t = cube;
    const std::size_t a = t.find('\n') + 1, b = t.find('\n', a);
    return t.replace(a, b - a, line);
  };
  expect_message(mesh_error(s, "nan.obj", with_vertex("v nan 0.2 0.2")),
                 {"nan.obj:2:", "vertex 2", "'nan'", "not a finite number"});
  expect_message(mesh_error(s, "inf.obj", with_vertex("v 0.8 -inf 0.2")),
                 {"inf.obj:2:", "vertex 2", "coordinate y", "'-inf'", "not a finite number"});
  expect_message(mesh_error(s, "word.obj", with_vertex("v 0.8 0.2 zero")),
                 {"word.obj:2:", "'zero'", "not a number"});
  expect_message(mesh_error(s, "e400.obj", with_vertex("v 1e400 0.2 0.2")),
                 {"e400.obj:2:", "'1e400'", "beyond the range of a double"});
  expect_message(mesh_error(s, "short.obj", with_vertex("v 0.8 0.2")),
                 {"short.obj:2:", "vertex 2 has 2 coordinates"});
  // 1e300 is a finite number: the mesh then reaches far outside the domain.
  expect_message(
      mesh_error(s, "huge.obj", with_vertex("v 1e300 0.2 0.2")),
      {"mesh-inside.json", "'objects.0.shape'", "outside the domain on axis x", "1e+300"});
  EXPECT_EQ(mesh_error(s, "huge.obj", with_vertex("v 1e300 0.2 0.2")).find("finite"),
            std::string::npos);
  // A scale that overflows a double once applied.
  {
    const std::string path = s.write("scaled.obj", cube_obj({2, 2, 2}, {3, 3, 3}));
    try {
      sample_object(mesh_scene(path, 0.1, R"(, "scale": 1e308)"), 0);
      ADD_FAILURE() << "scale 1e308 accepted";
    } catch (const SceneError& e) {
      expect_message(e.what(), {"'objects.0.shape'", "too large", "1e307"});
    }
  }
  // Face indices: 0, past the end, relative past the start, not a number, too few.
  const std::string v8 = cube.substr(0, cube.find("f "));
  expect_message(mesh_error(s, "zero.obj", v8 + "f 0 5 8\n"),
                 {"zero.obj:9:", "face 1", "vertex index 0", "from 1"});
  expect_message(mesh_error(s, "past.obj", v8 + "f 1 2 3\nf 1 2 9\n"),
                 {"past.obj:10:", "face 2", "vertex 9", "the file has 8 vertices"});
  expect_message(mesh_error(s, "back.obj", v8 + "f -1 -2 -9\n"),
                 {"back.obj:9:", "face 1", "vertex -9", "only 8 vertices precede it"});
  expect_message(mesh_error(s, "nonint.obj", v8 + "f 1 2 x/1\n"),
                 {"nonint.obj:9:", "'x/1'", "not a vertex index"});
  expect_message(mesh_error(s, "two.obj", v8 + "f 1 2\n"), {"two.obj:9:", "face 1 has 2 vertices"});
  // One face turned the other way: its edges run as its neighbours' do.
  {
    std::vector<V3> v;
    std::vector<Face> f;
    add_cube(v, f, {0.2, 0.2, 0.2}, {0.8, 0.8, 0.8});
    std::swap(f[4][1], f[4][2]);
    expect_message(mesh_error(s, "turned.obj", obj_text(v, f)),
                   {"turned.obj", "not consistently oriented", "13"});
  }
  // Relative indices and v/vt/vn corners read as their absolute twins.
  {
    std::vector<V3> v;
    std::vector<Face> f;
    add_cube(v, f, {0.2, 0.2, 0.2}, {0.8, 0.8, 0.8});
    std::string rel = obj_text(v, {});
    for (const Face& face : f)
      rel += "f " + std::to_string(face[0] - 9) + "/1/1 " + std::to_string(face[1]) + "//2 " +
             std::to_string(face[2] - 9) + "/3\n";
    rel = "# comment\no cube\nvt 0 0\n" + rel + "s off\n";
    EXPECT_EQ(sampled(s.write("relative.obj", rel), 0.05), 1728u);
  }
}

// A torus of n × n vertices (2 n² outward triangles) about the domain's centre.
std::string torus_obj(int n, double R, double r) {
  std::string out;
  out.reserve(std::size_t(n) * n * 90);
  char line[128];
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double u = 2 * M_PI * i / n, w = 2 * M_PI * j / n;
      std::snprintf(line, sizeof line, "v %.9f %.9f %.9f\n",
                    0.5 + (R + r * std::cos(w)) * std::cos(u),
                    0.5 + (R + r * std::cos(w)) * std::sin(u), 0.5 + r * std::sin(w));
      out += line;
    }
  auto id = [n](int i, int j) { return (i % n) * n + (j % n) + 1; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      std::snprintf(line, sizeof line, "f %d %d %d\nf %d %d %d\n", id(i, j), id(i + 1, j),
                    id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1));
      out += line;
    }
  return out;
}

// Peak resident memory since the last reset (Linux: VmHWM, reset by writing 5 to clear_refs);
// −1 where the reset is not allowed.
double reset_peak() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.close();
  return clear.fail() ? -1 : 0;
}
double peak_bytes() {
  std::ifstream in("/proc/self/status");
  std::string name;
  double kb = 0;
  while (in >> name) {
    if (name == "VmHWM:") {
      in >> kb;
      return kb * 1024;
    }
    std::getline(in, name);
  }
  return -1;
}

struct Measured {
  std::size_t particles;
  double seconds, peak_mb;
};
Measured sample_torus(const Scratch& s, int n, double dx) {
  const std::string path = s.write("torus.obj", torus_obj(n, 0.3, 0.1));
  const SceneDesc scene = mesh_scene(path, dx);
  const bool can_reset = reset_peak() == 0;
  const double before = peak_bytes();
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t particles = sample_object(scene, 0).positions.size();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double peak = can_reset ? (peak_bytes() - before) / 1e6 : -1;
  std::printf("torus %d x %d vertices, %zu particles: %.2f s, peak +%.0f MB\n", n, n, particles,
              seconds, peak);
  // The sites inside the smooth torus, give or take those closer to its surface than the
  // facets stray (a chord's sagitta, (R + r)(1 − cos π/n), twice over).
  const double band = 2 * 0.4 * (1 - std::cos(M_PI / n));
  std::size_t smooth = 0, near = 0;
  lattice_count(dx, [&](const V3& x) {
    const double rho = std::hypot(x[0] - 0.5, x[1] - 0.5) - 0.3, d = std::hypot(rho, x[2] - 0.5);
    smooth += d <= 0.1;
    near += std::abs(d - 0.1) <= band;
    return false;
  });
  EXPECT_LE(std::max(particles, smooth) - std::min(particles, smooth), near)
      << particles << " particles, " << smooth << " sites in the smooth torus";
  return {particles, seconds, peak};
}

// 40,000 vertices, 80,000 triangles, about 60,000 particles: the default tier's guard.
TEST(MeshInside, LargeMeshSamplesQuickly) {
  Scratch s;
  const Measured m = sample_torus(s, 200, 0.01);
#ifndef APICLAB_SANITIZED
  EXPECT_LT(m.seconds, 3.0);
  if (m.peak_mb >= 0) {
    EXPECT_LT(m.peak_mb, 100);
  }
#endif
}

// 1,000,000 vertices, 2,000,000 triangles, about 470,000 particles of 1,020,000 sites in the
// mesh's box (label slow).
TEST(MeshInsideSlow, MillionVertexMeshSamplesInSecondsAndUnder500MB) {
#ifdef APICLAB_SANITIZED
  GTEST_SKIP() << "timing under a sanitizer";
#endif
  Scratch s;
  const Measured m = sample_torus(s, 1000, 0.005);
  EXPECT_LT(m.seconds, 20.0);
  if (m.peak_mb >= 0) {
    EXPECT_LT(m.peak_mb, 500);
  }
}

}  // namespace
}  // namespace apiclab
