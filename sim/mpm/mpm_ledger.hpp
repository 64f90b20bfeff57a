// The conservation ledger's grid pass and its stages (sim/mpm/stage_ledger.hpp says what each
// stage's state is).
#pragma once
#include "sim/mpm/mpm.hpp"

namespace apiclab {

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
DiagnosticsRow MpmSimulation<T, D>::with_ledger(DiagnosticsRow r) const {
  ParticleSums start, updated;
  for (const LedgerChunk& c : ledger_.chunks) {
    start.add(c.start);
    updated.add(c.updated);
  }
  const double mass = total_mass();
  const ConservedSums s0 = ledger_state(start, mass, ledger_.elastic_start);
  const double potential = ledger_.elastic_start + start.gravity;  // Ψ + G until the move
  ConservedSums grid = ledger_.grid_p2g;
  grid.energy += potential;
  ConservedSums forced = ledger_.grid_forces;
  forced.energy += potential;
  ConservedSums walled = forced;
  walled += ledger_.walls;
  ConservedSums collided = walled;
  collided += ledger_.colliders;
  updated.gravity = start.gravity;  // G at xⁿ, as the start's sums have it
  const ConservedSums s5 = ledger_state(updated, mass, ledger_.elastic_start);
  ConservedSums end;
  end.mass = mass;
  end.p = r.p;
  end.L = r.L;
  end.energy = r.total;
  const ConservedSums states[] = {s0, grid, forced, walled, collided, s5, end};
  for (int s = 0; s < ledger_stage_count; ++s) r.stages[std::size_t(s)] = states[s + 1] - states[s];
  r.ledger = true;
  return r;
}

}  // namespace apiclab
