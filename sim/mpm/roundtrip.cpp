// The Sec 6.8 round trip through the solver's own transfers: an MpmSimulation on the periodic
// [0, 2π]² grid runs its G2P and P2G phases at Δt = 0 through MpmProbe.
#include "sim/mpm/roundtrip.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/geometry/sampling.hpp"
#include "sim/mpm/probe.hpp"

namespace apiclab {

std::string roundtrip_refusal(Scheme scheme) {
  if (!blends_flip(scheme)) return "";
  std::string others;
  for (const auto& c : scheme_choices())
    if (!blends_flip(c.value)) others += (others.empty() ? "" : ", ") + std::string(c.key);
  return "the round trip starts from the grid; FLIP and ASFLIP need prior particle velocities "
         "(use " +
         others + ")";
}

RoundTripResult roundtrip_error(KernelType kernel, Scheme scheme, int resolution,
                                std::uint64_t seed, int xpic_order) {
  if (const std::string why = roundtrip_refusal(scheme); !why.empty())
    throw std::invalid_argument(why);
  if (resolution < 4) throw std::invalid_argument("resolution must be at least 4");
  if (xpic_order < 1) throw std::invalid_argument("the XPIC order must be at least 1");
  SceneDesc s;
  s.name = "roundtrip";
  s.dim = 2;
  s.domain.min = {0, 0, 0};
  s.domain.max = {2 * M_PI, 2 * M_PI, 0};
  s.domain.dx = 2 * M_PI / resolution;
  s.domain.walls.fill(BoundaryCondition::periodic);
  s.solver.scheme = scheme;
  s.solver.kernel = kernel;
  s.solver.xpic_order = xpic_order;
  s.materials.emplace_back();  // particles name material 0; the probe never computes stress
  MpmSimulation<double, 2> sim(s);
  MpmProbe probe(sim);

  // Poisson disk particles (separation Δx/3), unit mass; G2P writes their v_p and C_p.
  const std::vector<Vec3d> points =
      poisson_disk(s.domain.min, s.domain.max, s.domain.dx / 3, 2, seed, true);
  Particles<double, 2>& p = probe.particles();
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
  probe.sort_particles();  // the phases run over the nodes the sorted particles reach
  // The node masses m_i = Σ w m_p (eq 24) of these particles before G2P, as a step has them:
  // XPIC's grid passes (A = S⁺S, sim/mpm/schemes/xpic_passes.hpp) read them; the other schemes' G2P
  // does not. The P2G velocity is zero (v_p = 0) and is overwritten below.
  probe.clear_grid();
  probe.particles_to_grid(false);

  // Grid velocity (1.1 sin x, 0.9 cos y) as both v_i^n and ṽ_i, then G2P with Δt = 0 and P2G
  // (MpmProbe::transfer_once). XPIC(m) then returns (I − (I − A)^m) v: its series needs only vⁿ
  // and the masses, not prior particle velocities.
  const Grid<double, 2>& g = probe.grid();
  std::vector<Vec<double, 2>> before(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    const Vec<double, 2> x = g.node_position(i);
    before[i] = Vec<double, 2>(1.1 * std::sin(x[0]), 0.9 * std::cos(x[1]));
  }
  probe.transfer_once(before);

  double err2 = 0;
  for (std::size_t i = 0; i < g.size(); ++i)
    err2 += (g.velocity[i] - before[i]).squaredNorm() * s.domain.dx * s.domain.dx;
  return {resolution, s.domain.dx, std::sqrt(err2), points.size()};
}

}  // namespace apiclab
