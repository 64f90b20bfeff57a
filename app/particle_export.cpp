#include "app/particle_export.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "app/output_file.hpp"
#include "sim/simulation.hpp"

#ifdef APICLAB_HAVE_ZLIB
#include <zlib.h>
#endif

namespace apiclab {
namespace {

// Little-endian bytes of a value (every machine apiclab builds for is little-endian; checked).
static_assert(std::endian::native == std::endian::little, "the dump writers assume little-endian");

template <class V>
void put(std::string& bytes, V v) {
  char b[sizeof(V)];
  std::memcpy(b, &v, sizeof(V));
  bytes.append(b, sizeof(V));
}

// The XML head, then the appended block (raw bytes: each array as VtkArrays wrote it).
void write_vtk_file(const std::string& path, const std::string& head, const std::string& data) {
  write_file_whole(path, head + "  <AppendedData encoding=\"raw\">\n   _" + data +
                             "\n  </AppendedData>\n</VTKFile>\n");
}

// Positions as 3 components (2D gets z = 0), the layout every viewer expects.
std::vector<double> positions3(const ParticleTable& t) {
  const ParticleColumn* x = t.find("position");
  std::vector<double> p(3 * t.count, 0.0);
  for (std::size_t q = 0; q < t.count; ++q)
    for (int a = 0; a < t.dim; ++a)
      p[3 * q + std::size_t(a)] = x->values[q * std::size_t(t.dim) + std::size_t(a)];
  return p;
}

// The root element; a compressed file names VTK's zlib compressor.
std::string vtk_file_tag(const char* type, bool zlib) {
  return std::string("<VTKFile type=\"") + type +
         "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"" +
         (zlib ? " compressor=\"vtkZLibDataCompressor\"" : "") + ">\n";
}

}  // namespace

bool vtk_zlib_available() {
#ifdef APICLAB_HAVE_ZLIB
  return true;
#else
  return false;
#endif
}

// VTK's appended layout (vtkXMLWriter): raw = UInt64 byte count, then the bytes; compressed =
// UInt64 [block count, block size, size of a partial last block (0: none), each block's
// compressed size], then the compressed blocks. Blocks are independent: compressed in parallel.
void append_vtk_array(std::string& data, const std::string& raw, bool zlib) {
  if (!zlib) {
    put<std::uint64_t>(data, raw.size());
    data += raw;
    return;
  }
#ifdef APICLAB_HAVE_ZLIB
  const std::size_t block = vtk_zlib_block_size;
  const std::size_t blocks = (raw.size() + block - 1) / block;
  std::vector<std::string> packed(blocks);
  bool failed = false;
#pragma omp parallel for schedule(dynamic) if (blocks > 4)
  for (std::ptrdiff_t b = 0; b < std::ptrdiff_t(blocks); ++b) {
    const std::size_t first = std::size_t(b) * block;
    const std::size_t size = std::min(block, raw.size() - first);
    uLongf out = compressBound(uLong(size));
    std::string& z = packed[std::size_t(b)];
    z.resize(out);
    // Level 1: most of level 6's gain on float arrays at several times the speed.
    if (compress2(reinterpret_cast<Bytef*>(z.data()), &out,
                  reinterpret_cast<const Bytef*>(raw.data() + first), uLong(size), 1) != Z_OK)
      failed = true;
    z.resize(out);
  }
  if (failed) throw std::runtime_error("zlib could not compress a VTK array");
  put<std::uint64_t>(data, blocks);
  put<std::uint64_t>(data, block);
  put<std::uint64_t>(data, raw.size() % block);
  for (const std::string& z : packed) put<std::uint64_t>(data, z.size());
  for (const std::string& z : packed) data += z;
#else
  throw std::runtime_error("this apiclab was built without zlib: use --dump-format vtk-raw");
#endif
}

std::vector<DumpFormat> parse_dump_formats(const std::string& list) {
  std::vector<DumpFormat> out;
  std::vector<std::string> keys;  // as given, for the messages
  std::istringstream in(list);
  for (std::string key; std::getline(in, key, ',');) {
    DumpFormat f;
    if (key == "csv")
      f = DumpFormat::csv;
    else if (key == "vtk")
      f = vtk_zlib_available() ? DumpFormat::vtk : DumpFormat::vtk_raw;
    else if (key == "vtk-raw")
      f = DumpFormat::vtk_raw;
    else if (key == "ply")
      f = DumpFormat::ply;
    else if (key == "obj")
      f = DumpFormat::obj;
    else
      throw std::invalid_argument("unknown dump format '" + key +
                                  "' (expected csv|vtk|vtk-raw|ply|obj)");
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (keys[i] == key) throw std::invalid_argument("dump format '" + key + "' is listed twice");
      if (is_vtk(out[i]) && is_vtk(f))
        throw std::invalid_argument(
            "'vtk' and 'vtk-raw' both write frame_NNNN.vtp (vtk zlib-compressed, vtk-raw "
            "uncompressed): give one of them");
    }
    out.push_back(f);
    keys.push_back(key);
  }
  if (out.empty())
    throw std::invalid_argument("no dump format given (expected csv|vtk|vtk-raw|ply|obj)");
  return out;
}

const char* extension_of(DumpFormat f) {
  switch (f) {
    case DumpFormat::csv:
      return "csv";
    case DumpFormat::vtk:
    case DumpFormat::vtk_raw:
      return "vtp";
    case DumpFormat::ply:
      return "ply";
    case DumpFormat::obj:
      break;
  }
  return "obj";
}

// VTK XML PolyData with appended binary data (zlib-compressed blocks, or raw). Positions in
// Float64 (a large domain needs them); the other fields in Float32 and ids in Int32: raw, a 3D
// frame is 140 bytes per particle; one vertex cell per particle so that every representation
// of ParaView draws them.
void write_vtp(const std::string& path, const ParticleTable& t, const ExtraScalars& extra,
               bool zlib) {
  std::ostringstream xml;
  std::string data, raw;
  auto array = [&](const std::string& type, const std::string& name, int components) {
    xml << "      <DataArray type=\"" << type << "\""
        << (name.empty() ? "" : " Name=\"" + name + "\"") << " NumberOfComponents=\"" << components
        << "\" format=\"appended\" offset=\"" << data.size() << "\"/>\n";
  };
  auto flush = [&] {
    append_vtk_array(data, raw, zlib);
    raw.clear();
  };
  const std::size_t n = t.count;
  xml << "<?xml version=\"1.0\"?>\n"
      << vtk_file_tag("PolyData", zlib) << "  <PolyData>\n"
      << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfVerts=\"" << n
      << "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
      << "    <PointData Scalars=\"speed\" Vectors=\"velocity\">\n";
  for (const ParticleColumn& c : t.columns) {
    if (c.name == "position") continue;
    const bool vector = c.name == "velocity";
    const int comps = vector ? 3 : c.components();
    array(c.integer ? "Int32" : "Float32", c.name, comps);
    raw.reserve(n * std::size_t(comps) * 4);
    for (std::size_t q = 0; q < n; ++q)
      for (int k = 0; k < comps; ++k) {
        const double v =
            k < c.components() ? c.values[q * std::size_t(c.components()) + std::size_t(k)] : 0.0;
        if (c.integer)
          put<std::int32_t>(raw, std::int32_t(v));
        else
          put<float>(raw, float(v));
      }
    flush();
  }
  for (const auto& [name, values] : extra.fields) {
    array("Float32", name, 1);
    for (std::size_t q = 0; q < n; ++q) put<float>(raw, values[q]);
    flush();
  }
  xml << "    </PointData>\n    <Points>\n";
  array("Float64", "", 3);
  for (double v : positions3(t)) put<double>(raw, v);
  flush();
  xml << "    </Points>\n    <Verts>\n";
  array("Int32", "connectivity", 1);
  for (std::size_t q = 0; q < n; ++q) put<std::int32_t>(raw, std::int32_t(q));
  flush();
  array("Int32", "offsets", 1);
  for (std::size_t q = 0; q < n; ++q) put<std::int32_t>(raw, std::int32_t(q + 1));
  flush();
  xml << "    </Verts>\n    </Piece>\n  </PolyData>\n";
  write_vtk_file(path, xml.str(), data);
}

void write_ply(const std::string& path, const ParticleTable& t) {
  std::ostringstream head;
  head << "ply\nformat binary_little_endian 1.0\ncomment apiclab particles\nelement vertex "
       << t.count << "\nproperty float x\nproperty float y\nproperty float z\n"
       << "property float vx\nproperty float vy\nproperty float vz\nproperty int object\n"
       << "end_header\n";
  const std::vector<double> x = positions3(t);
  const ParticleColumn* v = t.find("velocity");
  const ParticleColumn* o = t.find("object");
  std::string data;
  data.reserve(t.count * 28);
  for (std::size_t q = 0; q < t.count; ++q) {
    for (int a = 0; a < 3; ++a) put<float>(data, float(x[3 * q + std::size_t(a)]));
    for (int a = 0; a < 3; ++a)
      put<float>(data,
                 a < t.dim ? float(v->values[q * std::size_t(t.dim) + std::size_t(a)]) : 0.0f);
    put<std::int32_t>(data, std::int32_t(o->values[q]));
  }
  write_file_whole(path, head.str() + data);
}

void write_obj(const std::string& path, const ParticleTable& t) {
  std::ostringstream out;
  out << "# apiclab particles: one vertex per particle, ordered by id\n"
      << std::setprecision(t.digits);
  const std::vector<double> x = positions3(t);
  for (std::size_t q = 0; q < t.count; ++q)
    out << "v " << x[3 * q] << ' ' << x[3 * q + 1] << ' ' << x[3 * q + 2] << '\n';
  write_file_whole(path, out.str());
}

void write_vti(const std::string& path, const GridLayer& g, bool zlib) {
  std::ostringstream xml;
  std::string data, raw;
  const std::size_t n = g.node_count();
  xml << std::setprecision(17) << "<?xml version=\"1.0\"?>\n" << vtk_file_tag("ImageData", zlib);
  std::ostringstream extent;
  extent << "0 " << g.nodes[0] - 1 << " 0 " << g.nodes[1] - 1 << " 0 " << g.nodes[2] - 1;
  xml << "  <ImageData WholeExtent=\"" << extent.str() << "\" Origin=\"" << g.translation[0] << ' '
      << g.translation[1] << ' ' << g.translation[2] << "\" Spacing=\"" << g.dx << ' ' << g.dx
      << ' ' << g.dx << "\" Direction=\"";
  for (int k = 0; k < 9; ++k) xml << (k ? " " : "") << g.rotation[std::size_t(k)];
  xml << "\">\n    <Piece Extent=\"" << extent.str() << "\">\n      <PointData>\n";
  for (const GridLayer::Field& f : g.fields) {
    xml << "        <DataArray type=\"Float32\" Name=\"" << f.name
        << "\" NumberOfComponents=\"1\" format=\"appended\" offset=\"" << data.size() << "\"/>\n";
    for (std::size_t i = 0; i < n; ++i) put<float>(raw, f.values[i]);
    append_vtk_array(data, raw, zlib);
    raw.clear();
  }
  xml << "      </PointData>\n    </Piece>\n  </ImageData>\n";
  write_vtk_file(path, xml.str(), data);
}

// A surface's vertex a-th coordinate of a dim-float array as 3 components (2D: z = 0).
float component3(const std::vector<float>& values, std::size_t v, int a, int dim) {
  return a < dim ? values[v * std::size_t(dim) + std::size_t(a)] : 0.0f;
}

void write_surface_vtp(const std::string& path, const SurfaceLayer& s, int dim, bool zlib) {
  std::ostringstream xml;
  std::string data, raw;
  const std::size_t n = s.positions.size() / std::size_t(dim);
  const std::size_t cells = s.elements.size() / std::size_t(dim);
  const char* cell_kind = dim == 2 ? "Lines" : "Polys";
  auto array = [&](const char* type, const char* name, int components) {
    xml << "      <DataArray type=\"" << type << "\"" << (*name ? " Name=\"" : "") << name
        << (*name ? "\"" : "") << " NumberOfComponents=\"" << components
        << "\" format=\"appended\" offset=\"" << data.size() << "\"/>\n";
    append_vtk_array(data, raw, zlib);
    raw.clear();
  };
  xml << "<?xml version=\"1.0\"?>\n"
      << vtk_file_tag("PolyData", zlib) << "  <PolyData>\n"
      << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfVerts=\"0\" NumberOfLines=\""
      << (dim == 2 ? cells : 0) << "\" NumberOfStrips=\"0\" NumberOfPolys=\""
      << (dim == 2 ? 0 : cells) << "\">\n"
      << "    <PointData Scalars=\"speed\" Vectors=\"velocity\">\n";
  const bool moving = s.velocities.size() == s.positions.size();
  if (moving) {
    for (std::size_t v = 0; v < n; ++v)
      for (int a = 0; a < 3; ++a) put<float>(raw, component3(s.velocities, v, a, dim));
    array("Float32", "velocity", 3);
    for (std::size_t v = 0; v < n; ++v) {
      double s2 = 0;
      for (int a = 0; a < dim; ++a) s2 += std::pow(component3(s.velocities, v, a, dim), 2);
      put<float>(raw, float(std::sqrt(s2)));
    }
    array("Float32", "speed", 1);
  }
  xml << "    </PointData>\n    <Points>\n";
  for (std::size_t v = 0; v < n; ++v)
    for (int a = 0; a < 3; ++a) put<float>(raw, component3(s.positions, v, a, dim));
  array("Float32", "", 3);
  xml << "    </Points>\n    <" << cell_kind << ">\n";
  for (std::uint32_t i : s.elements) put<std::int32_t>(raw, std::int32_t(i));
  array("Int32", "connectivity", 1);
  for (std::size_t c = 0; c < cells; ++c) put<std::int32_t>(raw, std::int32_t((c + 1) * dim));
  array("Int32", "offsets", 1);
  xml << "    </" << cell_kind << ">\n    </Piece>\n  </PolyData>\n";
  write_vtk_file(path, xml.str(), data);
}

void write_surface_ply(const std::string& path, const SurfaceLayer& s, int dim) {
  const std::size_t n = s.positions.size() / std::size_t(dim);
  const std::size_t cells = s.elements.size() / std::size_t(dim);
  const bool moving = s.velocities.size() == s.positions.size();
  std::ostringstream head;
  head << "ply\nformat binary_little_endian 1.0\ncomment apiclab surface " << s.name
       << "\nelement vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\n"
       << (moving ? "property float vx\nproperty float vy\nproperty float vz\n" : "")
       << (dim == 2 ? "element edge " : "element face ") << cells << '\n'
       << (dim == 2 ? "property int vertex1\nproperty int vertex2\n"
                    : "property list uchar int vertex_indices\n")
       << "end_header\n";
  std::string data;
  for (std::size_t v = 0; v < n; ++v) {
    for (int a = 0; a < 3; ++a) put<float>(data, component3(s.positions, v, a, dim));
    if (moving)
      for (int a = 0; a < 3; ++a) put<float>(data, component3(s.velocities, v, a, dim));
  }
  for (std::size_t c = 0; c < cells; ++c) {
    if (dim == 3) put<std::uint8_t>(data, 3);
    for (int k = 0; k < dim; ++k)
      put<std::int32_t>(data, std::int32_t(s.elements[c * std::size_t(dim) + std::size_t(k)]));
  }
  write_file_whole(path, head.str() + data);
}

void write_surface_obj(const std::string& path, const SurfaceLayer& s, int dim) {
  std::ostringstream out;
  const std::size_t n = s.positions.size() / std::size_t(dim);
  // max_digits10 of float: the snapshot's positions read back exactly.
  out << "# apiclab surface " << s.name << (dim == 2 ? ": closed polyline\n" : ": triangle mesh\n")
      << "o " << (s.name.empty() ? "surface" : s.name) << '\n'
      << std::setprecision(std::numeric_limits<float>::max_digits10);
  for (std::size_t v = 0; v < n; ++v)
    out << "v " << component3(s.positions, v, 0, dim) << ' ' << component3(s.positions, v, 1, dim)
        << ' ' << component3(s.positions, v, 2, dim) << '\n';
  for (std::size_t c = 0; c + std::size_t(dim) <= s.elements.size(); c += std::size_t(dim)) {
    out << (dim == 2 ? 'l' : 'f');
    for (int k = 0; k < dim; ++k) out << ' ' << s.elements[c + std::size_t(k)] + 1;
    out << '\n';
  }
  write_file_whole(path, out.str());
}

bool is_vtk(DumpFormat f) { return f == DumpFormat::vtk || f == DumpFormat::vtk_raw; }

bool formats_need_particles(const std::vector<DumpFormat>& formats) {
  for (DumpFormat f : formats)
    if (f == DumpFormat::csv) return true;
  return false;
}

void PvdSeries::add(double t, const std::string& file, int part) {
  frames_.push_back({t, part, file});
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" "
         "byte_order=\"LittleEndian\">\n  <Collection>\n"
      << std::setprecision(17);
  for (const Entry& e : frames_)
    out << "    <DataSet timestep=\"" << e.t << "\" part=\"" << e.part << "\" file=\"" << e.file
        << "\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
  write_file_whole(dir_ + "/series.pvd", out.str());
}

}  // namespace apiclab

namespace apiclab {

void ParticleDump::write(const Simulation& sim, int frame) {
  const TransferControls* particles = sim.transfers();  // callers refuse CSV without
  char base[32];
  std::snprintf(base, sizeof base, "frame_%04d", frame);
  std::shared_ptr<Snapshot> snap;  // taken once, for grids and surfaces (not for CSV)
  for (DumpFormat f : formats_) {
    const std::string name = std::string(base) + "." + extension_of(f);
    const std::string path = dir_ + "/" + name;
    if (!snap && f != DumpFormat::csv) snap = sim.snapshot();
    int part = 0;
    if (is_vtk(f)) {
      const bool zlib = f == DumpFormat::vtk;
      if (particles) {
        // Speed and velocity noise as scalars (the noise is a fresh P2G: only when VTK asks).
        particles->fill_velocity_noise(*snap);
        const ParticleTable table = particles->particle_table();
        ExtraScalars extra;
        std::vector<float> speed(table.count);
        const ParticleColumn* v = table.find("velocity");
        for (std::size_t q = 0; q < table.count; ++q) {
          double s2 = 0;
          for (int a = 0; a < table.dim; ++a)
            s2 += std::pow(v->values[q * std::size_t(table.dim) + std::size_t(a)], 2);
          speed[q] = float(std::sqrt(s2));
        }
        extra.fields.emplace_back("speed", std::move(speed));
        if (snap->noise.size() == table.count) extra.fields.emplace_back("noise", snap->noise);
        write_vtp(path, table, extra, zlib);
        series_.add(sim.time(), name, part++);
      }
      for (std::size_t k = 0; k < snap->grids.size(); ++k) {
        const std::string grid = std::string(base) + "_grid" + std::to_string(k) + ".vti";
        write_vti(dir_ + "/" + grid, snap->grids[k], zlib);
        series_.add(sim.time(), grid, part++);
      }
    } else if (particles) {
      const ParticleTable table = particles->particle_table();
      if (f == DumpFormat::csv) {
        write_file_whole(path, [&](std::ostream& out) { write_particles_csv(out, table); });
      } else if (f == DumpFormat::ply) {
        write_ply(path, table);
      } else {
        write_obj(path, table);
      }
    }
    if (f == DumpFormat::csv) continue;
    // The object surfaces (EoL, Sec 3.8), beside the particles and grids.
    for (std::size_t k = 0; k < snap->surfaces.size(); ++k) {
      const std::string file =
          std::string(base) + "_surface" + std::to_string(k) + "." + extension_of(f);
      const SurfaceLayer& s = snap->surfaces[k];
      if (is_vtk(f)) {
        write_surface_vtp(dir_ + "/" + file, s, snap->dim, f == DumpFormat::vtk);
        series_.add(sim.time(), file, part++);
      } else if (f == DumpFormat::ply) {
        write_surface_ply(dir_ + "/" + file, s, snap->dim);
      } else {
        write_surface_obj(dir_ + "/" + file, s, snap->dim);
      }
    }
  }
}

}  // namespace apiclab
