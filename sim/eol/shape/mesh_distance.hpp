// The signed distance φ₀ of a mesh rest shape (an OBJ placed as the scene places it, the same
// placement as MPM's particles: place_mesh_vertices) in material space, negative inside. Sampled
// once on a lattice of spacing s = cell/2 and read by trilinear interpolation, since the solver
// reads φ₀ at every node after every advection (update_mass), not only at set-up.
//
// The mass reads φ₀ only through its fade, |φ₀| < cell/2 (smoothed_inside, eulerian_grid.hpp),
// and a point there interpolates lattice corners within √3 s of it, so every corner with
// |φ₀| ≤ cell/2 + √3 s = 1.37 cell < band = 1.5 cell holds the exact distance (closest point on
// the triangles).
// Beyond the band a chamfer distance propagated from it: an upper bound of |φ₀|, so a node
// outside the fade never gains mass from a short value. The sign is MeshSolid::inside (MPM's
// ray parity test), so EoL and MPM agree on which points are inside.
// Written by hand: the band needs each triangle's own neighbourhood only, no search tree
// (CGAL's AABB tree would answer far queries this never asks, at a heavy header's compile cost).
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "sim/geometry/obj_mesh.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab::eol {

// Distance from p to the triangle abc (Ericson, Real-Time Collision Detection, Sec 5.1.5).
double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b, const Eigen::Vector3d& c);

class MeshDistance {
 public:
  // cell: the EoL grid cell the mass fades over.
  MeshDistance(const ObjMesh& obj, const ShapeDesc& shape, double cell);
  double operator()(const Vec3d& x) const;  // φ₀(x)
  Vec3d lower() const { return lo_; }       // bounds of the placed mesh
  Vec3d upper() const { return hi_; }
  double spacing() const { return s_; }
  double band() const { return band_; }
  std::size_t lattice_points() const { return phi_.size(); }
  // The placed OBJ: vertices and triangles counter-clockwise seen from outside.
  const std::vector<Vec3d>& vertices() const { return vertices_; }
  const std::vector<std::array<std::uint32_t, 3>>& triangles() const { return triangles_; }

 private:
  std::vector<Vec3d> vertices_;
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  Vec3d lo_{}, hi_{};
  Eigen::Vector3d origin_;
  std::array<int, 3> n_{};
  double s_ = 0, band_ = 0;
  std::vector<double> phi_;  // x fastest, then y, then z
};

}  // namespace apiclab::eol
