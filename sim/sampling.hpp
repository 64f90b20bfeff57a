// Filling scene objects with particles: shapes (inside tests), grid-aligned lattices and
// Poisson disk sampling (Bridson 2007), closed triangle meshes (OBJ).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "scene.hpp"

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

// Where a mesh shape puts each OBJ vertex v in the world: R (scale v) + translate, R the
// shape's rotation about the OBJ's origin. MPM's particles and the EoL rest shape both place it so.
std::vector<Vec3d> place_mesh_vertices(const ShapeDesc& shape, const ObjMesh& obj);

// A closed triangle mesh with a fast inside test (ray parity along +z, triangles bucketed on xy).
class MeshSolid {
 public:
  // Loads an OBJ through tinyobjloader, scaled, rotated and translated as the shape says.
  MeshSolid(const std::string& obj_path, const ShapeDesc& shape);
  // The same from an OBJ already loaded (load_obj_mesh).
  MeshSolid(const ObjMesh& obj, const ShapeDesc& shape);
  bool inside(const Vec3d& p) const;
  Vec3d lower() const { return lo_; }
  Vec3d upper() const { return hi_; }
  double volume() const;  // signed-volume sum (divergence theorem)
  std::size_t triangle_count() const { return tris_.size(); }

 private:
  struct Tri {
    Vec3d a, b, c;
  };
  std::vector<Tri> tris_;
  Vec3d lo_{}, hi_{};
  int nx_ = 1, ny_ = 1;
  double cell_x_ = 1, cell_y_ = 1;
  std::vector<std::vector<std::uint32_t>> buckets_;
};

// Poisson disk samples (Bridson 2007) with minimum separation r in the box [lo, hi];
// `periodic` makes the separation hold across opposite faces too.
std::vector<Vec3d> poisson_disk(const Vec3d& lo, const Vec3d& hi, double r, int dim,
                                std::uint64_t seed, bool periodic = false);

}  // namespace apiclab
