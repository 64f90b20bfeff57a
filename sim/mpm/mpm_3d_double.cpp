// Explicit instantiation of the 3D solver in double, with the implicit-solve phases that tests
// call directly. One precision a file, so that a build compiles the four halves at once.
#include "sim/mpm/phases.hpp"

namespace apiclab {

#define APICLAB_INSTANTIATE(T, K)                                                               \
  template void MpmSimulation<T, 3>::implicit_begin<K>(T);                                      \
  template double MpmSimulation<T, 3>::implicit_energy<K>(const std::vector<Vec<T, 3>>&, bool); \
  template void MpmSimulation<T, 3>::implicit_hessian_apply<K>(const std::vector<Vec<T, 3>>&,   \
                                                               std::vector<Vec<T, 3>>&);

template class MpmSimulation<double, 3>;
APICLAB_INSTANTIATE(double, LinearKernel)
APICLAB_INSTANTIATE(double, QuadraticKernel)
APICLAB_INSTANTIATE(double, CubicKernel)

}  // namespace apiclab
