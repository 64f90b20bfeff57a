// The rest shape of an object as a signed distance φ₀(X) in material space (negative inside),
// for every scene shape: box, ball, annulus, torus exactly, a mesh sampled (mesh_distance.hpp)
// (Sec 3.3 needs only φ₀ < 0; the distance lets the mass fade smoothly across the surface,
// eulerian_grid.hpp).
#pragma once
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>

#include "sim/eol/shape/mesh_distance.hpp"
#include "sim/geometry/sampling.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab::eol {

// Signed distance of world point x to the shape (exact for box, ball, annulus, torus).
inline double rest_distance(const ShapeDesc& s, const Vec3d& x, int dim) {
  Eigen::Vector3d p(x[0] - s.center[0], x[1] - s.center[1], dim == 3 ? x[2] - s.center[2] : 0.0);
  const Eigen::Vector3d axis_in(s.rotation_axis[0], s.rotation_axis[1], s.rotation_axis[2]);
  if (s.rotation_degrees != 0 && axis_in.norm() > 0)
    p = Eigen::AngleAxisd(s.rotation_degrees * M_PI / 180.0, axis_in.normalized())
            .toRotationMatrix()
            .transpose() *
        p;
  if (dim == 2) p[2] = 0;
  auto along_axis = [&](double& radial, double& along) {
    const Eigen::Vector3d a = Eigen::Vector3d(s.axis[0], s.axis[1], s.axis[2]).normalized();
    along = p.dot(a);
    radial = (p - along * a).norm();
  };
  // Signed distance of a 2D box-like region given per-axis excesses q (negative inside).
  auto box_distance = [](const Eigen::Vector3d& q) {
    const double outside = q.cwiseMax(0.0).norm();
    return outside + std::min(q.maxCoeff(), 0.0);
  };
  switch (s.type) {
    case ShapeType::box: {
      Eigen::Vector3d q(-1e300, -1e300, -1e300);
      for (int a = 0; a < dim; ++a) q[a] = std::abs(p[a]) - 0.5 * (s.max[a] - s.min[a]);
      return box_distance(q);
    }
    case ShapeType::ball:
      return p.norm() - s.radius;
    case ShapeType::annulus: {
      if (dim == 2) return std::max(p.norm() - s.outer, s.inner - p.norm());
      double radial, along;
      along_axis(radial, along);
      const double mid = 0.5 * (s.inner + s.outer), half = 0.5 * (s.outer - s.inner);
      return box_distance(
          {std::abs(radial - mid) - half, std::abs(along) - 0.5 * s.length, -1e300});
    }
    case ShapeType::torus: {
      double radial, along;
      along_axis(radial, along);
      const double R = 0.5 * (s.inner + s.outer), r = 0.5 * (s.outer - s.inner);
      return std::hypot(radial - R, along) - r;
    }
    case ShapeType::mesh:
      break;
  }
  return 1e300;  // meshes: RestShape below
}

// World bounding box of the shape (a sphere's box around the center when rotated): the
// sampler's rule, so an EoL grid and the MPM particles of a scene see the same extent.
inline void rest_bounds(const ShapeDesc& s, int dim, Vec3d& lo, Vec3d& hi) {
  shape_bounds(s, dim, lo, hi);
}

// One object's rest shape: the scene's shape, and for a mesh its sampled distance.
struct RestShape {
  ShapeDesc shape;
  std::shared_ptr<const MeshDistance> mesh;  // mesh shapes only (read-only, shared by clones)

  double distance(const Vec3d& x, int dim) const {
    return mesh ? (*mesh)(x) : rest_distance(shape, x, dim);
  }
  void bounds(int dim, Vec3d& lo, Vec3d& hi) const {
    if (!mesh) return rest_bounds(shape, dim, lo, hi);
    lo = mesh->lower();
    hi = mesh->upper();
  }
  // The centre c of the initial velocity V + ω × (x − c): the shape's centre, a mesh's box
  // centre, as the MPM sampler takes them.
  Vec3d center() const {
    if (!mesh) return shape.center;
    const Vec3d lo = mesh->lower(), hi = mesh->upper();
    return {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  }
};

// The rest shape of scene object `object`; a mesh is read (resolve_mesh_file, load_obj_mesh:
// SceneError when missing, open or non-manifold) and sampled for an EoL grid of cell `cell`.
RestShape make_rest_shape(const SceneDesc& scene, int object, double cell);

}  // namespace apiclab::eol
