#include "render/scene_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace apiclab::render {

std::vector<Vec3> plane_in_box(Vec3 p, Vec3 n, const Box3& box, int dim) {
  const int corners = dim == 2 ? 4 : 8;
  auto corner = [&](int i) {
    return Vec3{i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                i & 4 ? box.max.z : box.min.z};
  };
  const float eps = 1e-5f * std::max(length(box.size()), 1e-12f);
  std::vector<Vec3> points;
  auto add = [&](Vec3 q) {
    for (const Vec3& o : points)
      if (length(o - q) < eps) return;
    points.push_back(q);
  };
  for (int i = 0; i < corners; ++i) {
    float si = dot(corner(i) - p, n);
    if (std::abs(si) < eps) add(corner(i));
    for (int axis = 0; axis < dim; ++axis) {
      int j = i | (1 << axis);
      if (j == i) continue;
      float sj = dot(corner(j) - p, n);
      if ((si < -eps && sj > eps) || (si > eps && sj < -eps))
        add(corner(i) + (corner(j) - corner(i)) * (si / (si - sj)));
    }
  }
  if (points.size() < 3) return points;
  // Sort around the centroid in the plane.
  Vec3 c;
  for (const Vec3& q : points) c = c + q * (1.0f / float(points.size()));
  Vec3 u = normalize(points[0] - c), v = cross(normalize(n), u);
  std::sort(points.begin(), points.end(), [&](Vec3 a, Vec3 b) {
    return std::atan2(dot(a - c, v), dot(a - c, u)) < std::atan2(dot(b - c, v), dot(b - c, u));
  });
  return points;
}

}  // namespace apiclab::render
