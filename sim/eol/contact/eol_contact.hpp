// The step's contact (Sec 3.5): whether an object's grid reaches a plane or another object's
// grid, the surface rows of eqs 27-28 against planes and between objects, and the QP of eq 29.
#pragma once
#include <chrono>
#include <cmath>
#include <utility>
#include <vector>

#include "sim/eol/eol_simulation.hpp"

namespace apiclab::eol {

// The world box of an object's grid (its 2^D corners through the frame).
template <class T, int D>
std::pair<Vec<T, D>, Vec<T, D>> grid_world_box(const EolObject<T, D>& o) {
  const Mat<T, D> R = o.frame.rotation();
  Vec<T, D> lo = Vec<T, D>::Constant(T(INFINITY)), hi = -lo;
  for (int corner = 0; corner < (1 << D); ++corner) {
    Vec<T, D> y = o.grid.origin;
    for (int a = 0; a < D; ++a)
      if (corner & (1 << a)) y[a] += o.grid.dx * T(o.grid.n[std::size_t(a)] - 1);
    const Vec<T, D> x = R * y + o.frame.p;
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  return {lo, hi};
}

// Whether any corner of the object's grid box is on or behind a plane, or the box comes within a
// body's reach (the surface lies inside the box, so otherwise no row can exist). The eulerian
// grid spans the domain: always for a plane.
template <class T, int D>
bool EolSimulation<T, D>::may_touch_planes(const EolObject<T, D>& o) const {
  const Mat<T, D> R = o.frame.rotation();
  for (int corner = 0; corner < (1 << D); ++corner) {
    Vec<T, D> y = o.grid.origin;
    for (int a = 0; a < D; ++a)
      if (corner & (1 << a)) y[a] += o.grid.dx * T(o.grid.n[std::size_t(a)] - 1);
    const Vec<T, D> x = R * y + o.frame.p;
    for (const auto& c : planes_)
      if ((x - c.point).dot(c.normal) <= T(0)) return true;
  }
  if (body_poses_.empty()) return false;
  const auto [lo, hi] = grid_world_box(o);
  return box_may_touch<T, D>(lo, hi, body_poses_);
}

template <class T, int D>
void EolSimulation<T, D>::impulse_nodes(EolObject<T, D>& o, T dt) {
  const std::ptrdiff_t n = std::ptrdiff_t(o.grid.size());
#pragma omp parallel for if (parallel_)
  for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
    const std::size_t i = std::size_t(ii);
    const T m = o.grid.mass[i];
    if (m > T(0)) impulse_update(o.u[i], o.force[i], m, o.x[i], {}, dt);
  }
}

// Eq 16 for every node with mass, then eqs 27-29: the surface placed now (Algorithm 2), its rows
// against the planes, and the QP on them. The impulse stage calls it only when may_touch_planes.
template <class T, int D>
void EolSimulation<T, D>::impulse_surface_contact(EolObject<T, D>& o, T dt) {
  {
    StageTimer timer{stages_.assembly};
    impulse_nodes(o, dt);
  }
  plane_rows(o);
  StageTimer timer{stages_.qp};
  contact_stats_ = contact_solver_.solve(contact_rows_, o.grid.mass, o.u);
}

// The object's surface placed now (Algorithm 2) and its rows against the planes and bodies, into
// contact_rows_.
template <class T, int D>
void EolSimulation<T, D>::plane_rows(EolObject<T, D>& o) {
  place_surface(o);
  StageTimer timer{stages_.collision};
  const T cell = scene_.solver.eol.contact_cell > 0 ? T(scene_.solver.eol.contact_cell) : o.grid.dx;
  contact_rows_.clear();
  assemble_surface_rows(o.grid, o.surface_y, o.surface.simplex, o.frame.rotation(), o.frame.p,
                        planes_, cell, contact_rows_);
  assemble_body_rows(o.grid, o.surface_y, o.surface.simplex, o.frame.rotation(), o.frame.p,
                     body_poses_, cell, 0, contact_rows_);
}

// The world box of an object's material: its nodes with mass, two cells wider each side (the
// surface, φ₀ = 0, lies within a cell of a node with mass, since mass fades over |φ₀| < Δx/2).
template <class T, int D>
std::pair<Vec<T, D>, Vec<T, D>> material_world_box(const EolObject<T, D>& o) {
  Vec<T, D> lo = Vec<T, D>::Constant(T(INFINITY)), hi = -lo;
  for (std::size_t i = 0; i < o.grid.size(); ++i) {
    if (!(o.grid.mass[i] > T(0))) continue;
    lo = lo.cwiseMin(o.x[i]);
    hi = hi.cwiseMax(o.x[i]);
  }
  const Vec<T, D> margin = Vec<T, D>::Constant(T(2) * o.grid.dx);
  return {lo - margin, hi + margin};
}

// A surface lies inside its material's box, so two objects whose boxes do not meet have no rows
// between them (an eol grid's padding or the Eulerian grid's whole domain would meet far sooner).
// Only with surface rows.
template <class T, int D>
std::vector<char> EolSimulation<T, D>::meeting_objects() const {
  const std::size_t count = objects_.size();
  if (count < 2 || scene_.solver.eol.contact != EolSolverDesc::Contact::surface) return {};
  std::vector<std::pair<Vec<T, D>, Vec<T, D>>> box(count);
  for (std::size_t k = 0; k < count; ++k) box[k] = material_world_box(objects_[k]);
  std::vector<char> meeting(count, 0);
  bool any = false;
  for (std::size_t a = 0; a < count; ++a)
    for (std::size_t b = a + 1; b < count; ++b) {
      const bool apart = (box[a].second.array() < box[b].first.array()).any() ||
                         (box[b].second.array() < box[a].first.array()).any();
      if (apart) continue;
      meeting[a] = meeting[b] = 1;
      any = true;
    }
  if (!any) return {};
  return meeting;
}

// Eqs 27-29 over the meeting objects together: their surfaces placed now (Algorithm 2), the rows
// of every overlapping pair (object_contact.hpp) and each object's rows against the planes, one
// QP (global_contact.hpp); their u take the constrained velocities.
template <class T, int D>
void EolSimulation<T, D>::object_contact(const std::vector<char>& meeting) {
  const std::vector<ObjectVelocities<T, D>> views = object_rows(meeting);
  StageTimer timer{stages_.qp};
  const auto start = std::chrono::steady_clock::now();
  contact_stats_ = global_solver_.solve(contact_rows_, views);
  contact_stats_.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The meeting objects' surfaces placed now and their rows (pairs, then each one's planes and
// bodies) into contact_rows_, over their nodes side by side; each one's masses, velocities and
// first node in that numbering.
template <class T, int D>
std::vector<ObjectVelocities<T, D>> EolSimulation<T, D>::object_rows(
    const std::vector<char>& meeting) {
  std::vector<ContactObject<T, D>> bodies;
  std::vector<ObjectVelocities<T, D>> views;
  std::uint32_t offset = 0;
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    if (!meeting[k]) continue;
    EolObject<T, D>& o = objects_[k];
    place_surface(o);
    ContactObject<T, D> c;
    c.grid = &o.grid;
    c.y = &o.surface_y;
    c.simplex = &o.surface.simplex;
    c.R = o.frame.rotation();
    c.p = o.frame.p;
    c.node_offset = offset;
    bodies.push_back(c);
    views.push_back({&o.grid.mass, &o.u, offset});
    offset += std::uint32_t(o.grid.size());
  }
  StageTimer timer{stages_.collision};
  const T cell = scene_.solver.eol.contact_cell > 0 ? T(scene_.solver.eol.contact_cell)
                                                    : bodies.front().grid->dx;
  contact_rows_.clear();
  object_pairs_ = assemble_object_rows(bodies, cell, contact_rows_);
  std::size_t b = 0;
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    if (!meeting[k]) continue;
    if ((!planes_.empty() || !body_poses_.empty()) && may_touch_planes(objects_[k])) {
      append_plane_rows(bodies[b], planes_, cell, plane_scratch_, contact_rows_);
      assemble_body_rows(*bodies[b].grid, *bodies[b].y, *bodies[b].simplex, bodies[b].R,
                         bodies[b].p, body_poses_, cell, bodies[b].node_offset, contact_rows_);
    }
    ++b;
  }
  return views;
}

}  // namespace apiclab::eol
