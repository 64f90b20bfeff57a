// Explicit instantiation of the 3D solver in float. One precision a file, so that a build compiles
// the four halves at once.
#include "sim/mpm/phases.hpp"

namespace apiclab {

template class MpmSimulation<float, 3>;

}  // namespace apiclab
