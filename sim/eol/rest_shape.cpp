#include "sim/eol/rest_shape.hpp"

#include "sim/obj_mesh.hpp"
#include "sim/sampling.hpp"

namespace apiclab::eol {

RestShape make_rest_shape(const SceneDesc& scene, int object, double cell) {
  RestShape r{scene.objects[std::size_t(object)].shape, nullptr};
  if (r.shape.type != ShapeType::mesh) return r;  // the scene reader checked it is in the domain
  r.mesh = std::make_shared<const MeshDistance>(load_obj_mesh(resolve_mesh_file(scene, object)),
                                                r.shape, cell);
  for (std::size_t a = 0; a < std::size_t(scene.dim); ++a)  // as the MPM sampler (sampling.cpp)
    if (r.mesh->lower()[a] < scene.domain.min[a] || r.mesh->upper()[a] > scene.domain.max[a])
      throw SceneError(scene.source + ": key 'objects." + std::to_string(object) +
                       ".shape': mesh lies outside the domain on axis " + std::string(1, "xyz"[a]));
  return r;
}

}  // namespace apiclab::eol
