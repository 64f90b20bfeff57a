// Explicit instantiations of the 2D solver, float and double.
#include "mpm_impl.hpp"

namespace apiclab {
template class MpmSimulation<float, 2>;
template class MpmSimulation<double, 2>;
}  // namespace apiclab
