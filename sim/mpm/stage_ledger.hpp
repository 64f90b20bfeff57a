// The conservation ledger of an MPM step (solver.ledger; docs/outputs.md, Conservation ledger):
// mass, momentum, angular momentum and energy E = K + Ψ + G of the state between the step's
// stages, and each stage's change,
//   particles (xⁿ, vⁿ, Cⁿ, Fⁿ) →P2G→ grid vⁿ →forces→ ṽ* →walls→ →colliders→ ṽ
//   →G2P→ particles (xⁿ, vⁿ⁺¹, Cⁿ⁺¹, Fⁿ) →move→ particles (xⁿ⁺¹, vⁿ⁺¹, Cⁿ⁺¹, Fⁿ⁺¹).
// The particles count as the diagnostics row does (K with ½ m tr(C D Cᵀ), L with m (Bᵀ : ε)); the
// grid as Σ m_i, Σ m_i v_i, Σ x_i × m_i v_i, ½ Σ m_i |v_i|²; Ψ and G are the particles' (x and F
// change only in the move). The particles are summed as the row sums them (ChunkTerms,
// sim/mpm/particle_sums.hpp), G2P's chunks in passes of their own before G2P and, at the kept
// xⁿ, after it, so that G2P's loop stays as without the ledger; the boundary pass adds what each
// condition changes, one pass over the grid sums vⁿ and ṽ*; the move's end is the row itself. Under
// the implicit integrators the solve sets the constrained components of the wall and collider nodes
// first and moves the free ones (implicit_begin): ṽ* is the solve's ṽ with the constrained
// components at vⁿ's, and the walls' and colliders' terms are what setting them changes, then what
// the boundary pass after the solve changes.
#pragma once
#include <cstddef>
#include <vector>

#include "sim/math.hpp"
#include "sim/measure/diagnostics.hpp"
#include "sim/mpm/particle_sums.hpp"

namespace apiclab {

// G2P's share of one chunk of particles: the sums at the step's start and after the particle
// update at xⁿ, before the move.
struct LedgerChunk {
  ParticleSums start, updated;
};

// The scheme and kernel as the ledger's particle sums read them: at run time, so that the sums are
// compiled once per precision and dimension, not per kernel and scheme.
struct LedgerTerms {
  bool affine;       // the scheme's C (D_p = k Δx² I, or the multilinear kernel's)
  bool multilinear;  // the multilinear kernel's D_p at x
  bool modes;        // PolyPIC's higher modes
};

// What a step with the ledger on keeps between its phases.
template <class T, int D>
struct StepLedger {
  static constexpr std::ptrdiff_t chunk = 1024;  // particles a sum: G2P's chunks (sim/mpm/g2p.hpp)
  std::vector<LedgerChunk> chunks;
  std::vector<Vec<T, D>> x_start;       // xⁿ, copied by G2P chunk by chunk before the move
  double elastic_start = 0;             // Ψ(Fⁿ)
  ConservedSums grid_p2g, grid_forces;  // the grid after P2G (vⁿ) and after the update (ṽ*)
  ConservedSums walls, colliders;       // the boundary pass's changes (no mass change)
};

// The grid's node i of mass m and velocity v added to `sums`.
template <class T, int D>
void add_node(ConservedSums& sums, const Vec<T, D>& x, T m, const Vec<T, D>& v) {
  const Vec<T, D> mv = m * v;
  sums.mass += double(m);
  for (int a = 0; a < D; ++a) sums.p[std::size_t(a)] += double(mv[a]);
  const Eigen::Vector3d L = cross_moment<T, D>(x, mv);
  for (int a = 0; a < 3; ++a) sums.L[std::size_t(a)] += L[a];
  sums.energy += 0.5 * double(m) * double(v.squaredNorm());
}

// A boundary condition's change of node velocity `before` → `after` at mass m, into `sums`.
template <class T, int D>
void add_node_change(ConservedSums& sums, const Vec<T, D>& x, T m, const Vec<T, D>& before,
                     const Vec<T, D>& after) {
  ConservedSums b, a;
  add_node<T, D>(b, x, m, before);
  add_node<T, D>(a, x, m, after);
  a.mass = b.mass = 0;
  sums += a - b;
}

// The particle sums as a state of the ledger: mass M, energy K + Ψ + G.
inline ConservedSums ledger_state(const ParticleSums& s, double mass, double elastic) {
  ConservedSums c;
  c.mass = mass;
  c.p = s.p;
  c.L = s.L;
  c.energy = s.kinetic + elastic + s.gravity;
  return c;
}

}  // namespace apiclab
