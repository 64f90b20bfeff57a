// The exact inside test of a closed triangle mesh (MeshSolid::inside): the winding number of the
// surface around a point, counted as signed crossings of a segment from the point out of the
// mesh's box. CGAL (exact orientation predicates, AABB tree) lives in mesh_inside.cpp alone.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace apiclab {

class MeshWinding {
 public:
  using Vec3d = std::array<double, 3>;
  // The triangles index `vertices`; both must outlive the object. Degenerate (collinear)
  // triangles are left out: they bound no solid angle.
  MeshWinding(const std::vector<Vec3d>& vertices,
              const std::vector<std::array<std::uint32_t, 3>>& triangles, const Vec3d& lo,
              const Vec3d& hi);
  ~MeshWinding();
  MeshWinding(const MeshWinding&) = delete;
  MeshWinding& operator=(const MeshWinding&) = delete;

  // Outward-facing triangles count +1 where the segment leaves through them: 1 inside a single
  // outward surface, 0 outside, −1 inside a surface facing in, 2 where two outward ones overlap.
  // A point on the surface reports `on_surface` (and winding 0).
  struct Result {
    int winding = 0;
    bool on_surface = false;
    int segments = 0;  // cast: one more for each that grazed an edge or a vertex
  };
  Result winding(const Vec3d& p) const;
  // The same at `to`, from the result `at_from` at a nearby point `from` (a lattice's previous
  // site): the crossings of the short segment between them change the count, fewer triangles
  // to meet than on a segment out of the box. A full query where that segment grazes an edge
  // or a vertex.
  Result walk(const Vec3d& from, const Result& at_from, const Vec3d& to) const;
  // The direction of the segment cast at each attempt (z component ±1).
  static Vec3d direction(int attempt);

  struct Impl;  // CGAL's tree and points (mesh_inside.cpp)

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace apiclab
