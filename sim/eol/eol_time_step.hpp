// Δt by the scene's rule (Sec 3.6, sim/eol/time_step.hpp): fixed, or the advection limit of
// eq 33 capped by the explicit elastic limit and time.dt.value, per object; the landing on the
// frame time is Simulation::step's.
#pragma once
#include <algorithm>
#include <limits>

#include "sim/eol/eol_simulation.hpp"

namespace apiclab::eol {

// The elastic cap's ν: time.dt.nu under the `elastic` rule, whose formula it is; MPM's `cfl` and
// `two-step` rules give ν for a particle-speed bound (rotating-disk's ν = 1), so there it is at
// most kElasticNu, the shipped EoL scenes' stable value.
inline double elastic_nu(const TimeDesc& tm) {
  return tm.rule == DtRule::elastic ? tm.nu : std::min(tm.nu, kElasticNu);
}

template <class T, int D>
double EolSimulation<T, D>::choose_dt() {
  if (!forces_ready_) forces_ahead();  // eq 31's v₁ = M⁻¹ f reads this step's forces
  const TimeDesc& tm = scene_.time;
  if (tm.rule == DtRule::fixed) {
    last_limit_ = DtLimit::fixed;
    return tm.dt;
  }
  StageTimer timer{stages_.split};
  double dt = tm.dt;
  last_limit_ = DtLimit::max;
  for (const auto& o : objects_) dt = object_dt(o, dt, last_limit_);
  if (implicit_elasticity() && objects_.size() > 1) {
    const double approach = objects_approach_limit();
    if (approach < dt) {
      dt = approach;
      last_limit_ = DtLimit::contact;
    }
  }
  return dt;
}

// One pass for eq 32's two fields u (v₀) and M⁻¹f (v₁): either their rates and max|u| (eulerian:
// v* is the field) or the sums of their splits (eq 23).
template <class T, int D>
typename EolSimulation<T, D>::DtSums EolSimulation<T, D>::dt_sums(const EolObject<T, D>& o) {
  const auto& mass = o.grid.mass;
  const double dx = double(o.grid.dx);
  return sum_node_blocks(o.grid.size(), parallel_, dt_partial_, [&](DtSums& acc, std::size_t i) {
    if (!(mass[i] > T(0))) return;
    const Vec<T, D> a = o.force[i] / mass[i];
    if (lagrangian_) {
      acc.split.template add<T>(o.r[i], {o.u[i], a});
    } else {
      acc.umax = std::max(acc.umax, double(o.u[i].norm()));
      acc.gamma0 = std::max(acc.gamma0, double(o.u[i].template lpNorm<1>()) / dx);
      acc.gamma1 = std::max(acc.gamma1, double(a.template lpNorm<1>()) / dx);
    }
  });
}

// Eq 32: v* = v₀* + Δt v₁*, each the split (eq 24) of its own field; eq 33's γ are maxima (the
// same in any order), so a plain parallel max. Also max|v₀*|, the speed through the grid.
template <class T, int D>
std::array<double, 3> EolSimulation<T, D>::split_rates(const EolObject<T, D>& o,
                                                       const DtSums& sums) const {
  const auto& mass = o.grid.mass;
  const double dx = double(o.grid.dx);
  const std::array<FrameVec<T, D>, 2> q = sums.split.template solve<T>();
  const Mat<T, D> Rt = o.frame.rotation().transpose();
  const std::ptrdiff_t n = std::ptrdiff_t(o.grid.size());
  double g0 = 0, g1 = 0, speed = 0;
#pragma omp parallel for reduction(max : g0, g1, speed) if (parallel_)
  for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
    const std::size_t i = std::size_t(ii);
    if (!(mass[i] > T(0))) continue;
    const Vec<T, D> a = o.force[i] / mass[i];
    const Vec<T, D> v0 = eulerian_velocity<T, D>(o.u[i], o.r[i], q[0], Rt);
    const Vec<T, D> v1 = eulerian_velocity<T, D>(a, o.r[i], q[1], Rt);
    g0 = std::max(g0, double(v0.template lpNorm<1>()) / dx);
    g1 = std::max(g1, double(v1.template lpNorm<1>()) / dx);
    speed = std::max(speed, double(v0.norm()));
  }
  return {g0, g1, speed};
}

// dt lowered to this object's advection limit (eq 33) and explicit elastic limit
// ν Δx / (c + max|v*|), with the bound that set it. v* is the velocity through the object's own
// grid (u itself on the Eulerian baseline's world grid), so the frame's motion does not count:
// a step is the same at any constant velocity (Galilean invariance).
template <class T, int D>
double EolSimulation<T, D>::object_dt(const EolObject<T, D>& o, double dt, DtLimit& limit) {
  const DtSums sums = dt_sums(o);
  const std::array<double, 3> rates =
      lagrangian_ ? split_rates(o, sums)
                  : std::array<double, 3>{sums.gamma0, sums.gamma1, sums.umax};
  const double advection = advection_limit(rates[0], rates[1], scene_.solver.eol.alpha);
  // Backward Euler's elasticity has no stability cap: only eq 33 and 1/fps bind. Kelvin–Voigt
  // damping stays explicit in both modes: a diffusion of v, stable for Δt ≤ ρ Δx²/(4 d η),
  // here with ν of it as for the waves (reported as `elastic`: the material's stress).
  const double nu = elastic_nu(scene_.time), dx = double(o.grid.dx);
  const double viscous = max_kinematic_viscosity_ > 0
                             ? nu * dx * dx / (2.0 * D * max_kinematic_viscosity_)
                             : std::numeric_limits<double>::infinity();
  const double elastic = std::min(implicit_elasticity() ? std::numeric_limits<double>::infinity()
                                                        : nu * dx / (max_wave_speed_ + rates[2]),
                                  viscous);
  if (advection < dt) {
    dt = advection;
    limit = DtLimit::advection;
  }
  if (elastic < dt) {
    dt = elastic;
    limit = DtLimit::elastic;
  }
  if (implicit_elasticity()) {
    const double approach = approach_limit(o);
    if (approach < dt) {
      dt = approach;
      limit = DtLimit::contact;
    }
  }
  return dt;
}

// Under implicit elasticity: the step that carries no node with mass more than α Δx into a wall
// or collider at its velocity now. Eq 33 reads v before the contact solve, so it cannot see a
// contact coming: eol-drop's frame-long steps in free fall (v* = 0) met the floor 6 cells deep
// and blew up in the next step.
template <class T, int D>
double EolSimulation<T, D>::approach_limit(const EolObject<T, D>& o) const {
  double dt = std::numeric_limits<double>::infinity();
  const double reach = scene_.solver.eol.alpha * double(o.grid.dx);
  for (const auto& pl : planes_) {
    const Vec<T, D> point = pl.start + T(time_) * pl.velocity;
    const Vec<T, D>& at = pl.velocity.isZero(T(0)) ? pl.point : point;
    for (std::size_t i = 0; i < o.grid.size(); ++i) {
      if (!(o.grid.mass[i] > T(0))) continue;
      const double speed = -double((o.u[i] - pl.velocity).dot(pl.normal));
      if (!(speed > 0)) continue;
      const double gap = std::max(double((o.x[i] - at).dot(pl.normal)), 0.0);
      dt = std::min(dt, (gap + reach) / speed);
    }
  }
  return dt;
}

// Under implicit elasticity, between objects as approach_limit against planes: the step that
// closes the gap between two objects' material boxes (nodes with mass, world axes), less the
// 2 Δx by which their surfaces may be closer, by no more than a tenth of a cell beyond it, at the
// fastest approach along the line between their centres (the largest speed of A's nodes towards
// B less the smallest of B's towards A: Galilean invariant).
// Eq 33 reads v* only, zero for balls in flight: the two balls' frame-long steps met 6 cells deep.
template <class T, int D>
double EolSimulation<T, D>::objects_approach_limit() const {
  struct Extent {
    Vec<T, D> lo, hi, centre;
    double mass = 0, dx = 0;
  };
  std::vector<Extent> ext(objects_.size());
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    const auto& o = objects_[k];
    Extent& e = ext[k];
    e.lo.setConstant(std::numeric_limits<T>::infinity());
    e.hi.setConstant(-std::numeric_limits<T>::infinity());
    e.centre.setZero();
    e.dx = double(o.grid.dx);
    for (std::size_t i = 0; i < o.grid.size(); ++i) {
      const T m = o.grid.mass[i];
      if (!(m > T(0))) continue;
      e.lo = e.lo.cwiseMin(o.x[i]);
      e.hi = e.hi.cwiseMax(o.x[i]);
      e.centre += m * o.x[i];
      e.mass += double(m);
    }
    if (e.mass > 0) e.centre /= T(e.mass);
  }
  // The largest velocity component of object k along n over its nodes with mass.
  auto fastest = [&](std::size_t k, const Vec<T, D>& n) {
    double top = -std::numeric_limits<double>::infinity();
    const auto& o = objects_[k];
    for (std::size_t i = 0; i < o.grid.size(); ++i)
      if (o.grid.mass[i] > T(0)) top = std::max(top, double(o.u[i].dot(n)));
    return top;
  };
  double dt = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < objects_.size(); ++a)
    for (std::size_t b = a + 1; b < objects_.size(); ++b) {
      if (!(ext[a].mass > 0) || !(ext[b].mass > 0)) continue;
      Vec<T, D> n = ext[b].centre - ext[a].centre;
      if (!(n.norm() > T(0))) continue;
      n.normalize();
      const double speed = fastest(a, n) + fastest(b, Vec<T, D>(-n));
      if (!(speed > 0)) continue;
      const Vec<T, D> gap =
          (ext[b].lo - ext[a].hi).cwiseMax(ext[a].lo - ext[b].hi).cwiseMax(Vec<T, D>::Zero());
      // A surface lies within a cell of its nodes with mass, so the surfaces may be 2 Δx closer
      // than the boxes; the step then reaches a tenth of a cell past them. Reaching α Δx, the
      // two balls' first step with pair rows started 1.6 cells of area deep (Δx 0.0125).
      const double cell = std::min(ext[a].dx, ext[b].dx);
      dt = std::min(dt, (std::max(double(gap.norm()) - 2 * cell, 0.0) + 0.1 * cell) / speed);
    }
  return dt;
}

}  // namespace apiclab::eol
