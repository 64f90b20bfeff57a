// The EoL solver in 2D, double precision.
#include "sim/eol/phases.hpp"

namespace apiclab::eol {
template class EolSimulation<double, 2>;
}  // namespace apiclab::eol
