// The conservation ledger of an MPM step (solver.ledger; docs/outputs.md, Conservation ledger):
// mass, momentum, angular momentum and energy E = K + Ψ + G of the state between the step's
// stages, and each stage's change,
//   particles (xⁿ, vⁿ, Cⁿ, Fⁿ) →P2G→ grid vⁿ →forces→ ṽ* →walls→ →colliders→ ṽ
//   →G2P→ particles (xⁿ, vⁿ⁺¹, Cⁿ⁺¹, Fⁿ) →move→ particles (xⁿ⁺¹, vⁿ⁺¹, Cⁿ⁺¹, Fⁿ⁺¹).
// The particles count as the diagnostics row does (K with ½ m tr(C D Cᵀ), L with m (Bᵀ : ε)); the
// grid as Σ m_i, Σ m_i v_i, Σ x_i × m_i v_i, ½ Σ m_i |v_i|²; Ψ and G are the particles' (x and F
// change only in the move). The particles are summed as the row sums them (ChunkTerms,
// sim/mpm/particle_sums.hpp), G2P's chunks in passes of their own before G2P and, at the kept
// xⁿ, after it, so that G2P's loop stays as without the ledger (the start's sums only when the last
// step's row is not the start, StepLedger); the boundary pass adds what each
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

// The scheme and kernel as the ledger's particle sums read them: at run time, so that the sums are
// compiled once per precision and dimension, not per kernel and scheme.
struct LedgerTerms {
  bool affine;       // the scheme's C (D_p = k Δx² I, or the multilinear kernel's)
  bool multilinear;  // the multilinear kernel's D_p at x
  bool modes;        // PolyPIC's higher modes
};

// What a step with the ledger on keeps between its phases. The step's start is the last step's
// row when that row was the ledger's and nothing wrote the state since (Python, a scheme switch,
// a checkpoint load); otherwise G2P sums it first.
template <class T, int D>
struct StepLedger {
  static constexpr std::ptrdiff_t chunk = 1024;  // particles a sum: G2P's chunks (sim/mpm/g2p.hpp)
  std::vector<ParticleSums> updated;             // each G2P chunk's sums after its update, at xⁿ
  std::vector<Vec<T, D>> x_start;                // xⁿ, copied before G2P
  ConservedSums start;                           // the state at the step's start
  double start_potential = 0;                    // its Ψ + G, which the stages keep until the move
  long start_of_step = -1;                       // the step `start` is the start of (-1: none)
  ConservedSums grid_p2g, grid_forces;  // the grid after P2G (vⁿ) and after the update (ṽ*)
  ConservedSums walls, colliders;       // the boundary pass's changes (no mass change)

  void forget_start() { start_of_step = -1; }
};

// Momentum mv at node position x added to `sums`: p and x × mv, in double.
template <class T, int D>
[[gnu::always_inline]] inline void add_moments(ConservedSums& sums, const Vec<T, D>& x,
                                               const Eigen::Matrix<double, D, 1>& mv) {
  for (int a = 0; a < D; ++a) sums.p[std::size_t(a)] += mv[a];
  const Eigen::Vector3d L = cross_moment<double, D>(x.template cast<double>(), mv);
  for (int a = 0; a < 3; ++a) sums.L[std::size_t(a)] += L[a];
}

// The grid's node i of mass m and velocity v added to `sums`, in double. Inlined: the ledger's
// grid pass calls it twice a node.
template <class T, int D>
[[gnu::always_inline]] inline void add_node(ConservedSums& sums, const Vec<T, D>& x, T m,
                                            const Vec<T, D>& v) {
  const double md = double(m);
  const Eigen::Matrix<double, D, 1> mv = md * v.template cast<double>();
  sums.mass += md;
  add_moments<T, D>(sums, x, mv);
  sums.energy += 0.5 * mv.dot(v.template cast<double>());
}

// A boundary condition's change of node velocity `before` → `after` at mass m, into `sums`: the
// change itself, m (after − before), not the difference of two sums.
template <class T, int D>
[[gnu::always_inline]] inline void add_node_change(ConservedSums& sums, const Vec<T, D>& x, T m,
                                                   const Vec<T, D>& before,
                                                   const Vec<T, D>& after) {
  const double md = double(m);
  const Eigen::Matrix<double, D, 1> a = after.template cast<double>(),
                                    b = before.template cast<double>();
  add_moments<T, D>(sums, x, Eigen::Matrix<double, D, 1>(md * (a - b)));
  sums.energy += 0.5 * md * (a.squaredNorm() - b.squaredNorm());
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
