// The reference step as a ReferenceRun (sim/simulation.hpp) on a copy of an MPM solver's
// particles: what `apiclab bench --reference` times against the fast step on the same state.
#pragma once
#include <memory>

#include "sim/mpm/particles.hpp"
#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"

namespace apiclab::reference {

// Compiled once, with the reference step, in sim/reference/reference_step.cpp.
template <class T, int D>
std::unique_ptr<ReferenceRun> run_of(const SceneDesc& scene, const Particles<T, D>& p);

}  // namespace apiclab::reference
