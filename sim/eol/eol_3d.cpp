// The EoL solver in 3D, double precision.
#include "sim/eol/phases.hpp"

namespace apiclab::eol {
template class EolSimulation<double, 3>;
}  // namespace apiclab::eol
