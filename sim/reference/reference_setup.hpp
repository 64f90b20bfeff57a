// A scene and a solver's particles in the form of the readable reference step
// (sim/reference/reference_step.hpp): what tests/mpm/test_reference_step.cpp compares against and
// what `apiclab bench --reference` times on the same state. The reference step takes the first
// material only, no triangle meshes, and symplectic Euler.
#pragma once
#include <cmath>

#include "sim/mpm/particles.hpp"
#include "sim/reference/reference_step.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab::reference {

template <class T, int D>
Setup<T, D> setup_of(const SceneDesc& s) {
  Setup<T, D> r;
  for (int a = 0; a < D; ++a) {
    r.min[a] = T(s.domain.min[a]);
    r.cells[a] = int(std::lround((s.domain.max[a] - s.domain.min[a]) / s.domain.dx));
    r.gravity[a] = T(s.gravity[a]);
  }
  r.dx = T(s.domain.dx);
  for (int k = 0; k < 2 * D; ++k) r.walls[std::size_t(k)] = s.domain.walls[std::size_t(k)];
  for (const ColliderDesc& c : s.colliders) {
    if (c.type != ColliderType::plane)
      throw SceneError(s.source + ": the reference step takes collider planes only");
    Plane<T, D> plane;
    for (int a = 0; a < D; ++a) plane.point[a] = T(c.point[a]), plane.normal[a] = T(c.normal[a]);
    plane.condition = c.condition;
    r.colliders.push_back(plane);
  }
  r.scheme = s.solver.scheme;
  r.flip_alpha = T(s.solver.flip_alpha);
  r.asflip_beta = T(s.solver.asflip_beta);
  r.xpic_order = s.solver.xpic_order;
  r.kernel = s.solver.kernel;
  r.polypic_modes = s.solver.polypic_modes;
  r.model = s.materials[0].model;
  r.lame = {T(s.materials[0].mu()), T(s.materials[0].lambda())};
  return r;
}

template <class T, int D>
ParticleState<T, D> state_of(const Particles<T, D>& p) {
  ParticleState<T, D> r;
  r.x = p.x, r.v = p.v, r.C = p.C, r.F = p.F, r.mass = p.mass, r.volume = p.volume0;
  r.modes = p.modes;
  return r;
}

}  // namespace apiclab::reference
