// --dump formats read back: VTK PolyData (header, offsets and sizes checked by a
// reader of our own; every array bit for bit), binary PLY bit for bit, OBJ and CSV to their
// printed precision (max_digits10 round-trips exactly), series.pvd lists every frame's time.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <regex>
#include <sstream>

#include "app/particle_export.hpp"
#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"
#include "sim/snapshot.hpp"

#ifdef APICLAB_HAVE_ZLIB
#include <zlib.h>
#endif

namespace apiclab {
namespace {

const std::string kDir = std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/";

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

template <class V>
V get(const std::string& bytes, std::size_t at) {
  V v;
  std::memcpy(&v, bytes.data() + at, sizeof(V));
  return v;
}

// A table after a few steps, so that F, C and v are not trivial.
ParticleTable table_of(const std::string& scene_name, int steps) {
  auto sim = make_simulation(load_scene(kDir + scene_name + ".json"));
  for (int k = 0; k < steps; ++k) sim->step(1e9);
  return sim->transfers()->particle_table();
}

// Named by process: ctest runs the parameterised cases (and other checkouts their own) at the
// same time, and a shared name let one case read the file another was writing.
std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("apiclab-export-" + std::to_string(::getpid()) + "-" + name))
      .string();
}

struct VtkArray {
  std::string type, name;
  int components = 0;
  std::size_t offset = 0;
};

// Our reader: the DataArray headers, then each array's UInt64 byte count in the appended block,
// checked against the point count and type size.
std::vector<VtkArray> read_vtk_arrays(const std::string& file, std::size_t& appended,
                                      std::size_t& points) {
  const std::size_t mark = file.find("<AppendedData encoding=\"raw\">");
  EXPECT_NE(mark, std::string::npos);
  appended = file.find('_', mark) + 1;
  std::smatch m;
  std::string head = file.substr(0, mark);
  EXPECT_TRUE(std::regex_search(head, m, std::regex("NumberOfPoints=\"(\\d+)\"")));
  points = std::stoul(m[1]);
  std::vector<VtkArray> out;
  const std::regex array(
      "<DataArray type=\"(\\w+)\"(?: Name=\"(\\w+)\")? NumberOfComponents=\"(\\d+)\" "
      "format=\"appended\" offset=\"(\\d+)\"/>");
  for (auto it = std::sregex_iterator(head.begin(), head.end(), array);
       it != std::sregex_iterator(); ++it)
    out.push_back({(*it)[1], (*it)[2], std::stoi((*it)[3]), std::stoul((*it)[4])});
  return out;
}

// One appended array's bytes, decoded: raw (UInt64 size + bytes) or VTK's zlib layout (UInt64
// block count, block size, partial last block size, compressed sizes, blocks). `end` is where
// the array's stored bytes end.
std::string array_bytes(const std::string& file, std::size_t at, bool zlib, std::size_t& end) {
  if (!zlib) {
    const std::size_t bytes = get<std::uint64_t>(file, at);
    end = at + 8 + bytes;
    return file.substr(at + 8, bytes);
  }
  std::string out;
#ifdef APICLAB_HAVE_ZLIB
  const std::size_t blocks = get<std::uint64_t>(file, at);
  const std::size_t block = get<std::uint64_t>(file, at + 8);
  const std::size_t last = get<std::uint64_t>(file, at + 16);
  std::size_t z = at + 24 + 8 * blocks;
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t packed = get<std::uint64_t>(file, at + 24 + 8 * b);
    const std::size_t want = (b + 1 == blocks && last) ? last : block;
    std::string chunk(want, '\0');
    uLongf got = uLongf(want);
    EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(chunk.data()), &got,
                         reinterpret_cast<const Bytef*>(file.data() + z), uLong(packed)),
              Z_OK);
    EXPECT_EQ(got, want);
    out += chunk;
    z += packed;
  }
  end = z;
#else
  ADD_FAILURE() << "zlib layout without zlib";
#endif
  return out;
}

class VtkEncodings : public ::testing::TestWithParam<bool> {};

TEST_P(VtkEncodings, RoundTripsEveryColumn) {
  const bool zlib = GetParam();
  if (zlib && !vtk_zlib_available()) GTEST_SKIP() << "built without zlib";
  for (const char* scene : {"rotating-disk", "two-cubes"}) {
    SCOPED_TRACE(scene);
    const ParticleTable t = table_of(scene, 3);
    ExtraScalars extra;
    std::vector<float> speed(t.count);
    for (std::size_t q = 0; q < t.count; ++q) speed[q] = float(q) * 0.5f;
    extra.fields.emplace_back("speed", speed);
    const std::string path = temp_path(std::string(scene) + ".vtp");
    write_vtp(path, t, extra, zlib);
    const std::string file = read_all(path);
    EXPECT_EQ(file.find("compressor=\"vtkZLibDataCompressor\"") != std::string::npos, zlib);
    std::size_t base = 0, n = 0;
    const std::vector<VtkArray> arrays = read_vtk_arrays(file, base, n);
    ASSERT_EQ(n, t.count);
    ASSERT_EQ(arrays.size(),
              t.columns.size() - 1 + 1 + 1 + 2);  // − position, + speed, points, verts
    std::size_t end = 0;
    for (const VtkArray& a : arrays) {
      const std::size_t size = a.type == "Float64" ? 8 : 4;
      std::size_t stored_end = 0;
      const std::string bytes = array_bytes(file, base + a.offset, zlib, stored_end);
      ASSERT_EQ(bytes.size(), n * std::size_t(a.components) * size) << a.name;
      end = std::max(end, stored_end);
      auto value = [&](std::size_t i) {
        if (a.type == "Float64") return get<double>(bytes, 8 * i);
        if (a.type == "Int32") return double(get<std::int32_t>(bytes, 4 * i));
        return double(get<float>(bytes, 4 * i));
      };
      if (a.name.empty()) {  // points: Float64, 2D padded with z = 0
        const ParticleColumn* x = t.find("position");
        for (std::size_t q = 0; q < n; ++q)
          for (int k = 0; k < 3; ++k)
            ASSERT_EQ(value(3 * q + std::size_t(k)),
                      k < t.dim ? x->values[q * std::size_t(t.dim) + std::size_t(k)] : 0.0);
      } else if (a.name == "connectivity" || a.name == "offsets") {
        for (std::size_t q = 0; q < n; ++q)
          ASSERT_EQ(value(q), double(q + (a.name == "offsets" ? 1 : 0)));
      } else if (a.name == "speed") {
        for (std::size_t q = 0; q < n; ++q) ASSERT_EQ(value(q), double(speed[q]));
      } else {
        const ParticleColumn* c = t.find(a.name);
        ASSERT_NE(c, nullptr) << a.name;
        for (std::size_t q = 0; q < n; ++q)
          for (int k = 0; k < a.components; ++k) {
            const double want = k < c->components()
                                    ? c->values[q * std::size_t(c->components()) + std::size_t(k)]
                                    : 0.0;
            // Float32 fields hold the value rounded to float: bit for bit that.
            ASSERT_EQ(value(q * std::size_t(a.components) + std::size_t(k)),
                      c->integer ? want : double(float(want)))
                << a.name << " particle " << q;
          }
      }
    }
    EXPECT_EQ(file.substr(end, 2), "\n ");  // the appended data ends where the arrays say
    std::filesystem::remove(path);
  }
}

INSTANTIATE_TEST_SUITE_P(ParticleExport, VtkEncodings, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Zlib" : "Raw"; });

// VTK's layout for an array of several blocks with a partial last one, and for an empty one.
TEST(ParticleExport, ZlibBlocksFollowVtksLayout) {
  if (!vtk_zlib_available()) GTEST_SKIP() << "built without zlib";
  std::string raw;
  for (std::size_t i = 0; i < vtk_zlib_block_size * 2 + 100; ++i) raw += char(i * 7 % 251);
  std::string data;
  append_vtk_array(data, raw, true);
  EXPECT_EQ(get<std::uint64_t>(data, 0), 3u);
  EXPECT_EQ(get<std::uint64_t>(data, 8), vtk_zlib_block_size);
  EXPECT_EQ(get<std::uint64_t>(data, 16), 100u);
  std::size_t end = 0;
  EXPECT_TRUE(array_bytes(data, 0, true, end) == raw);  // (EXPECT_EQ would print 128 kB)
  EXPECT_EQ(end, data.size());
  std::string full(vtk_zlib_block_size, 'x'), packed;
  append_vtk_array(packed, full, true);  // a full last block: partial size 0
  EXPECT_EQ(get<std::uint64_t>(packed, 0), 1u);
  EXPECT_EQ(get<std::uint64_t>(packed, 16), 0u);
  EXPECT_TRUE(array_bytes(packed, 0, true, end) == full);
  std::string empty;
  append_vtk_array(empty, "", true);
  EXPECT_EQ(get<std::uint64_t>(empty, 0), 0u);
  EXPECT_EQ(array_bytes(empty, 0, true, end), "");
}

// A 3D run's VTK frame is at most a quarter of the bytes of its CSV frame (zlib; raw
// VTK is 140 bytes per particle, the CSV 141 at rest to about 600 fully deformed).
TEST(ParticleExport, VtkFrameIsAtMostAQuarterOfTheCsv) {
  if (!vtk_zlib_available()) GTEST_SKIP() << "built without zlib: raw VTK is 140 B/particle";
  const ParticleTable t = table_of("two-cubes", 3);
  const std::string vtp = temp_path("quarter.vtp"), csv = temp_path("quarter.csv");
  write_vtp(vtp, t, {}, true);
  {
    std::ofstream out(csv);
    write_particles_csv(out, t);
  }
  const double ratio =
      double(std::filesystem::file_size(vtp)) / double(std::filesystem::file_size(csv));
  RecordProperty("vtk_over_csv", std::to_string(ratio));
  EXPECT_LE(ratio, 0.25) << std::filesystem::file_size(vtp) << " against "
                         << std::filesystem::file_size(csv) << " bytes";
  std::filesystem::remove(vtp);
  std::filesystem::remove(csv);
}

TEST(ParticleExport, PlyAndObjRoundTrip) {
  const ParticleTable t = table_of("two-cubes", 2);
  const std::string ply = temp_path("t.ply"), obj = temp_path("t.obj");
  write_ply(ply, t);
  write_obj(obj, t);
  const std::string file = read_all(ply);
  const std::size_t body = file.find("end_header\n") + 11;
  ASSERT_NE(file.find("element vertex " + std::to_string(t.count) + "\n"), std::string::npos);
  ASSERT_EQ(file.size() - body, t.count * 28);
  const ParticleColumn *x = t.find("position"), *v = t.find("velocity"), *o = t.find("object");
  for (std::size_t q = 0; q < t.count; ++q) {
    const std::size_t at = body + 28 * q;
    for (int a = 0; a < 3; ++a) {
      ASSERT_EQ(get<float>(file, at + 4 * std::size_t(a)),
                float(x->values[3 * q + std::size_t(a)]));
      ASSERT_EQ(get<float>(file, at + 12 + 4 * std::size_t(a)),
                float(v->values[3 * q + std::size_t(a)]));
    }
    ASSERT_EQ(get<std::int32_t>(file, at + 24), std::int32_t(o->values[q]));
  }
  std::ifstream in(obj);
  std::string line;
  std::getline(in, line);  // comment
  for (std::size_t q = 0; q < t.count; ++q) {
    char tag;
    double p[3];
    ASSERT_TRUE(in >> tag >> p[0] >> p[1] >> p[2]);
    ASSERT_EQ(tag, 'v');
    for (int a = 0; a < 3; ++a) ASSERT_EQ(p[a], x->values[3 * q + std::size_t(a)]);  // max_digits10
  }
  std::filesystem::remove(ply);
  std::filesystem::remove(obj);
}

TEST(ParticleExport, CsvKeepsTheContractAndRoundTrips) {
  const ParticleTable t = table_of("rotating-disk", 3);
  std::ostringstream out;
  write_particles_csv(out, t);
  std::istringstream in(out.str());
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "id,object,x,y,vx,vy,mass,volume0,F00,F01,F10,F11,C00,C01,C10,C11");
  for (std::size_t q = 0; q < t.count; ++q) {
    std::string row;
    ASSERT_TRUE(std::getline(in, row));
    std::istringstream cells(row);
    std::string cell;
    for (const ParticleColumn& c : t.columns)
      for (int k = 0; k < c.components(); ++k) {
        ASSERT_TRUE(std::getline(cells, cell, ','));
        ASSERT_EQ(std::stod(cell), c.values[q * std::size_t(c.components()) + std::size_t(k)]);
      }
  }
}

TEST(ParticleExport, PvdListsEveryFrameWithItsTime) {
  const std::string dir = temp_path("pvd");
  std::filesystem::create_directories(dir);
  PvdSeries series(dir);
  const double times[] = {0.0, 1.0 / 24, 0.1 + 0.2};
  for (int f = 0; f < 3; ++f) series.add(times[f], "frame_000" + std::to_string(f) + ".vtp");
  const std::string pvd = read_all(dir + "/series.pvd");
  const std::regex entry("<DataSet timestep=\"([^\"]+)\" part=\"0\" file=\"([^\"]+)\"/>");
  int k = 0;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), entry); it != std::sregex_iterator();
       ++it, ++k) {
    ASSERT_LT(k, 3);
    EXPECT_EQ(std::stod((*it)[1]), times[k]);
    EXPECT_EQ((*it)[2], "frame_000" + std::to_string(k) + ".vtp");
  }
  EXPECT_EQ(k, 3);
  std::filesystem::remove_all(dir);
}

// An EoL object grid riding its rotated frame: origin, spacing and Direction in the header,
// each field bit for bit (NaN for empty nodes stays NaN).
TEST(ParticleExport, GridLayerAsImageData) {
  auto sim = make_simulation(load_scene(kDir + "eol-spin.json"));
  for (int k = 0; k < 20; ++k) sim->step(1e9);
  const auto snap = sim->snapshot();
  ASSERT_FALSE(snap->grids.empty());
  const GridLayer& g = snap->grids[0];
  const std::string path = temp_path("grid.vti");
  write_vti(path, g);
  const std::string file = read_all(path);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(file, m, std::regex("WholeExtent=\"0 (\\d+) 0 (\\d+) 0 (\\d+)\"")));
  for (int a = 0; a < 3; ++a)
    EXPECT_EQ(std::stoi(m[std::size_t(a) + 1]), g.nodes[std::size_t(a)] - 1);
  ASSERT_TRUE(std::regex_search(
      file, m, std::regex("Origin=\"([^\"]+)\" Spacing=\"([^\"]+)\" Direction=\"([^\"]+)\"")));
  std::istringstream origin(m[1].str()), spacing(m[2].str()), direction(m[3].str());
  for (int a = 0; a < 3; ++a) {
    double o, h;
    origin >> o;
    spacing >> h;
    EXPECT_EQ(o, g.translation[a]);
    EXPECT_EQ(h, g.dx);
  }
  for (int k = 0; k < 9; ++k) {
    double r;
    direction >> r;
    EXPECT_EQ(r, g.rotation[std::size_t(k)]);
  }
  EXPECT_NE(g.rotation[1], 0.0);  // the frame has turned: Direction is not the identity
  const std::size_t base = file.find('_', file.find("<AppendedData")) + 1;
  const std::regex array(
      "Name=\"(\\w+)\" NumberOfComponents=\"1\" format=\"appended\" offset=\"(\\d+)\"");
  std::size_t k = 0;
  const std::string head = file.substr(0, base);
  for (auto it = std::sregex_iterator(head.begin(), head.end(), array);
       it != std::sregex_iterator(); ++it, ++k) {
    ASSERT_LT(k, g.fields.size());
    EXPECT_EQ((*it)[1], g.fields[k].name);
    const std::size_t at = base + std::stoul((*it)[2]);
    ASSERT_EQ(get<std::uint64_t>(file, at), g.node_count() * 4);
    for (std::size_t i = 0; i < g.node_count(); ++i) {
      const float want = g.fields[k].values[i], got = get<float>(file, at + 8 + 4 * i);
      ASSERT_TRUE(std::memcmp(&want, &got, 4) == 0) << g.fields[k].name << " node " << i;
    }
  }
  EXPECT_EQ(k, g.fields.size());
  std::filesystem::remove(path);
}

// The EoL object surfaces (Fan et al. 2013 Sec 3.8) through ParticleDump, read back: the .vtp's
// points, velocity and cells bit for bit against the snapshot's SurfaceLayer (in both encodings),
// the OBJ and PLY to the same vertices and elements, a closed curve (2D: every vertex in two
// segments) or a closed mesh (3D: every edge in exactly two triangles, once each way), and
// series.pvd listing each frame's surface. Broken on purpose while writing it: offsets of
// (c + 1) * 3 in 2D, 0-based OBJ indices and a missing pvd entry each failed it.
struct SurfaceFiles {
  std::vector<float> points, velocity;  // 3 per vertex
  std::vector<std::uint32_t> cells;     // dim per element
};

SurfaceFiles read_surface_vtp(const std::string& path, bool zlib, int dim) {
  const std::string file = read_all(path);
  std::size_t appended = 0, points = 0;
  const std::vector<VtkArray> arrays = read_vtk_arrays(file, appended, points);
  SurfaceFiles out;
  std::vector<std::int32_t> offsets;
  for (const VtkArray& a : arrays) {
    std::size_t end = 0;
    const std::string bytes = array_bytes(file, appended + a.offset, zlib, end);
    if (a.type == "Float32") {
      EXPECT_EQ(bytes.size(), points * std::size_t(a.components) * 4) << a.name;
      std::vector<float>& to = a.name.empty() ? out.points : out.velocity;
      if (a.name == "speed") continue;
      for (std::size_t k = 0; k < bytes.size(); k += 4) to.push_back(get<float>(bytes, k));
    } else {
      EXPECT_EQ(a.type, "Int32");
      std::vector<std::int32_t> v;
      for (std::size_t k = 0; k < bytes.size(); k += 4) v.push_back(get<std::int32_t>(bytes, k));
      if (a.name == "connectivity")
        out.cells.assign(v.begin(), v.end());
      else
        offsets = v;
    }
  }
  EXPECT_EQ(out.points.size(), 3 * points);
  std::smatch m;
  const std::string kind = dim == 2 ? "NumberOfLines" : "NumberOfPolys";
  EXPECT_TRUE(std::regex_search(file, m, std::regex(kind + "=\"(\\d+)\"")));
  EXPECT_EQ(std::stoul(m[1]), offsets.size());
  for (std::size_t c = 0; c < offsets.size(); ++c)
    EXPECT_EQ(offsets[c], std::int32_t((c + 1) * std::size_t(dim))) << "cell " << c;
  EXPECT_EQ(out.cells.size(), offsets.size() * std::size_t(dim));
  return out;
}

SurfaceFiles read_surface_obj(const std::string& path, int dim) {
  std::ifstream in(path);
  SurfaceFiles out;
  for (std::string line; std::getline(in, line);) {
    std::istringstream row(line);
    std::string tag;
    row >> tag;
    if (tag == "v") {
      for (std::string x; row >> x;) out.points.push_back(std::stof(x));
    } else if (tag == (dim == 2 ? "l" : "f")) {
      for (long i; row >> i;) {
        EXPECT_GE(i, 1);  // OBJ indices are 1-based
        out.cells.push_back(std::uint32_t(i - 1));
      }
    }
  }
  return out;
}

// PLY: the header's counts, then x y z vx vy vz per vertex and each element's indices.
SurfaceFiles read_surface_ply(const std::string& path, int dim) {
  const std::string file = read_all(path);
  std::smatch m;
  SurfaceFiles out;
  EXPECT_TRUE(std::regex_search(file, m, std::regex("element vertex (\\d+)\n")));
  const std::size_t n = std::stoul(m[1]);
  const std::string element = dim == 2 ? "element edge (\\d+)\n" : "element face (\\d+)\n";
  EXPECT_TRUE(std::regex_search(file, m, std::regex(element)));
  const std::size_t cells = std::stoul(m[1]);
  std::size_t at = file.find("end_header\n") + 11;
  for (std::size_t v = 0; v < n; ++v, at += 24)
    for (int a = 0; a < 6; ++a)
      (a < 3 ? out.points : out.velocity).push_back(get<float>(file, at + 4 * std::size_t(a)));
  for (std::size_t c = 0; c < cells; ++c) {
    if (dim == 3) {
      EXPECT_EQ(std::uint8_t(file[at++]), 3u);
    }
    for (int k = 0; k < dim; ++k, at += 4) out.cells.push_back(get<std::uint32_t>(file, at));
  }
  EXPECT_EQ(at, file.size());
  return out;
}

void expect_same_floats(const std::vector<float>& got, const std::vector<float>& want, int dim,
                        const std::string& what) {
  const std::size_t n = want.size() / std::size_t(dim);
  ASSERT_EQ(got.size(), 3 * n) << what;
  for (std::size_t v = 0; v < n; ++v)
    for (int a = 0; a < 3; ++a) {
      const float w = a < dim ? want[v * std::size_t(dim) + std::size_t(a)] : 0.0f;
      ASSERT_TRUE(std::memcmp(&got[3 * v + std::size_t(a)], &w, 4) == 0)
          << what << " vertex " << v << " axis " << a << ": " << got[3 * v + std::size_t(a)]
          << " != " << w;
    }
}

// 2D: every vertex ends exactly two segments (a closed curve); 3D: every edge lies in exactly
// two triangles, traversed once each way (closed and consistently oriented).
void expect_closed(const std::vector<std::uint32_t>& cells, std::size_t vertices, int dim) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  std::vector<int> degree(vertices, 0);
  for (std::size_t c = 0; c < cells.size(); c += std::size_t(dim))
    for (int k = 0; k < dim; ++k) {
      const std::uint32_t a = cells[c + std::size_t(k)];
      const std::uint32_t b = cells[c + std::size_t((k + 1) % dim)];
      ASSERT_LT(a, vertices);
      ++degree[a];
      if (dim == 3) ++directed[{a, b}];
    }
  if (dim == 2) {
    for (std::size_t v = 0; v < vertices; ++v) EXPECT_EQ(degree[v], 2) << "vertex " << v;
    return;
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second;
    const auto back = directed.find({edge.second, edge.first});
    EXPECT_TRUE(back != directed.end() && back->second == 1)
        << "edge " << edge.first << "-" << edge.second << " lies in one triangle only";
  }
}

class SurfaceDumps : public ::testing::TestWithParam<const char*> {};

TEST_P(SurfaceDumps, ReadBackAsTheSnapshotPlacesThem) {
  const std::string scene = GetParam();
  auto sim = make_simulation(load_scene(kDir + scene + ".json"));
  const std::string dir = temp_path("surface-" + scene);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const DumpFormat vtk = vtk_zlib_available() ? DumpFormat::vtk : DumpFormat::vtk_raw;
  ParticleDump dump(dir, {vtk, DumpFormat::ply, DumpFormat::obj});
  dump.write(*sim, 0);
  const double t0 = sim->time();
  for (int k = 0; k < 4; ++k) sim->step(1e9);  // falling: the surface has moved and has speed
  dump.write(*sim, 1);
  const auto snap = sim->snapshot();
  ASSERT_FALSE(snap->surfaces.empty());
  const int dim = snap->dim;
  for (std::size_t k = 0; k < snap->surfaces.size(); ++k) {
    const SurfaceLayer& s = snap->surfaces[k];
    SCOPED_TRACE(scene + " surface " + std::to_string(k));
    const std::size_t vertices = s.positions.size() / std::size_t(dim);
    ASSERT_GT(vertices, 8u);
    ASSERT_GT(s.elements.size(), 0u);
    EXPECT_FALSE(std::filesystem::exists(dir + "/frame_0001.obj"));  // no particles
    const std::string base = dir + "/frame_0001_surface" + std::to_string(k);
    // Both encodings: ParticleDump's, and the other one written directly.
    for (const bool zlib : {vtk == DumpFormat::vtk, false}) {
      std::string path = base + ".vtp";
      if (!zlib && vtk == DumpFormat::vtk) {
        path = base + "-raw.vtp";
        write_surface_vtp(path, s, dim, false);
      }
      const SurfaceFiles f = read_surface_vtp(path, zlib, dim);
      expect_same_floats(f.points, s.positions, dim, "vtp points");
      expect_same_floats(f.velocity, s.velocities, dim, "vtp velocity");
      EXPECT_EQ(f.cells, s.elements);
      expect_closed(f.cells, vertices, dim);
    }
    const SurfaceFiles obj = read_surface_obj(base + ".obj", dim);
    expect_same_floats(obj.points, s.positions, dim, "obj vertices");
    EXPECT_EQ(obj.cells, s.elements);
    const SurfaceFiles ply = read_surface_ply(base + ".ply", dim);
    expect_same_floats(ply.points, s.positions, dim, "ply vertices");
    expect_same_floats(ply.velocity, s.velocities, dim, "ply velocity");
    EXPECT_EQ(ply.cells, s.elements);
    float fastest = 0;
    for (float u : s.velocities) fastest = std::max(fastest, std::abs(u));
    EXPECT_GT(fastest, 0.0f);  // the velocity compared above is not all zeros
  }
  // series.pvd: each frame's grids and surfaces at that frame's time.
  const std::string pvd = read_all(dir + "/series.pvd");
  for (int frame = 0; frame < 2; ++frame)
    for (std::size_t k = 0; k < snap->surfaces.size(); ++k) {
      std::ostringstream time;
      time << std::setprecision(17) << (frame == 0 ? t0 : sim->time());
      const std::string entry = "<DataSet timestep=\"" + time.str() + "\" part=\"" +
                                std::to_string(snap->grids.size() + k) + "\" file=\"frame_000" +
                                std::to_string(frame) + "_surface" + std::to_string(k) + ".vtp\"/>";
      EXPECT_NE(pvd.find(entry), std::string::npos) << entry << "\n" << pvd;
    }
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(ParticleExport, SurfaceDumps, ::testing::Values("eol-drop", "eol-drop-3d"),
                         [](const auto& info) {
                           return std::string(info.param) == "eol-drop" ? "Drop2D" : "Drop3D";
                         });

TEST(ParticleExport, FormatsParseOrSayWhy) {
  EXPECT_EQ(parse_dump_formats("csv,vtk,ply,obj").size(), 4u);
  EXPECT_EQ(parse_dump_formats("vtk-raw"), std::vector<DumpFormat>{DumpFormat::vtk_raw});
  EXPECT_THROW(parse_dump_formats("vtk,vtk-raw"), std::invalid_argument);  // one .vtp per frame
  EXPECT_THROW(parse_dump_formats("vtk,xyz"), std::invalid_argument);
  EXPECT_THROW(parse_dump_formats("vtk,vtk"), std::invalid_argument);
  EXPECT_THROW(parse_dump_formats(""), std::invalid_argument);
  // Only CSV needs particles: EoL writes its grids and surfaces in the others.
  EXPECT_FALSE(formats_need_particles({DumpFormat::vtk, DumpFormat::ply, DumpFormat::obj}));
  EXPECT_TRUE(formats_need_particles({DumpFormat::obj, DumpFormat::csv}));
}

}  // namespace
}  // namespace apiclab
