// The energy ledger's terms (energy_ledger.hpp), taken around the stages of one object's step
// when record_energy_ledger is on: before the impulse, after it, after the transport.
#pragma once
#include "sim/eol/eol_simulation.hpp"

namespace apiclab::eol {

// K and G of one object as measure() counts them.
template <class T, int D>
typename EolSimulation<T, D>::LedgerEnergies EolSimulation<T, D>::ledger_energies(
    const EolObject<T, D>& o) const {
  LedgerEnergies e;
  for (std::size_t i = 0; i < o.grid.size(); ++i) {
    const double m = double(o.grid.mass[i]);
    if (!(m > 0)) continue;
    e.kinetic += 0.5 * m * double(o.u[i].squaredNorm());
    for (int a = 0; a < D; ++a) e.gravity -= m * scene_.gravity[std::size_t(a)] * double(o.x[i][a]);
    // Mass and momenta as measure() counts them, for the CSV's ledger columns.
    const Vec<T, D> mv = o.grid.mass[i] * o.u[i];
    e.moments.mass += m;
    for (int a = 0; a < D; ++a) e.moments.p[std::size_t(a)] += double(mv[a]);
    const Eigen::Vector3d L = cross_moment<T, D>(o.x[i], mv);
    for (int a = 0; a < 3; ++a) e.moments.L[std::size_t(a)] += L[a];
  }
  return e;
}

// Adds the forces' work Δt Σ f·u⁺ (u⁺ after the impulse and plane rows) to `step`, split into
// gravity m g, f_qvv (from the frame's ω and the v this step's forces saw) and elasticity, the
// rest of f. The impulse's loss is what the work leaves over ΔK (ledger_impulse).
template <class T, int D>
void EolSimulation<T, D>::ledger_work(const EolObject<T, D>& o, double dt,
                                      EnergyLedger& step) const {
  const Mat<T, D> R = o.frame.rotation();
  Vec<T, D> g;
  for (int a = 0; a < D; ++a) g[a] = T(scene_.gravity[std::size_t(a)]);
  for (std::size_t i = 0; i < o.grid.size(); ++i) {
    const T m = o.grid.mass[i];
    if (!(m > T(0))) continue;
    const Vec<T, D> fg = m * g;
    const Vec<T, D> fq = lagrangian_ ? quadratic_velocity_force<T, D>(m, o.frame.omega, o.r[i],
                                                                      Vec<T, D>(R * o.grid.v[i]))
                                     : Vec<T, D>::Zero();
    const Vec<T, D>& u = o.u[i];
    step.gravity_work += dt * double(fg.dot(u));
    step.qvv_work += dt * double(fq.dot(u));
    step.elastic_work += dt * double((o.force[i] - fg - fq).dot(u));
    const Vec<T, D> impulse = T(dt) * o.force[i];
    for (int a = 0; a < D; ++a) step.force_impulse.p[std::size_t(a)] += double(impulse[a]);
    const Eigen::Vector3d L = cross_moment<T, D>(o.x[i], impulse);
    for (int a = 0; a < 3; ++a) step.force_impulse.L[std::size_t(a)] += L[a];
  }
}

// Before the impulse: K and G, and Ψ of this state (its forces' pass) out of the elastic change.
template <class T, int D>
typename EolSimulation<T, D>::LedgerEnergies EolSimulation<T, D>::ledger_before(
    const EolObject<T, D>& o, EnergyLedger& step) const {
  step.elastic_change -= o.elastic.energy();
  return ledger_energies(o);
}

// After the impulse and plane rows, before the split changes the frame's ω: the forces' work,
// and the impulse's loss, what the work leaves over ΔK. Returns K and G there.
template <class T, int D>
typename EolSimulation<T, D>::LedgerEnergies EolSimulation<T, D>::ledger_impulse(
    const EolObject<T, D>& o, double dt, const LedgerEnergies& before, EnergyLedger& step) const {
  const double work_before = step.elastic_work + step.gravity_work + step.qvv_work;
  ledger_work(o, dt, step);
  const LedgerEnergies pushed = ledger_energies(o);
  const double work = step.elastic_work + step.gravity_work + step.qvv_work;
  step.impulse_loss += work - work_before - (pushed.kinetic - before.kinetic);
  step.impulse_change += pushed.moments - before.moments;
  return pushed;
}

// After the transport: its change of K, the change of G over the step, and Ψ of the moved state.
template <class T, int D>
void EolSimulation<T, D>::ledger_transport(const EolObject<T, D>& o, const LedgerEnergies& before,
                                           const LedgerEnergies& pushed, EnergyLedger& step) const {
  const LedgerEnergies after = ledger_energies(o);
  step.transport_kinetic_change += after.kinetic - pushed.kinetic;
  step.transport_change += after.moments - pushed.moments;
  step.gravity_change += after.gravity - before.gravity;
  step.elastic_change += elastic_energy_moved(o.grid, materials_);
}

}  // namespace apiclab::eol
