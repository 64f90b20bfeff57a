#include "sim/geometry/object_overlap.hpp"

#include <memory>
#include <optional>

#include "sim/geometry/sampling.hpp"

namespace apiclab {
namespace {

struct Bounds {
  Vec3d lo, hi;
};

bool boxes_meet(const Bounds& a, const Bounds& b, int dim) {
  for (int k = 0; k < dim; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;
}

}  // namespace

std::vector<std::string> object_overlaps(const SceneDesc& scene) {
  const int n = int(scene.objects.size()), dim = scene.dim;
  std::vector<std::string> out;
  if (n < 2) return out;
  const std::size_t count = scene.objects.size();
  std::vector<std::unique_ptr<MeshSolid>> meshes(count);
  std::vector<Bounds> bounds(count);
  for (int o = 0; o < n; ++o) {
    const ShapeDesc& s = scene.objects[size_t(o)].shape;
    if (s.type == ShapeType::mesh) {
      meshes[size_t(o)] = load_mesh_solid(scene, o);
      bounds[size_t(o)] = {meshes[size_t(o)]->lower(), meshes[size_t(o)]->upper()};
    } else if (s.type == ShapeType::box &&
               scene.objects[size_t(o)].sampling.type == SamplingType::triangulated) {
      bounds[size_t(o)] = {s.min, s.max};
    } else {
      shape_bounds(s, dim, bounds[size_t(o)].lo, bounds[size_t(o)].hi);
    }
  }
  auto inside = [&](int o, const Vec3d& x) {
    const ShapeDesc& s = scene.objects[size_t(o)].shape;
    return meshes[size_t(o)] ? meshes[size_t(o)]->inside(x) : inside_shape(s, x, dim);
  };
  // Particle positions of an object, sampled once when first needed.
  std::vector<std::optional<std::vector<Vec3d>>> samples(count);
  auto particles = [&](int o) -> const std::vector<Vec3d>& {
    auto& p = samples[size_t(o)];
    if (!p) {
      const ObjectDesc& obj = scene.objects[size_t(o)];
      if (obj.sampling.type == SamplingType::triangulated) {
        // The vertex lattice of the triangulated box (sim/mpm/mpm_setup.hpp).
        p.emplace();
        const double h = obj.sampling.spacing;
        const int nx = std::max(1, int(std::lround((obj.shape.max[0] - obj.shape.min[0]) / h)));
        const int ny = std::max(1, int(std::lround((obj.shape.max[1] - obj.shape.min[1]) / h)));
        for (int j = 0; j <= ny; ++j)
          for (int i = 0; i <= nx; ++i)
            p->push_back({obj.shape.min[0] + i * (obj.shape.max[0] - obj.shape.min[0]) / nx,
                          obj.shape.min[1] + j * (obj.shape.max[1] - obj.shape.min[1]) / ny, 0});
      } else {
        p = sample_object(scene, o).positions;
      }
    }
    return *p;
  };
  auto count_inside = [&](int a, int b) {
    std::size_t k = 0;
    for (const Vec3d& x : particles(a)) {
      bool in_box = true;
      for (int d = 0; d < dim; ++d)
        in_box = in_box && x[d] >= bounds[size_t(b)].lo[d] && x[d] <= bounds[size_t(b)].hi[d];
      if (in_box && inside(b, x)) ++k;
    }
    return k;
  };
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      if (!boxes_meet(bounds[size_t(a)], bounds[size_t(b)], dim)) continue;
      const std::size_t ab = count_inside(a, b), ba = count_inside(b, a);
      if (ab == 0 && ba == 0) continue;
      const std::string& na = scene.objects[size_t(a)].name;
      const std::string& nb = scene.objects[size_t(b)].name;
      out.push_back("objects '" + na + "' and '" + nb + "' overlap: " + std::to_string(ab) +
                    " of " + na + "'s " + std::to_string(particles(a).size()) +
                    " particles lie inside " + nb + ", " + std::to_string(ba) + " of " + nb +
                    "'s " + std::to_string(particles(b).size()) + " inside " + na +
                    " (the overlap starts compressed)");
    }
  return out;
}

}  // namespace apiclab
