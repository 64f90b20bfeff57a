// What a node carries from X and v: the fill, owner, material and lumped mass (eq 6), and the
// spatial state r, x, u of eqs 1-4.
#pragma once
#include <algorithm>
#include <cmath>

#include "sim/eol/eol_simulation.hpp"
#include "sim/eol/shape/rest_shape.hpp"

namespace apiclab::eol {

template <class T, int D>
double grid_mass(const EulerianGrid<T, D>& g) {
  double total = 0;
  for (T m : g.mass) total += double(m);
  return total;
}

template <class T, int D>
void EolSimulation<T, D>::update_mass(EolObject<T, D>& o) {
  forces_ready_ = false;
  update_mass(o, false);
}

// after_extrapolation: only the nodes without mass changed X since the last call (extrapolation
// writes nothing else), so only they and the cells touching them are evaluated again.
template <class T, int D>
void EolSimulation<T, D>::update_mass(EolObject<T, D>& o, bool after_extrapolation) {
  EulerianGrid<T, D>& g = o.grid;
  const std::ptrdiff_t n = std::ptrdiff_t(g.size());
#pragma omp parallel for if (parallel_)
  for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
    const std::size_t i = std::size_t(ii);
    if (after_extrapolation && g.mass[i] > T(0)) continue;
    Vec3d X{0, 0, 0};
    for (int a = 0; a < D; ++a) X[std::size_t(a)] = double(g.X[i][a]);
    double best = 1e300;
    int owner = -1;
    for (int s : o.shapes) {
      const double phi = rest_[std::size_t(s)].distance(X, D);
      if (phi < best) {
        best = phi;
        owner = s;
      }
    }
    const T fill = std::isfinite(best) ? smoothed_inside<T>(best, double(g.dx)) : T(0);
    g.fill[i] = fill;
    o.owner[i] = fill > T(0) ? owner : -1;
    g.material[i] = fill > T(0) ? scene_.objects[std::size_t(owner)].material : -1;
  }
  o.elastic.lumped_mass(g, density_, g.mass, parallel_, after_extrapolation ? &g.mass : nullptr);
  if (!lagrangian_) {
    if (o.rest_mass == 0) o.rest_mass = grid_mass(g);  // the set-up's, slivers included
    drop_sliver_masses(o);
    keep_rest_mass(o);
  }
}

// Multilinear ∇N stays finite where N → 0, so a node holding a sliver of a cell's mass gets a
// stiffness to mass ratio without bound, and no explicit Δt is stable for every place a surface
// can cut a cell; a body carried across the baseline's world grid sweeps every cut. Nodes under
// this share of a full node's mass count as empty (their X and v extrapolated); the share is
// chosen in docs/eol.md's departures. (eol's grid rides with the body: its cuts stay.)
constexpr double kSliverMassShare = 0.003;

template <class T, int D>
void EolSimulation<T, D>::drop_sliver_masses(EolObject<T, D>& o) const {
  double density = 0;  // a node outside the surface has mass (its neighbours') and no material
  for (int s : o.shapes)
    density =
        std::max(density, double(density_[std::size_t(scene_.objects[std::size_t(s)].material)]));
  const T floor = T(kSliverMassShare * density * std::pow(double(o.grid.dx), D));
  for (T& m : o.grid.mass)
    if (m < floor) m = T(0);
}

// Eq 6's M₂ = ∫ ρ₀ det(∇X) H(φ₀(X)) dy = ∫ ρ₀ H(φ₀(X)) dX is the same for every X, but its
// quadrature (H sampled at the nodes, faded over one cell) depends on where the surface cuts the
// cells: a body crossing the world grid gains and loses up to 0.5 % of its mass once per cell,
// and its momentum and kinetic energy with it. So the baseline scales its node masses to the
// set-up's total. (eol's grid rides with the body, so there the cut barely moves.)
template <class T, int D>
void EolSimulation<T, D>::keep_rest_mass(EolObject<T, D>& o) {
  const double total = grid_mass(o.grid);
  if (!(total > 0) || total == o.rest_mass) return;
  const T scale = T(o.rest_mass / total);
  for (T& m : o.grid.mass) m *= scale;
}

template <class T, int D>
void EolSimulation<T, D>::spatial_state(EolObject<T, D>& o) {
  forces_ready_ = false;
  update_spatial(o);
}

// r = R y, x = r + p, u = ν + ω × r + R v (eqs 1-4).
template <class T, int D>
void EolSimulation<T, D>::update_spatial(EolObject<T, D>& o) const {
  const Mat<T, D> R = o.frame.rotation();
  for (std::size_t i = 0; i < o.grid.size(); ++i) {
    o.r[i] = R * o.grid.y(i);
    o.x[i] = o.r[i] + o.frame.p;
    o.u[i] = o.frame.nu + spin_cross<T, D>(o.frame.omega, o.r[i]) + R * o.grid.v[i];
  }
}

}  // namespace apiclab::eol
