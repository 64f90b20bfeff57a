// Energies, momenta and sizes from the grid fields (the diagnostics CSV's columns).
#pragma once
#include <cmath>

#include "sim/eol/eol_simulation.hpp"

namespace apiclab::eol {

template <class T, int D>
double EolSimulation<T, D>::elastic_energy() const {
  double e = 0;
  for (const auto& o : objects_)
    e += forces_ready_ ? o.elastic.energy() : elastic_energy_moved(o.grid, materials_);
  return e;
}

template <class T, int D>
double EolSimulation<T, D>::occupied_volume() const {
  double v = 0;
  for (const auto& o : objects_) {
    double fill = 0;
    for (T h : o.grid.fill) fill += double(h);
    v += fill * std::pow(double(o.grid.dx), D);
  }
  return v;
}

template <class T, int D>
double EolSimulation<T, D>::total_mass() const {
  double m = 0;
  for (const auto& o : objects_)
    for (T x : o.grid.mass) m += double(x);
  return m;
}

// Kinetic ½ Σ m|u|², elastic Σ V₀ Ψ, gravity −Σ m g·x, p = Σ m u, L = Σ x × m u about the origin.
template <class T, int D>
DiagnosticsRow EolSimulation<T, D>::measure() const {
  DiagnosticsRow r;
  r.step = steps_;
  r.t = time_;
  double kin = 0, grav = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), L = Eigen::Vector3d::Zero();
  for (const auto& o : objects_)
    for (std::size_t i = 0; i < o.grid.size(); ++i) {
      const T m = o.grid.mass[i];
      if (!(m > T(0))) continue;
      const Vec<T, D> mv = m * o.u[i];
      kin += 0.5 * double(m) * double(o.u[i].squaredNorm());
      for (int a = 0; a < D; ++a) {
        p[a] += double(mv[a]);
        grav -= double(m) * scene_.gravity[std::size_t(a)] * double(o.x[i][a]);
      }
      L += cross_moment<T, D>(o.x[i], mv);
    }
  r.kinetic = kin;
  r.kinetic_grid = kin;
  r.elastic = elastic_energy();
  r.potential = r.elastic + grav;
  r.total = r.kinetic + r.potential;
  r.p = {p[0], p[1], p[2]};
  r.L = {L[0], L[1], L[2]};
  r.dt_limit = dt_limit_name(last_limit_);
  r.contact_pairs = int(object_pairs_.size());
  r.ledger = scene_.solver.ledger;  // its stages are the step's (step_fixed_measured)
  if (implicit_elasticity()) {
    r.newton_iters = implicit_report_.newton_iterations;
    r.cg_iters = implicit_report_.cg_iterations;
    r.residual = implicit_report_.residual;
  }
  for (const auto& o : objects_) {
    r.grid_nodes += double(o.grid.size());
    r.grid_bytes += double(o.grid_bytes());
  }
  return r;
}

}  // namespace apiclab::eol
