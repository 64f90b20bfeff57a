// The Eulerian-on-Lagrangian family as registered methods (Fan et al. 2013): `eol` (a rigid
// frame and a grid per object) and `eulerian` (the baseline: the frame locked to the world, each
// object's grid over the domain), with the validation of their keys in the scene's `solver`
// section.
#include "sim/eol/eol_positions.hpp"
#include "sim/eol/eol_simulation.hpp"
#include "sim/method_registry.hpp"
#include "sim/scene/memory_estimate.hpp"

namespace apiclab {
namespace {

// Double precision only: the split and the affine-exact advection are tested to round-off.
std::unique_ptr<Simulation> make_eol_family(const SceneDesc& scene, bool lagrangian) {
  check_memory(scene, Precision::dbl);  // before the object grids are allocated
  if (scene.dim == 2) return std::make_unique<eol::EolSimulation<double, 2>>(scene, lagrangian);
  return std::make_unique<eol::EolSimulation<double, 3>>(scene, lagrangian);
}

// The words and numbers are read by now (the registries' keys of each method); ranges are checked
// once, for every method, by validate() (sim/scene/parameters.hpp).
void validate_eol_family(SceneSection&, SceneDesc& s) {
  for (int a = 0; a < s.dim; ++a)
    if (s.domain.periodic(a))
      throw SceneError(s.source + ": key 'domain.boundary': the " + s.solver.method +
                       " solver has no periodic walls");
}

// Algorithm 2 places the surfaces at every frame time (reached_frame_time): at a frame, the last
// placement is the frame's.
template <int D>
MaterialPoints surface_points(const eol::EolSimulation<double, D>& sim) {
  MaterialPoints p;
  for (const auto& o : sim.objects()) {
    for (std::size_t s = 0; s < o.surface_y.size(); ++s) {
      const Vec<double, D> x = o.surface_world(s);
      for (int a = 0; a < D; ++a) p.positions.push_back(x[a]);
      p.object.push_back(o.surface.owner[s]);
    }
  }
  return p;
}

}  // namespace

std::optional<MaterialPoints> eol_surface_points(const Simulation& sim) {
  if (const auto* s = dynamic_cast<const eol::EolSimulation<double, 2>*>(&sim))
    return surface_points(*s);
  if (const auto* s = dynamic_cast<const eol::EolSimulation<double, 3>*>(&sim))
    return surface_points(*s);
  return std::nullopt;
}

SolverMethod eol_method() {
  return {"eol",
          "Eulerian-on-Lagrangian: a rigid frame and an Eulerian grid per object, least-squares "
          "split (Fan et al. 2013)",
          [](const SceneDesc& s, Precision) { return make_eol_family(s, true); },
          validate_eol_family};
}

SolverMethod eulerian_method() {
  return {"eulerian",
          "pure-Eulerian baseline of Fan et al. 2013: the EoL solver with the frame locked to the "
          "world, one grid over the domain per object",
          [](const SceneDesc& s, Precision) { return make_eol_family(s, false); },
          validate_eol_family};
}

}  // namespace apiclab
