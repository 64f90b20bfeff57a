// Explicit instantiation of the 2D solver in double, with the implicit-solve phases that tests
// call directly. One precision a file, so that a build compiles the four halves at once.
#include "sim/mpm/phases.hpp"

namespace apiclab {

#define APICLAB_INSTANTIATE(T, K)                                                               \
  template void MpmSimulation<T, 2>::implicit_begin<K>(T);                                      \
  template double MpmSimulation<T, 2>::implicit_energy<K>(const std::vector<Vec<T, 2>>&, bool); \
  template void MpmSimulation<T, 2>::implicit_hessian_apply<K>(const std::vector<Vec<T, 2>>&,   \
                                                               std::vector<Vec<T, 2>>&);

template class MpmSimulation<double, 2>;
APICLAB_INSTANTIATE(double, LinearKernel)
APICLAB_INSTANTIATE(double, QuadraticKernel)
APICLAB_INSTANTIATE(double, CubicKernel)

}  // namespace apiclab
