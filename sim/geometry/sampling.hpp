// Filling scene objects with particles: shapes (inside tests), grid-aligned lattices and
// Poisson disk sampling (Bridson 2007), closed triangle meshes (OBJ).
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/scene/scene.hpp"

namespace apiclab {

struct SampledParticles {
  std::vector<Vec3d> positions;
  std::vector<Vec3d> velocities;
  std::vector<double> volumes;
  double spacing = 0;  // nominal particle spacing (drawing radius, D_p checks)
};

// Samples one object of a scene. Throws SceneError (e.g. unreadable mesh, no particle inside).
SampledParticles sample_object(const SceneDesc& scene, int object_index);

// The mesh file of a mesh object: beside the scene, in its parent folder, then in
// scene.asset_dirs. Throws SceneError naming the key when missing or not a regular file.
std::string resolve_mesh_file(const SceneDesc& scene, int object_index);

// Bounding box of a non-mesh shape in world coordinates (rotated shapes: the box of the sphere
// around the center that holds them).
void shape_bounds(const ShapeDesc& shape, int dim, Vec3d& lo, Vec3d& hi);

// Inside test for a shape in world coordinates (meshes need a MeshSolid, below).
bool inside_shape(const ShapeDesc& shape, const Vec3d& x, int dim);

struct ObjMesh;
class MeshWinding;

// Where a mesh shape puts each OBJ vertex v in the world: R (scale v) + translate, R the
// shape's rotation about the OBJ's origin. MPM's particles and the EoL rest shape both place it so.
std::vector<Vec3d> place_mesh_vertices(const ShapeDesc& shape, const ObjMesh& obj);

// A closed triangle mesh placed in the world, with an exact inside test
// (sim/geometry/mesh_inside.hpp): a point is inside where the surface's winding number is nonzero,
// so overlapping parts of a mesh fill their union and a surface facing in cuts a cavity; a point on
// the surface is inside.
class MeshSolid {
 public:
  // Loads an OBJ (load_obj_mesh), scaled, rotated and translated as the shape says.
  MeshSolid(const std::string& obj_path, const ShapeDesc& shape);
  // The same from an OBJ already loaded (load_obj_mesh).
  MeshSolid(const ObjMesh& obj, const ShapeDesc& shape);
  ~MeshSolid();
  MeshSolid(MeshSolid&&) noexcept;
  // Thread-safe; the first call builds the search tree (bounds and volume need none).
  bool inside(const Vec3d& p) const;
  // inside() of each point into `in`, walking from each point to the next: for a lattice's
  // rows, where the short steps meet few triangles (the same answers, a few times faster).
  void inside_run(const std::vector<Vec3d>& points, std::vector<char>& in) const;
  Vec3d lower() const { return lo_; }
  Vec3d upper() const { return hi_; }
  bool finite() const { return finite_; }  // every placed coordinate within ±1e307
  double volume() const;                   // signed-volume sum (divergence theorem)
  std::size_t triangle_count() const { return triangles_.size(); }

 private:
  std::vector<Vec3d> vertices_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  Vec3d lo_{}, hi_{};
  bool finite_ = true;
  struct Search;
  std::unique_ptr<Search> search_;
  const MeshWinding& search() const;  // built on first use
};

// The mesh of a mesh object, placed, and checked to be finite and inside the domain (SceneError
// naming the scene key otherwise). Every reader of a scene's mesh goes through it, so the memory
// estimate never sizes a mesh far outside the domain.
std::unique_ptr<MeshSolid> load_mesh_solid(const SceneDesc& scene, int object_index);
void check_mesh_placement(const SceneDesc& scene, int object_index, const MeshSolid& mesh);

// Poisson disk samples (Bridson 2007) with minimum separation r in the box [lo, hi];
// `periodic` makes the separation hold across opposite faces too.
std::vector<Vec3d> poisson_disk(const Vec3d& lo, const Vec3d& hi, double r, int dim,
                                std::uint64_t seed, bool periodic = false);

}  // namespace apiclab
