// The Eulerian-on-Lagrangian solver's material nodes at its own precision, in the order its
// snapshot lists them: what a sweep's distances read (app/sweep/record.cpp).
#pragma once
#include <optional>
#include <vector>

namespace apiclab {

class Simulation;

// dim values per node (each object's nodes the rest shape covers, as the snapshot shows them);
// nullopt when `sim` is not an EoL or Eulerian simulation.
std::optional<std::vector<double>> eol_node_positions(const Simulation& sim);

}  // namespace apiclab
