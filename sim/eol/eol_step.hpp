// One step of Algorithm 1 after the forces and Δt, per object: impulse and contact (eqs 16,
// 27-29) → least-squares split (eqs 23-24) → q₁ += Δt q̇₁ → X and v advected by v* (eq 15) →
// extrapolation and mass; then step()'s failure check. Objects whose material boxes meet take
// the impulse first, then one contact QP together, then each its split and transport. The
// skeleton is Simulation::step.
#pragma once
#include <utility>

#include "sim/eol/eol_simulation.hpp"
#include "sim/eol/grid/advection.hpp"
#include "sim/eol/least_squares_split.hpp"
#include "sim/scene/parameters.hpp"

namespace apiclab::eol {

template <class T, int D>
void EolSimulation<T, D>::step_fixed(double dt) {
  if (!forces_ready_) forces_ahead();
  if (implicit_elasticity()) implicit_forces(dt);
  finish_step(dt);
  plastic_flow();
  // The next step's forces now, from the state they would see then; their Ψ gives the
  // diagnostics' elastic energy without another pass over the cells.
  forces_ahead();
}

template <class T, int D>
void EolSimulation<T, D>::finish_step(double dt) {
  forces_ready_ = false;
  EnergyLedger ledger;
  ledger.steps = 1;
  object_pairs_.clear();
  move_planes(planes_, time_);  // moving colliders where they are at the step's start
  if (!bodies_.empty()) place_bodies(bodies_, D, time_, body_poses_);
  std::vector<char> meeting;
  {
    StageTimer timer{stages_.collision};
    meeting = meeting_objects();
  }
  for (std::size_t k = 0; k < objects_.size(); ++k)
    if (meeting.empty() || !meeting[k]) finish_object(objects_[k], dt, ledger);
  if (!meeting.empty()) finish_together(meeting, dt, ledger);
  if (ledger_on_) {
    last_ledger_ = ledger;
    ledger_.add(ledger);
  }
  surfaces_placed_ = false;
  time_ += dt;
  ++steps_;
}

template <class T, int D>
void EolSimulation<T, D>::finish_object(EolObject<T, D>& o, double dt, EnergyLedger& ledger) {
  const LedgerEnergies before = ledger_on_ ? ledger_before(o, ledger) : LedgerEnergies{};
  const SplitSums<D, 1> sums = impulse(o, T(dt));
  // The forces' work before the split changes the frame's ω.
  const LedgerEnergies pushed =
      ledger_on_ ? ledger_impulse(o, dt, before, ledger) : LedgerEnergies{};
  split(o, sums, T(dt));
  advect(o, T(dt));
  if (ledger_on_) ledger_transport(o, before, pushed, ledger);
}

// Eqs 16 and 29 node by node and, in the same pass, the sums of the split's normal equations
// (eq 23), which read the u just written: one pass over the nodes, not two. Surface rows (eqs
// 27-29) need the impulse of every node before their QP, so a pass of their own; only while the
// object's grid box reaches a plane, else no row can exist and the impulse stays in this pass,
// with no node rows.
template <class T, int D>
SplitSums<D, 1> EolSimulation<T, D>::impulse(EolObject<T, D>& o, T dt) {
  const bool surface = scene_.solver.eol.contact == EolSolverDesc::Contact::surface;
  const bool surface_rows =
      surface && (!planes_.empty() || !body_poses_.empty()) && may_touch_planes(o);
  if (surface_rows) impulse_surface_contact(o, dt);
  StageTimer timer{stages_.assembly};
  return impulse_pass(o, dt, surface_rows);
}

template <class T, int D>
SplitSums<D, 1> EolSimulation<T, D>::impulse_pass(EolObject<T, D>& o, T dt, bool impulse_done) {
  static const std::vector<PlaneConstraint<T, D>> no_planes;
  const bool surface = scene_.solver.eol.contact == EolSolverDesc::Contact::surface;
  const auto& node_planes = surface ? no_planes : planes_;
  return sum_node_blocks(o.grid.size(), parallel_, split_partial_,
                         [&](SplitSums<D, 1>& acc, std::size_t i) {
                           const T m = o.grid.mass[i];
                           if (!(m > T(0))) return;
                           if (!impulse_done) {
                             impulse_update(o.u[i], o.force[i], m, o.x[i], node_planes, dt);
                             if (!surface) apply_bodies(o.u[i], o.x[i], body_poses_);
                           }
                           if (lagrangian_) acc.template add<T>(o.r[i], {o.u[i]});
                         });
}

// The meeting objects: each one's impulse (eq 16), then one QP over their pair rows and plane
// rows (eq 29), then each one's split (eqs 23-24) from its constrained velocities and its
// transport. The ledger's impulse loss is taken after the QP, so it holds the QP's loss.
template <class T, int D>
void EolSimulation<T, D>::finish_together(const std::vector<char>& meeting, double dt,
                                          EnergyLedger& ledger) {
  std::vector<LedgerEnergies> before(objects_.size());
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    if (!meeting[k]) continue;
    if (ledger_on_) before[k] = ledger_before(objects_[k], ledger);
    StageTimer timer{stages_.assembly};
    impulse_nodes(objects_[k], T(dt));
  }
  object_contact(meeting);
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    if (!meeting[k]) continue;
    EolObject<T, D>& o = objects_[k];
    SplitSums<D, 1> sums;
    {
      StageTimer timer{stages_.assembly};
      sums = impulse_pass(o, T(dt), true);
    }
    const LedgerEnergies pushed =
        ledger_on_ ? ledger_impulse(o, dt, before[k], ledger) : LedgerEnergies{};
    split(o, sums, T(dt));
    advect(o, T(dt));
    if (ledger_on_) ledger_transport(o, before[k], pushed, ledger);
  }
}

// eol: q̇₁ from the split (eq 23), v* the remainder (eq 24), then q₁ += Δt q̇₁; eulerian: v* = u.
template <class T, int D>
void EolSimulation<T, D>::split(EolObject<T, D>& o, const SplitSums<D, 1>& sums, T dt) {
  StageTimer timer{stages_.split};
  if (!lagrangian_) {
    o.vstar = o.u;
    return;
  }
  const Mat<T, D> R = o.frame.rotation();
  const FrameVec<T, D> q1 = sums.template solve<T>()[0];
  o.frame.set_velocity(q1);
  eulerian_remainder(o.u, o.r, q1, R, o.vstar, parallel_);
  o.frame.advance(dt);
}

// Eq 15 for X (Algorithm 1 step 4) and v (step 2), both by v*; then the mass, the extrapolation
// into the empty nodes, the mass there, and the spatial state.
template <class T, int D>
void EolSimulation<T, D>::advect(EolObject<T, D>& o, T dt) {
  {
    StageTimer timer{stages_.advection};
    advect_pair(o.grid, o.vstar, dt, o.grid.X, o.scratch, o.vstar, o.grid.v, parallel_);
    std::swap(o.grid.X, o.scratch);
  }
  StageTimer timer{stages_.extrapolation};
  update_mass(o, false);
  o.extrapolation.apply(o.grid);
  update_mass(o, true);
  update_spatial(o);
}

template <class T, int D>
std::optional<Failure> EolSimulation<T, D>::check_step(const DiagnosticsRow& r) const {
  std::optional<Failure> f = energy_failure(r, steps_, time_, "grid state",
                                            scene_.solver.blowup_energy_factor, energy_ref_);
  // Elasticity is explicit: a ν above the shipped scenes' names the key that sets the cap.
  const TimeDesc& tm = scene_.time;
  if (f && !implicit_elasticity() && tm.rule == DtRule::elastic && tm.nu > kElasticNu)
    f->message += " (time.dt.nu = " + format_value(tm.nu) +
                  " sets the explicit elastic cap; the shipped EoL scenes are stable at " +
                  format_value(kElasticNu) + ")";
  return f;
}

}  // namespace apiclab::eol
