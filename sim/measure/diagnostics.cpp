#include "sim/measure/diagnostics.hpp"

#include <iomanip>
#include <limits>

namespace apiclab {

ConservedSums& ConservedSums::operator+=(const ConservedSums& o) {
  mass += o.mass;
  for (int a = 0; a < 3; ++a) {
    p[a] += o.p[a];
    L[a] += o.L[a];
  }
  energy += o.energy;
  return *this;
}

ConservedSums operator-(ConservedSums a, const ConservedSums& b) {
  a.mass -= b.mass;
  for (int k = 0; k < 3; ++k) {
    a.p[k] -= b.p[k];
    a.L[k] -= b.L[k];
  }
  a.energy -= b.energy;
  return a;
}

const char* ledger_stage_name(LedgerStage s) {
  static const char* const names[ledger_stage_count] = {"p2g",       "forces", "walls",
                                                        "colliders", "g2p",    "move"};
  return names[int(s)];
}

std::string diagnostics_header(bool ledger) {
  std::string h = diagnostics_header();
  if (!ledger) return h;
  for (int s = 0; s < ledger_stage_count; ++s) {
    const std::string stage = ledger_stage_name(LedgerStage(s));
    for (const char* q : {"dm", "dpx", "dpy", "dpz", "dLx", "dLy", "dLz", "dE"})
      h += "," + stage + "_" + q;
  }
  return h;
}

void write_diagnostics_row(std::ostream& out, const DiagnosticsRow& r) {
  out << std::setprecision(std::numeric_limits<double>::max_digits10) << r.step << ',' << r.t << ','
      << r.dt << ',' << r.kinetic << ',' << r.kinetic_grid << ',' << r.potential << ',' << r.total
      << ',' << r.p[0] << ',' << r.p[1] << ',' << r.p[2] << ',' << r.L[0] << ',' << r.L[1] << ','
      << r.L[2] << ',' << r.newton_iters << ',' << r.cg_iters << ',' << r.residual << ','
      << std::setprecision(6) << r.wall_seconds << ',' << r.dt_limit;
  if (r.ledger) {
    out << std::setprecision(std::numeric_limits<double>::max_digits10);
    for (const ConservedSums& c : r.stages)
      out << ',' << c.mass << ',' << c.p[0] << ',' << c.p[1] << ',' << c.p[2] << ',' << c.L[0]
          << ',' << c.L[1] << ',' << c.L[2] << ',' << c.energy;
  }
  out << '\n';
}

}  // namespace apiclab
