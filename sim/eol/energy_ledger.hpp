// Where the energy of an Eulerian-on-Lagrangian step goes, stage by stage (to find why a
// spinning object that hits a slip floor gains energy). Opt-in
// (EolSimulation::record_energy_ledger); the step pays for it only when it is on (two extra
// passes over the nodes, one over the cells).
//
// Energy E = K + G + Ψ: kinetic ½ Σ m|u|², gravity −Σ m g·x, elastic Σ V₀ Ψ(F). One step:
//   impulse and plane rows (eqs 16, 29): u → u⁺ = P(u + Δt f/m), x and m fixed, so
//     ΔK_impulse = W_e + W_g + W_qvv − loss,  W_• = Δt Σ f_•·u⁺,
//     loss = ½ Σ m|u⁺ − u|² ≥ 0 (the plane rows remove only the normal part they act on, so
//     u⁺·(u⁺ − u − Δt f/m) = 0 node by node; symplectic Euler's own dissipation; the QP over
//     several objects makes it Σ u⁺ᵀM(u⁺ − u*) = −λᵀJu⁺ = 0 over them together, so the step's
//     loss is ≥ 0, one object's share need not be);
//   split (eqs 23–24): moves velocity between modes, leaves u⁺ and so K unchanged;
//   transport (frame update, advection eq 15, mass, extrapolation): ΔK_transport, ΔG, ΔΨ.
// A consistent step returns each force's work in its potential: W_e + ΔΨ, W_g + ΔG and
// W_qvv + ΔK_transport (f_qvv takes back what turning v with the frame adds, forces.hpp) are
// each small; the step's ΔE is their sum minus the loss.
// The same stages give the diagnostics CSV's ledger columns (solver.ledger, docs/outputs.md):
// forces = the work W and the impulse Δt Σ f, walls = what the impulse and contact rows change
// beyond them (ΔK − W = −loss), move = the transport; with the mass and momenta of the nodes.
#pragma once
#include <algorithm>

#include "sim/measure/diagnostics.hpp"

namespace apiclab::eol {

struct EnergyLedger {
  long steps = 0;
  double elastic_work = 0, gravity_work = 0, qvv_work = 0;  // W_e, W_g, W_qvv with u⁺
  double impulse_loss = 0;  // W_e + W_g + W_qvv − ΔK_impulse = ½ Σ m|u⁺ − u|² (≥ 0)
  double elastic_change = 0, gravity_change = 0;  // ΔΨ, ΔG over the transport
  double transport_kinetic_change = 0;            // ΔK over the transport
  double min_step_impulse_loss = 0;  // the smallest single-step loss (negative: a row added K)
  // Mass and momenta (their energy unused): the forces' impulse Δt Σ f and Δt Σ x × f, the
  // impulse stage's change with the rows, the transport's change.
  ConservedSums force_impulse, impulse_change, transport_change;

  // What each force's work left unreturned to its own energy over the steps recorded.
  double elastic_residual() const { return elastic_work + elastic_change; }
  double gravity_residual() const { return gravity_work + gravity_change; }
  double qvv_residual() const { return qvv_work + transport_kinetic_change; }
  // ΔE over the steps recorded, from the ledger's terms.
  double total_change() const {
    return elastic_residual() + gravity_residual() + qvv_residual() - impulse_loss;
  }
  void add(const EnergyLedger& s) {
    min_step_impulse_loss =
        steps == 0 ? s.impulse_loss : std::min(min_step_impulse_loss, s.impulse_loss);
    steps += s.steps;
    elastic_work += s.elastic_work;
    gravity_work += s.gravity_work;
    qvv_work += s.qvv_work;
    impulse_loss += s.impulse_loss;
    elastic_change += s.elastic_change;
    gravity_change += s.gravity_change;
    transport_kinetic_change += s.transport_kinetic_change;
    force_impulse += s.force_impulse;
    impulse_change += s.impulse_change;
    transport_change += s.transport_change;
  }

  // The diagnostics row's stages (LedgerStage) of the steps recorded.
  std::array<ConservedSums, ledger_stage_count> stages() const {
    std::array<ConservedSums, ledger_stage_count> out{};
    ConservedSums& forces = out[std::size_t(LedgerStage::forces)];
    forces = force_impulse;
    forces.energy = elastic_work + gravity_work + qvv_work;
    ConservedSums& walls = out[std::size_t(LedgerStage::walls)];
    walls = impulse_change - force_impulse;
    walls.energy = -impulse_loss;
    ConservedSums& move = out[std::size_t(LedgerStage::move)];
    move = transport_change;
    move.energy = transport_kinetic_change + gravity_change + elastic_change;
    return out;
  }
};

}  // namespace apiclab::eol
