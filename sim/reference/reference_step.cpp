// The readable reference step (sim/reference/reference_step.hpp), compiled once for 2D and 3D in
// float and double, at the solver's optimisation: the bench compares the two steps built alike.
#include "sim/reference/reference_step.hpp"

namespace apiclab::reference {

template void step<float, 2>(const Setup<float, 2>&, ParticleState<float, 2>&, float);
template void step<double, 2>(const Setup<double, 2>&, ParticleState<double, 2>&, double);
template void step<float, 3>(const Setup<float, 3>&, ParticleState<float, 3>&, float);
template void step<double, 3>(const Setup<double, 3>&, ParticleState<double, 3>&, double);

}  // namespace apiclab::reference
