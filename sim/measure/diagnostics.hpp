// One diagnostics row per step (docs/architecture.md, Diagnostics CSV).
#pragma once
#include <array>
#include <ostream>
#include <string>
#include <vector>

namespace apiclab {

// Mass, linear momentum, angular momentum about the origin and energy of a state, or their change
// across one stage of a step (the conservation ledger, docs/outputs.md).
struct ConservedSums {
  double mass = 0;
  std::array<double, 3> p{0, 0, 0}, L{0, 0, 0};
  double energy = 0;

  ConservedSums& operator+=(const ConservedSums& o);
  friend ConservedSums operator-(ConservedSums a, const ConservedSums& b);
};

// The ledger's stages, in a step's order; a family without a stage leaves its change zero.
enum class LedgerStage { p2g, forces, walls, colliders, g2p, move };
inline constexpr int ledger_stage_count = 6;
const char* ledger_stage_name(LedgerStage s);

struct DiagnosticsRow {
  long step = 0;
  double t = 0, dt = 0;
  double kinetic = 0;       // particles, with ½ m tr(C D Cᵀ) for APIC/RPIC
  double kinetic_grid = 0;  // ½ Σ m_i |v_i^n|² right after P2G
  double potential = 0;     // elastic Σ V_p Ψ(F_p) plus gravitational -Σ m_p g·x_p
  double elastic = 0;       // the elastic part of potential (blow-up checks)
  double total = 0;
  std::array<double, 3> p{0, 0, 0};  // linear momentum
  std::array<double, 3> L{0, 0, 0};  // angular momentum about the origin, with m (B : ε)
  double wall_seconds = 0;           // cost of the step
  double newton_iters = 0, cg_iters = 0, residual = 0;  // implicit integrators
  bool converged = true;  // the implicit solve met its tolerance within its caps
  std::string dt_limit;   // which bound set dt (EoL, Sec 3.6: advection|elastic|max|frame|fixed)
  // Grid storage the solver holds (EoL: nodes of every object's grid, bytes of their per-node
  // and per-cell arrays); not in the diagnostics CSV: Fig 6's CSV carries them.
  double grid_nodes = 0, grid_bytes = 0;
  // EoL: pairs of objects whose surfaces overlapped at the step's start (the contact interval
  // of Fan et al. Fig 8); not in the diagnostics CSV.
  int contact_pairs = 0;
  // The conservation ledger (solver.ledger): each stage's change, by LedgerStage; the stages add
  // up to the step's change. Written as the CSV's ledger columns when `ledger` is set.
  bool ledger = false;
  std::array<ConservedSums, ledger_stage_count> stages{};
};

inline const char* diagnostics_header() {
  return "step,t,dt,kinetic,kinetic_grid,potential,total,px,py,pz,Lx,Ly,Lz,newton_iters,cg_iters,"
         "residual,wall_s,dt_limit";
}

// The header, with the ledger's columns (STAGE_dm, STAGE_dpx … STAGE_dLz, STAGE_dE per stage)
// after it when `ledger`.
std::string diagnostics_header(bool ledger);

void write_diagnostics_row(std::ostream& out, const DiagnosticsRow& r);

}  // namespace apiclab
