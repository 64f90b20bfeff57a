// The Eulerian-on-Lagrangian solver's material points at its own precision: what a sweep's
// distances read (app/sweep/record.cpp). The nodes that hold material change from frame to frame
// (material moves through the baseline's world grid, and through eol's grid as the body
// deforms), so the points are each object's surface vertices where Algorithm 2 places them: the
// same material points, in the same order, at every frame.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

namespace apiclab {

class Simulation;

struct MaterialPoints {
  std::vector<double> positions;     // dim values per point, world
  std::vector<std::int32_t> object;  // the scene object per point
};

// nullopt when `sim` is not an EoL or Eulerian simulation.
std::optional<MaterialPoints> eol_surface_points(const Simulation& sim);

}  // namespace apiclab
