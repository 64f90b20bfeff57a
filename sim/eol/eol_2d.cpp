// The EoL solver in 2D, double precision.
#include "sim/eol/eol_simulation_impl.hpp"
#include "sim/eol/eol_snapshot.hpp"

namespace apiclab::eol {
template class EolSimulation<double, 2>;
}  // namespace apiclab::eol
