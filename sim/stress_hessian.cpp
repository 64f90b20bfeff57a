// The explicit instantiations that sim/stress_hessian.hpp declares extern.
#include "stress_hessian.hpp"

namespace apiclab {

APICLAB_STRESS_HESSIAN(, float, 2)
APICLAB_STRESS_HESSIAN(, float, 3)
APICLAB_STRESS_HESSIAN(, double, 2)
APICLAB_STRESS_HESSIAN(, double, 3)

}  // namespace apiclab
