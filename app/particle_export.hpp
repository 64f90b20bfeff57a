// `--dump DIR --dump-format csv,vtk,ply,obj`: one file per frame and format, from the solver's
// ParticleTable (sim/measure/particle_table.hpp). VTK: `.vtp` PolyData with appended binary (zlib
// blocks as VTK's own writer makes them; `vtk-raw` uncompressed) and a `series.pvd` time series
// (ParaView opens the run in one click); PLY: binary little-endian with position, velocity and
// object (Houdini, Blender); OBJ: one vertex list per frame, as the 3D seed wrote for Houdini. The
// VTK XML is written by hand: the VTK library is several hundred MB of dependencies for a file
// format of a page.
#pragma once
#include <string>
#include <vector>

#include "sim/measure/particle_table.hpp"
#include "sim/snapshot.hpp"

namespace apiclab {

// vtk: zlib-compressed appended data (raw when built without zlib); vtk_raw: uncompressed.
enum class DumpFormat { csv, vtk, vtk_raw, ply, obj };
bool is_vtk(DumpFormat f);
bool vtk_zlib_available();

// "csv,vtk" → {csv, vtk}; throws std::invalid_argument naming an unknown or repeated format.
std::vector<DumpFormat> parse_dump_formats(const std::string& list);
const char* extension_of(DumpFormat f);  // "csv", "vtp", "ply", "obj"

// Per-particle scalars beyond the table's columns (speed |v|, velocity noise), by table row.
struct ExtraScalars {
  std::vector<std::pair<std::string, std::vector<float>>> fields;
};

void write_vtp(const std::string& path, const ParticleTable& t, const ExtraScalars& extra = {},
               bool zlib = false);
void write_ply(const std::string& path, const ParticleTable& t);
void write_obj(const std::string& path, const ParticleTable& t);
// A snapshot's grid layer (an EoL object grid riding its frame) as VTK ImageData: origin = the
// layer's translation, Direction = its rotation, one Float32 point array per field.
void write_vti(const std::string& path, const GridLayer& layer, bool zlib = false);
// One array into a VTK appended block: UInt64 size + bytes, or VTK's zlib block layout.
inline constexpr std::size_t vtk_zlib_block_size = 1 << 16;
void append_vtk_array(std::string& data, const std::string& raw, bool zlib);
// An object's surface (EoL, Fan et al. 2013 Sec 3.8) as placed in the snapshot: VTK PolyData
// (2D segments as Lines, 3D triangles as Polys; positions, velocity and speed as the snapshot's
// Float32), binary PLY (vertices with velocity; edges in 2D, faces in 3D) or OBJ (`v`, then `l`
// segments in 2D or `f` triangles in 3D, 1-based), so Blender and Houdini open the deforming
// object.
void write_surface_vtp(const std::string& path, const SurfaceLayer& s, int dim, bool zlib = false);
void write_surface_ply(const std::string& path, const SurfaceLayer& s, int dim);
void write_surface_obj(const std::string& path, const SurfaceLayer& s, int dim);
// Whether the formats need particles: CSV does (a solver without particles writes its grids and
// surfaces in VTK, its surfaces in PLY and OBJ); `dump_without_particles` says so to the user.
bool formats_need_particles(const std::vector<DumpFormat>& formats);
inline constexpr const char* dump_without_particles =
    "has no particles for --dump-format csv (vtk writes its grids and surfaces, ply and obj its "
    "surfaces)";

// DIR/series.pvd: every frame's .vtp with its simulation time, rewritten after each frame so a
// run stopped early still opens.
class PvdSeries {
 public:
  explicit PvdSeries(std::string dir) : dir_(std::move(dir)) {}
  void add(double t, const std::string& file, int part = 0);  // file relative to DIR
  struct Entry {
    double t;
    int part;
    std::string file;
  };
  // The files listed so far; a resumed run (app/checkpoint.hpp) lists them again.
  const std::vector<Entry>& entries() const { return frames_; }
  void restore(std::vector<Entry> entries) { frames_ = std::move(entries); }

 private:
  std::string dir_;
  std::vector<Entry> frames_;
};

}  // namespace apiclab

namespace apiclab {

class Simulation;

// Writes frame `frame` into DIR in every format (frame_0000.csv, frame_0000.vtp, …; with VTK
// also each grid layer of the snapshot, frame_0000_grid0.vti, …; with VTK, PLY and OBJ each
// surface of the snapshot, frame_0000_surface0.vtp, …) and keeps DIR/series.pvd current when VTK
// is among them. A solver without particles writes its grids and surfaces only.
class ParticleDump {
 public:
  ParticleDump(std::string dir, std::vector<DumpFormat> formats)
      : dir_(std::move(dir)), formats_(std::move(formats)), series_(dir_) {}
  void write(const Simulation& sim, int frame);
  PvdSeries& series() { return series_; }

 private:
  std::string dir_;
  std::vector<DumpFormat> formats_;
  PvdSeries series_;
};

}  // namespace apiclab
