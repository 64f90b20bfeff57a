// MPM's part of a checkpoint (Simulation::save_state): the particles in their storage order
// (the order every sum of the next step runs in), PolyPIC's modes, the plastic model's F_p⁻¹
// (mpm_plasticity.hpp), the block sort's state, and
// the scalars a step reads from the one before (the two-step rule's grid speed, the grid's
// kinetic energy, the frozen flag, the conservation ledger's start). Everything else a step writes
// before it reads: the grid, XPIC's node arrays, the implicit solve's Δv (zero at each step's
// start, no warm start), the stencils. The explicit step's stress of F^n is computed again on load,
// as the step did.
#pragma once
#include <algorithm>

#include "sim/mpm/mpm.hpp"
#include "sim/state_io.hpp"

namespace apiclab {

template <class T, int D>
void MpmSimulation<T, D>::save_family_state(StateWriter& w) const {
  w.tag("mpm");
  w.value(std::int32_t(D));
  w.value(std::int32_t(sizeof(T)));
  w.value(std::uint64_t(p_.modes.size()));
  w.array(p_.x);
  w.array(p_.v);
  w.array(p_.C);
  w.array(p_.F);
  w.array(p_.mass);
  w.array(p_.volume0);
  w.array(p_.material);
  w.array(p_.object);
  w.array(p_.id);
  for (const auto& m : p_.modes) w.array(m);
  w.array(p_.fp_inv);
  blocks_.save(w);
  w.tag("scalars");
  w.value(kinetic_grid_);
  w.value(max_grid_speed_);
  w.value(std::uint8_t(non_finite_));
  w.tag("ledger");  // the next step's start, when the last row was the ledger's
  w.value(std::int64_t(ledger_.start_of_step));
  w.value(ledger_.start_potential);
  w.value(ledger_.start);
}

template <class T, int D>
void MpmSimulation<T, D>::load_family_state(StateReader& r) {
  r.tag("mpm");
  if (r.value<std::int32_t>() != D || r.value<std::int32_t>() != std::int32_t(sizeof(T)))
    throw StateError("its MPM state is of another dimension or precision");
  if (r.value<std::uint64_t>() != p_.modes.size())
    throw StateError("its particles hold another number of PolyPIC modes");
  std::vector<std::int32_t> ids = p_.id;  // the scene's, in setup order
  r.same_size_array(p_.x, "particles");
  r.same_size_array(p_.v, "particles");
  r.same_size_array(p_.C, "particles");
  r.same_size_array(p_.F, "particles");
  r.same_size_array(p_.mass, "particles");
  r.same_size_array(p_.volume0, "particles");
  r.same_size_array(p_.material, "particles");
  r.same_size_array(p_.object, "particles");
  r.same_size_array(p_.id, "particles");
  for (auto& m : p_.modes) r.same_size_array(m, "particles");
  r.same_size_array(p_.fp_inv, "plastic particles");
  std::vector<std::int32_t> loaded = p_.id;
  std::sort(ids.begin(), ids.end());
  std::sort(loaded.begin(), loaded.end());
  if (ids != loaded) throw StateError("its particle ids are not those of the scene");
  rebuild_index_of_id();
  boundary_.move_to(time_);
  blocks_.load(r, grid_, boundary_);
  r.tag("scalars");
  r.value(kinetic_grid_);
  r.value(max_grid_speed_);
  non_finite_ = r.value<std::uint8_t>() != 0;
  r.tag("ledger");
  ledger_.start_of_step = long(r.value<std::int64_t>());
  r.value(ledger_.start_potential);
  r.value(ledger_.start);
  stress_of_current_F_ = false;
  if (!uses_implicit_solve() && !non_finite_) compute_stress();
}

}  // namespace apiclab
