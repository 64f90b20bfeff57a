#include "sim/eol/shape/rest_shape.hpp"

#include "sim/geometry/obj_mesh.hpp"
#include "sim/geometry/sampling.hpp"

namespace apiclab::eol {

RestShape make_rest_shape(const SceneDesc& scene, int object, double cell) {
  RestShape r{scene.objects[std::size_t(object)].shape, nullptr};
  if (r.shape.type != ShapeType::mesh) return r;  // the scene reader checked it is in the domain
  const ObjMesh obj = load_obj_mesh(resolve_mesh_file(scene, object));
  check_mesh_placement(scene, object, MeshSolid(obj, r.shape));  // before sizing its lattice
  r.mesh = std::make_shared<const MeshDistance>(obj, r.shape, cell);
  return r;
}

}  // namespace apiclab::eol
