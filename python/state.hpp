// The particle state and grid of an MPM simulation as NumPy arrays (docs/python.md, The state).
#pragma once
#include <pybind11/pybind11.h>

#include <string>

#include "sim/simulation.hpp"

namespace apiclab::python {

// Read-only views of the particle arrays in storage order (no copies), kept alive by `owner`:
// x, v, F, C, mass, volume (V_p⁰), material, object, id. Throws ValueError for a method
// without particles.
pybind11::dict particle_views(Simulation& sim, pybind11::handle owner);
// Writes the given arrays (names as particle_views; storage order) between steps. Every array is
// checked before any is written: ValueError naming the array and the first bad particle.
void write_particles(Simulation& sim, const pybind11::dict& arrays);
// The parallel P2G's invariant for the current positions (MpmProbe::partition_conflict): "" or
// what breaks it; "" for a method without particles. For the tests.
std::string partition_conflict(Simulation& sim);
// The MPM grid's stored region as copies: origin, dx, mass, velocity (vⁿ), velocity_new (ṽ),
// indexed [i, j(, k)]; the dict is empty for a method without an MPM grid.
pybind11::dict mpm_grid(Simulation& sim);

}  // namespace apiclab::python
