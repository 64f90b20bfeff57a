// Algorithm 2 on the solver's objects: placed at frame times (Simulation::step's
// reached_frame_time), on contact (the surface rows), and on a copy for a snapshot between frames.
#pragma once
#include "sim/eol/eol_simulation.hpp"
#include "sim/eol/surface/surface_placement.hpp"

namespace apiclab::eol {

template <class T, int D>
void EolSimulation<T, D>::place_surface(EolObject<T, D>& o) {
  StageTimer timer{stages_.surface};
  o.surface_misses = eol::place_surface(o.grid, o.surface.X, o.surface_y, parallel_);
}

template <class T, int D>
void EolSimulation<T, D>::place_surfaces() {
  if (surfaces_placed_) return;
  for (auto& o : objects_) place_surface(o);
  surfaces_placed_ = true;
}

template <class T, int D>
std::vector<Vec<T, D>> EolSimulation<T, D>::placed_surface(const EolObject<T, D>& o) const {
  std::vector<Vec<T, D>> y = o.surface_y;
  if (!surfaces_placed_) eol::place_surface(o.grid, o.surface.X, y, parallel_);
  return y;
}

}  // namespace apiclab::eol
