// The EoL solver in 3D, double precision.
#include "sim/eol/eol_simulation_impl.hpp"
#include "sim/eol/eol_snapshot.hpp"

namespace apiclab::eol {
template class EolSimulation<double, 3>;
}  // namespace apiclab::eol
