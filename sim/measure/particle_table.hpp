// The particles of one frame as named columns, ordered by id: what `--dump` writes in every
// format (CSV, VTK, PLY, OBJ; app/particle_export.*). One place names the columns, so the
// formats cannot disagree.
#pragma once
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace apiclab {

struct ParticleColumn {
  std::string name;                    // VTK array name: "velocity", "F", …
  std::vector<std::string> csv_names;  // one CSV header per component: "vx", "vy", …
  bool integer = false;                // id, object
  std::vector<double> values;          // count × components, particle-major
  int components() const { return int(csv_names.size()); }
};

struct ParticleTable {
  int dim = 2;
  int digits = 17;  // significant digits that round-trip the solver's scalar (max_digits10)
  std::size_t count = 0;
  std::vector<ParticleColumn> columns;  // id, object, position, velocity, mass, volume0, F, C
  // The column of that name, or nullptr.
  const ParticleColumn* find(const std::string& name) const;
};

// The --dump CSV (docs/outputs.md#particle-dumps---dump): `id,object,x,y[,z],vx,vy[,vz],mass,
// volume0,F..,C..`, one row per particle by id; its columns are a contract.
void write_particles_csv(std::ostream& out, const ParticleTable& table);

}  // namespace apiclab
