// The conservation ledger's grid pass and its stages (sim/mpm/stage_ledger.hpp says what each
// stage's state is).
#pragma once
#include "sim/mpm/mpm.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"
#include "sim/mpm/stencil.hpp"

namespace apiclab {

// The ledger's sums of particles [first, end) at positions xs (from particle `first` on), with
// their v, C and modes as they are: the row's terms, as G2P's run_chunk and diagnostics_terms
// form them (sim/mpm/g2p.hpp).
template <class T, int D>
ParticleSums MpmSimulation<T, D>::ledger_sums(std::ptrdiff_t first, std::ptrdiff_t end,
                                              const Vec<T, D>* xs, LedgerTerms how) const {
  ChunkTerms<T, D, StepLedger<T, D>::chunk> terms;
  if (how.affine && !how.multilinear) terms.isotropic_k = inertia_scale();
  terms.extras = (how.affine && how.multilinear) || how.modes;
  if (terms.extras)
    for (std::ptrdiff_t q = first; q < end; ++q) {
      const int j = int(q - first);
      const T m = p_.mass[q];
      T modes_kinetic = 0;
      if (how.modes) {
        Stencil<T, D, QuadraticKernel> at_x;
        at_x.compute(xs[j], grid_);
        modes_kinetic =
            T(0.5) * m *
            polypic::modes_energy_density<T, D>(at_x, grid_.inv_dx, p_.modes, std::size_t(q));
      }
      if (how.multilinear) {
        Stencil<T, D, LinearKernel> at_x;
        at_x.compute(xs[j], grid_);
        terms.set_affine(j, m, p_.C[q], Mat<T, D>(at_x.inertia()), modes_kinetic);
      } else {  // PolyPIC's higher modes; its C is read with x and v
        terms.extra_kinetic[j] = modes_kinetic;
        for (int a = 0; a < terms.moments; ++a) terms.affine_moment[a][j] = T(0);
      }
    }
  return terms.sum(&p_.mass[std::size_t(first)], xs, &p_.v[std::size_t(first)], p_.C.data() + first,
                   int(end - first), scene_.gravity);
}

// Before G2P: xⁿ kept for the sums after G2P, and the state at the step's start (xⁿ, vⁿ, Cⁿ,
// Fⁿ) summed in G2P's chunks, unless the last step's row is this step's start (with_ledger).
template <class T, int D>
void MpmSimulation<T, D>::ledger_start(LedgerTerms how) {
  ledger_.x_start.assign(p_.x.begin(), p_.x.end());
  if (ledger_.start_of_step == steps_) return;
  std::vector<ParticleSums> sums;
  ledger_chunk_sums(p_.x.data(), how, sums);
  ParticleSums start;
  for (const ParticleSums& s : sums) start.add(s);
  const double elastic = elastic_energy();
  ledger_.start = ledger_state(start, total_mass(), elastic);
  ledger_.start_potential = elastic + start.gravity;
  ledger_.start_of_step = steps_;
}

// After G2P: the particles' sums at the kept xⁿ, chunk by chunk.
template <class T, int D>
void MpmSimulation<T, D>::ledger_updated(LedgerTerms how) {
  ledger_chunk_sums(ledger_.x_start.data(), how, ledger_.updated);
}

// The particles' sums at positions xs (one per particle), in G2P's chunks, into `sums` (kept
// between steps: no allocation a step).
template <class T, int D>
void MpmSimulation<T, D>::ledger_chunk_sums(const Vec<T, D>* xs, LedgerTerms how,
                                            std::vector<ParticleSums>& sums) const {
  constexpr std::ptrdiff_t chunk = StepLedger<T, D>::chunk;
  const std::ptrdiff_t n = std::ptrdiff_t(p_.size()), chunks = (n + chunk - 1) / chunk;
  sums.resize(std::size_t(chunks));
#pragma omp parallel for schedule(static) if (parallel_worthwhile())
  for (std::ptrdiff_t c = 0; c < chunks; ++c) {
    const std::ptrdiff_t first = c * chunk, end = std::min(n, (c + 1) * chunk);
    sums[std::size_t(c)] = ledger_sums(first, end, xs + first, how);
  }
}

// After the grid update, before the boundary pass: the grid with vⁿ and with ṽ*, row by row of
// the active box, the rows' sums added in row order (the same at every thread count).
template <class T, int D>
void MpmSimulation<T, D>::ledger_grid() {
  const auto& rows = blocks_.box_rows();
  std::vector<std::array<ConservedSums, 2>> row_sums(rows.size());
  const std::ptrdiff_t count = std::ptrdiff_t(rows.size());
#pragma omp parallel for schedule(static) if (parallel_worthwhile())
  for (std::ptrdiff_t r = 0; r < count; ++r) {
    const auto [start, length] = rows[std::size_t(r)];
    Vec<T, D> x = grid_.node_position(start);
    for (std::size_t i = start; i < start + length; ++i) {
      x[0] = grid_.origin[0] + T(grid_.lo[0] + int(i - start)) * grid_.dx;  // node_position's
      if (!has_mass(i)) continue;
      add_node<T, D>(row_sums[std::size_t(r)][0], x, grid_.mass[i], grid_.velocity[i]);
      add_node<T, D>(row_sums[std::size_t(r)][1], x, grid_.mass[i], grid_.velocity_new[i]);
    }
  }
  ledger_.grid_p2g = ledger_.grid_forces = ConservedSums{};
  for (const auto& s : row_sums) {
    ledger_.grid_p2g += s[0];
    ledger_.grid_forces += s[1];
  }
  ledger_.walls = ledger_.colliders = ConservedSums{};
  if (uses_implicit_solve()) ledger_constraints();
}

// The implicit solve starts from ṽ = vⁿ + d, d setting the constrained components of the wall
// and collider nodes (implicit_begin), and moves the free ones: the forces' state there is ṽ
// with the constrained components back at vⁿ's, and the walls and colliders change it to ṽ,
// each condition in the solve's order (the constraints come node by node).
template <class T, int D>
void MpmSimulation<T, D>::ledger_constraints() {
  const auto& cs = imp_.constraints;
  for (std::size_t k = 0; k < cs.size();) {
    const std::size_t node = cs[k].node;
    std::size_t end = k;
    while (end < cs.size() && cs[end].node == node) ++end;
    const Vec<T, D> vn = grid_.velocity[node], solved = grid_.velocity_new[node];
    Vec<T, D> v = solved;
    for (std::size_t j = k; j < end; ++j)
      v = cs[j].condition == BoundaryCondition::sticky
              ? vn
              : Vec<T, D>(v - (v - vn).dot(cs[j].normal) * cs[j].normal);
    const Vec<T, D> x = grid_.node_position(node);
    const T m = grid_.mass[node];
    add_node_change<T, D>(ledger_.grid_forces, x, m, solved, v);
    for (std::size_t j = k; j < end; ++j) {
      const ConstrainedNode<T, D>& c = cs[j];
      const Vec<T, D> before = v;
      if (j + 1 == end)
        v = solved;  // the solve's ṽ, which the conditions in order make
      else if (c.condition == BoundaryCondition::sticky)
        v = c.body;
      else
        v -= (v - c.body).dot(c.normal) * c.normal;
      add_node_change<T, D>(c.collider ? ledger_.colliders : ledger_.walls, x, m, before, v);
    }
    k = end;
  }
}

// The step's row r with each stage's change: the states between the stages (particles at the
// start, the grid after P2G, after the forces, the walls and the colliders, the particles after
// G2P at xⁿ, and r itself) taken one from the next. Ψ and G stay the start's until the move.
template <class T, int D>
DiagnosticsRow MpmSimulation<T, D>::with_ledger(DiagnosticsRow r) {
  ParticleSums updated;
  for (const ParticleSums& c : ledger_.updated) updated.add(c);
  const double mass = total_mass(), potential = ledger_.start_potential;  // Ψ + G until the move
  ConservedSums grid = ledger_.grid_p2g;
  grid.energy += potential;
  ConservedSums forced = ledger_.grid_forces;
  forced.energy += potential;
  ConservedSums walled = forced;
  walled += ledger_.walls;
  ConservedSums collided = walled;
  collided += ledger_.colliders;
  ConservedSums s5 = ledger_state(updated, mass, 0);
  s5.energy = updated.kinetic + potential;
  ConservedSums end;
  end.mass = mass;
  end.p = r.p;
  end.L = r.L;
  end.energy = r.total;
  const ConservedSums states[] = {ledger_.start, grid, forced, walled, collided, s5, end};
  for (int s = 0; s < ledger_stage_count; ++s) r.stages[std::size_t(s)] = states[s + 1] - states[s];
  r.ledger = true;
  ledger_.start = end;
  ledger_.start_potential = r.potential;
  ledger_.start_of_step = steps_;
  return r;
}

}  // namespace apiclab
