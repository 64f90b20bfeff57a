// --dump formats read back (issue 16): VTK PolyData (header, offsets and sizes checked by a
// reader of our own; every array bit for bit), binary PLY bit for bit, OBJ and CSV to their
// printed precision (max_digits10 round-trips exactly), series.pvd lists every frame's time.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "app/particle_export.hpp"
#include "sim/scene.hpp"
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

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("apiclab-export-" + name)).string();
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

// Issue 16: a 3D run's VTK frame is at most a quarter of the bytes of its CSV frame (zlib; raw
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

TEST(ParticleExport, FormatsParseOrSayWhy) {
  EXPECT_EQ(parse_dump_formats("csv,vtk,ply,obj").size(), 4u);
  EXPECT_EQ(parse_dump_formats("vtk-raw"), std::vector<DumpFormat>{DumpFormat::vtk_raw});
  EXPECT_THROW(parse_dump_formats("vtk,vtk-raw"), std::invalid_argument);  // one .vtp per frame
  EXPECT_THROW(parse_dump_formats("vtk,xyz"), std::invalid_argument);
  EXPECT_THROW(parse_dump_formats("vtk,vtk"), std::invalid_argument);
  EXPECT_THROW(parse_dump_formats(""), std::invalid_argument);
}

}  // namespace
}  // namespace apiclab
