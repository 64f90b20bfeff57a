#include "sim/measure/particle_table.hpp"

#include <iomanip>

namespace apiclab {

const ParticleColumn* ParticleTable::find(const std::string& name) const {
  for (const ParticleColumn& c : columns)
    if (c.name == name) return &c;
  return nullptr;
}

void write_particles_csv(std::ostream& out, const ParticleTable& table) {
  bool first = true;
  for (const ParticleColumn& c : table.columns)
    for (const std::string& h : c.csv_names) {
      out << (first ? "" : ",") << h;
      first = false;
    }
  out << '\n' << std::setprecision(table.digits);
  for (std::size_t q = 0; q < table.count; ++q) {
    first = true;
    for (const ParticleColumn& c : table.columns)
      for (int k = 0; k < c.components(); ++k) {
        const double v = c.values[q * std::size_t(c.components()) + std::size_t(k)];
        out << (first ? "" : ",");
        if (c.integer)
          out << static_cast<long long>(v);
        else
          out << v;
        first = false;
      }
    out << '\n';
  }
}

}  // namespace apiclab
