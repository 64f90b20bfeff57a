// Explicit instantiation of the 2D solver in float. One precision a file, so that a build compiles
// the four halves at once.
#include "sim/mpm/phases.hpp"

namespace apiclab {

template class MpmSimulation<float, 2>;

}  // namespace apiclab
