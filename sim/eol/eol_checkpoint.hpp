// The EoL family's part of a checkpoint (Simulation::save_state), for `eol` and `eulerian`: per
// object its frame (p, ν, ω, angle or quaternion), its node fields (X, v, mass, fill, material,
// owner, and the spatial r, x, u the next step starts from), Algorithm 2's last placement
// (each placement starts from the one before), the eulerian baseline's rest mass and the plastic
// samples' F_p⁻¹ and last placements (eol_plasticity.hpp); then the
// moving colliders' placement of the last step's start, the last Δt bound and implicit solve
// (the next row reports them), and the flags the next step reads. A step writes before it reads
// the forces (computed again on load, as the step computed them ahead), v*, the contact QP (its
// multipliers start at zero every solve), implicit elasticity's unknowns (started at ũ) and the
// extrapolation's fronts, so they stay out, as do the tests' energy ledger, the stage timings and
// the last contact rows (read by tests only). The grid sizes and the surface's vertex count are
// checked against the fresh solver of the same scene.
#pragma once
#include <string>

#include "sim/eol/eol_simulation.hpp"
#include "sim/state_io.hpp"

namespace apiclab::eol {
namespace detail {

// A fixed-size Eigen value as its coefficients (Eigen's types are not trivially copyable).
template <class M>
void save_coeffs(StateWriter& w, const M& m) {
  for (Eigen::Index k = 0; k < m.size(); ++k) w.value(m.data()[k]);
}
template <class M>
void load_coeffs(StateReader& r, M& m) {
  for (Eigen::Index k = 0; k < m.size(); ++k) r.value(m.data()[k]);
}

template <class T, int D>
void save_frame(StateWriter& w, const RigidFrame<T, D>& f) {
  save_coeffs(w, f.p);
  save_coeffs(w, f.nu);
  save_coeffs(w, f.omega);
  w.value(f.angle);
  save_coeffs(w, f.q.coeffs());
}
template <class T, int D>
void load_frame(StateReader& r, RigidFrame<T, D>& f) {
  load_coeffs(r, f.p);
  load_coeffs(r, f.nu);
  load_coeffs(r, f.omega);
  r.value(f.angle);
  load_coeffs(r, f.q.coeffs());
}

// Every entry of `ids` in [-1, count): a material or scene object index the step looks up.
inline void check_indices(const std::vector<std::int32_t>& ids, std::size_t count,
                          const char* what) {
  for (std::int32_t i : ids)
    if (i < -1 || i >= std::int32_t(count))
      throw StateError(std::string("its nodes name a ") + what + " the scene does not have");
}

}  // namespace detail

template <class T, int D>
void EolSimulation<T, D>::save_family_state(StateWriter& w) const {
  w.tag(lagrangian_ ? "eol" : "eulerian");
  w.value(std::int32_t(D));
  w.value(std::int32_t(sizeof(T)));
  w.value(std::uint64_t(objects_.size()));
  for (const auto& o : objects_) {
    w.tag("object");
    for (int a = 0; a < D; ++a) w.value(std::int32_t(o.grid.n[std::size_t(a)]));
    w.value(o.grid.dx);
    detail::save_coeffs(w, o.grid.origin);
    detail::save_frame(w, o.frame);
    w.array(o.grid.X);
    w.array(o.grid.v);
    w.array(o.grid.mass);
    w.array(o.grid.fill);
    w.array(o.grid.material);
    w.array(o.owner);
    w.array(o.r);
    w.array(o.x);
    w.array(o.u);
    w.array(o.surface_y);
    w.value(std::int32_t(o.surface_misses));
    w.value(o.rest_mass);
    w.array(o.plastic.fp_inv);
    w.array(o.plastic.identity);
    w.array(o.plastic.y);
  }
  w.tag("colliders");
  w.value(std::uint64_t(planes_.size()));
  for (const auto& pl : planes_) detail::save_coeffs(w, pl.point);
  w.array(body_poses_);
  w.tag("scalars");
  w.value(std::uint8_t(forces_ready_));
  w.value(std::uint8_t(surfaces_placed_));
  w.value(std::int32_t(last_limit_));
  w.value(std::int32_t(implicit_report_.newton_iterations));
  w.value(std::int32_t(implicit_report_.cg_iterations));
  w.value(implicit_report_.residual);
  w.value(implicit_report_.tolerance);
  w.value(std::uint8_t(implicit_report_.converged));
  w.value(energy_ref_);
}

template <class T, int D>
void EolSimulation<T, D>::load_family_state(StateReader& r) {
  r.tag(lagrangian_ ? "eol" : "eulerian");
  if (r.value<std::int32_t>() != D || r.value<std::int32_t>() != std::int32_t(sizeof(T)))
    throw StateError("its EoL state is of another dimension or precision");
  if (r.value<std::uint64_t>() != objects_.size())
    throw StateError("it holds another number of EoL objects than the scene makes");
  for (auto& o : objects_) {
    r.tag("object");
    bool same = true;  // every value read, so the state stays in step
    for (int a = 0; a < D; ++a) same &= r.value<std::int32_t>() == o.grid.n[std::size_t(a)];
    same &= r.value<T>() == o.grid.dx;
    Vec<T, D> origin;
    detail::load_coeffs(r, origin);
    if (!same || origin != o.grid.origin)
      throw StateError("its object grids are not those the scene makes");
    detail::load_frame(r, o.frame);
    r.same_size_array(o.grid.X, "grid nodes");
    r.same_size_array(o.grid.v, "grid nodes");
    r.same_size_array(o.grid.mass, "grid nodes");
    r.same_size_array(o.grid.fill, "grid nodes");
    r.same_size_array(o.grid.material, "grid nodes");
    r.same_size_array(o.owner, "grid nodes");
    r.same_size_array(o.r, "grid nodes");
    r.same_size_array(o.x, "grid nodes");
    r.same_size_array(o.u, "grid nodes");
    r.same_size_array(o.surface_y, "surface vertices");
    detail::check_indices(o.grid.material, materials_.size(), "material");
    detail::check_indices(o.owner, scene_.objects.size(), "scene object");
    o.surface_misses = r.value<std::int32_t>();
    r.value(o.rest_mass);
    r.same_size_array(o.plastic.fp_inv, "plastic samples");
    r.same_size_array(o.plastic.identity, "plastic samples");
    r.same_size_array(o.plastic.y, "plastic samples");
  }
  r.tag("colliders");
  if (r.value<std::uint64_t>() != planes_.size())
    throw StateError("its walls and planes are not those of the scene");
  for (auto& pl : planes_) detail::load_coeffs(r, pl.point);
  r.same_size_array(body_poses_, "moving colliders");
  r.tag("scalars");
  const bool forces_ready = r.value<std::uint8_t>() != 0;
  surfaces_placed_ = r.value<std::uint8_t>() != 0;
  const auto limit = r.value<std::int32_t>();
  if (limit < 0 || limit > std::int32_t(DtLimit::fixed))
    throw StateError("its last time-step bound is not one this build knows");
  last_limit_ = DtLimit(limit);
  implicit_report_.newton_iterations = r.value<std::int32_t>();
  implicit_report_.cg_iterations = r.value<std::int32_t>();
  r.value(implicit_report_.residual);
  r.value(implicit_report_.tolerance);
  implicit_report_.converged = r.value<std::uint8_t>() != 0;
  r.value(energy_ref_);
  // The forces of this state, as the step that wrote it computed them ahead (their Ψ is the
  // next row's elastic energy).
  forces_ready_ = false;
  if (forces_ready) forces_ahead();
}

}  // namespace apiclab::eol
