// Explicit instantiations of the 3D solver, float and double.
#include "mpm_impl.hpp"

namespace apiclab {
template class MpmSimulation<float, 3>;
template class MpmSimulation<double, 3>;
}  // namespace apiclab
