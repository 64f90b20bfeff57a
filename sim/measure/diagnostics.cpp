#include "sim/measure/diagnostics.hpp"

#include <iomanip>
#include <limits>

namespace apiclab {

void write_diagnostics_row(std::ostream& out, const DiagnosticsRow& r) {
  out << std::setprecision(std::numeric_limits<double>::max_digits10) << r.step << ',' << r.t << ','
      << r.dt << ',' << r.kinetic << ',' << r.kinetic_grid << ',' << r.potential << ',' << r.total
      << ',' << r.p[0] << ',' << r.p[1] << ',' << r.p[2] << ',' << r.L[0] << ',' << r.L[1] << ','
      << r.L[2] << ',' << r.newton_iters << ',' << r.cg_iters << ',' << r.residual << ','
      << std::setprecision(6) << r.wall_seconds << ',' << r.dt_limit << '\n';
}

}  // namespace apiclab
