// The Sec 6.8 round trip through the solver's own transfers: an MpmSimulation on the periodic
// [0, 2π]² grid runs its public G2P and P2G phases at Δt = 0.
#include "roundtrip.hpp"

#include <cmath>
#include <stdexcept>

#include "mpm.hpp"
#include "sampling.hpp"

namespace apiclab {

RoundTripResult roundtrip_error(KernelType kernel, Scheme scheme, int resolution,
                                std::uint64_t seed) {
  if (blends_flip(scheme))
    throw std::invalid_argument(
        "the round trip starts from the grid; FLIP and ASFLIP need prior particle velocities (use "
        "pic, apic, rpic, mls or xpic)");
  if (resolution < 4) throw std::invalid_argument("resolution must be at least 4");
  SceneDesc s;
  s.name = "roundtrip";
  s.dim = 2;
  s.domain.min = {0, 0, 0};
  s.domain.max = {2 * M_PI, 2 * M_PI, 0};
  s.domain.dx = 2 * M_PI / resolution;
  s.domain.walls.fill(BoundaryCondition::periodic);
  s.solver.scheme = scheme;
  s.solver.kernel = kernel;
  s.materials.emplace_back();  // particles name material 0; the probe never computes stress
  MpmSimulation<double, 2> sim(s);

  // Poisson disk particles (separation Δx/3), unit mass; G2P writes their v_p and C_p.
  const std::vector<Vec3d> points =
      poisson_disk(s.domain.min, s.domain.max, s.domain.dx / 3, 2, seed, true);
  Particles<double, 2>& p = sim.particles();
  p.resize(points.size());
  for (std::size_t q = 0; q < points.size(); ++q) {
    p.x[q] = Vec<double, 2>(points[q][0], points[q][1]);
    p.v[q].setZero();
    p.C[q].setZero();
    p.F[q].setIdentity();
    p.mass[q] = 1;
    p.volume0[q] = 0;
    p.material[q] = p.object[q] = 0;
    p.id[q] = std::int32_t(q);
  }
  sim.sort_particles();  // the phases run over the nodes the sorted particles reach

  // Grid velocity (1.1 sin x, 0.9 cos y) as both v_i^n and ṽ_i, then G2P with Δt = 0 (x_p and
  // F_p stay), then P2G (eqs 24, 26) and v_i = (mv)_i / m_i.
  Grid<double, 2>& g = sim.grid();
  std::vector<Vec<double, 2>> before(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    const Vec<double, 2> x = g.node_position(i);
    before[i] = Vec<double, 2>(1.1 * std::sin(x[0]), 0.9 * std::cos(x[1]));
    g.velocity[i] = g.velocity_new[i] = before[i];
  }
  sim.grid_to_particles(0.0);
  sim.clear_grid();
  sim.particles_to_grid(false);
  sim.grid_velocity_update(0.0);  // massless nodes get v_i = 0

  double err2 = 0;
  for (std::size_t i = 0; i < g.size(); ++i)
    err2 += (g.velocity[i] - before[i]).squaredNorm() * s.domain.dx * s.domain.dx;
  return {resolution, s.domain.dx, std::sqrt(err2), points.size()};
}

}  // namespace apiclab
