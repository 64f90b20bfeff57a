// Setup: the materials, one grid per object (eol: around it; eulerian: over the domain), the
// initial velocities, the mass and spatial state, and the blow-up check's energy scale.
#pragma once
#include <cmath>
#include <sstream>

#include "sim/eol/eol_simulation.hpp"
#include "sim/eol/shape/rest_shape.hpp"
#include "sim/mpm/implicit/round_off_floor.hpp"

namespace apiclab::eol {

template <class T, int D>
EolSimulation<T, D>::EolSimulation(const SceneDesc& scene, bool lagrangian)
    : scene_(scene), lagrangian_(lagrangian) {
  if (scene.dim != D) throw SceneError(scene.source + ": key 'dim': internal dimension mismatch");
  add_materials();
  planes_ = scene_planes<T, D>(scene);
  bodies_ = scene_bodies(scene);
  place_bodies(bodies_, D, 0, body_poses_);
  const EolSolverDesc& e = scene.solver.eol;
  const double cell = lagrangian && e.cell > 0 ? e.cell : scene.domain.dx;
  for (int o = 0; o < int(scene.objects.size()); ++o)
    rest_.push_back(make_rest_shape(scene, o, cell));
  add_object_grids();
  std::size_t nodes = 0;
  for (const auto& o : objects_) nodes += o.grid.size();
  parallel_ = nodes >= scene.solver.parallel_min_particles;
  ledger_on_ = scene.solver.ledger;  // the CSV's ledger columns
  for (auto& o : objects_) {
    update_mass(o, false);
    update_spatial(o);
  }
  energy_ref_ = energy_reference();
}

template <class T, int D>
void EolSimulation<T, D>::add_materials() {
  for (const MaterialDesc& m : scene_.materials) {
    materials_.push_back({m.model, {T(m.mu()), T(m.lambda())}, T(m.viscosity), {}});
    if (m.model == MaterialModel::plastic) {
      if (implicit_elasticity())  // its backward Euler solve reads F, not F F_p⁻¹
        throw SceneError(scene_.source +
                         ": key 'solver.elasticity': the plastic model needs explicit elasticity "
                         "under " +
                         scene_.solver.method);
      materials_.back().plastic = {T(m.yield_stress.value_or(HUGE_VAL)), T(m.flow_rate)};
    }
    density_.push_back(T(m.rho));
    max_wave_speed_ = std::max(max_wave_speed_, m.wave_speed());
    max_kinematic_viscosity_ = std::max(max_kinematic_viscosity_, m.viscosity / m.rho);
  }
}

// eol: a grid per object around its rest shape (padded, or solver.grid_extent wide); eulerian:
// per object its own X and v on a grid over the whole domain (eq 27's v^A, v^B).
template <class T, int D>
void EolSimulation<T, D>::add_object_grids() {
  const SceneDesc& scene = scene_;
  if (!lagrangian_) {
    for (int o = 0; o < int(scene.objects.size()); ++o)
      add_object_grid({o}, scene.domain.min, scene.domain.max, scene.domain.dx, 0);
    return;
  }
  const EolSolverDesc& e = scene.solver.eol;
  const double dx = e.cell > 0 ? e.cell : scene.domain.dx;
  for (int o = 0; o < int(scene.objects.size()); ++o) {
    Vec3d lo, hi;
    rest_[std::size_t(o)].bounds(D, lo, hi);
    int padding = e.padding;
    if (e.grid_extent > 0) {
      for (int a = 0; a < D; ++a) {
        if (hi[a] - lo[a] + 2 * dx > e.grid_extent) {
          std::ostringstream msg;
          msg << scene.source << ": key 'objects." << o << ".shape': the rest shape spans "
              << hi[a] - lo[a] << " m along "
              << "xyz"[a]
              << ", more than its EoL grid holds with a cell each side (solver.grid_extent = "
              << e.grid_extent << " m, cell " << dx << " m)";
          throw SceneError(msg.str());
        }
        const double c = 0.5 * (lo[a] + hi[a]);
        lo[a] = c - 0.5 * e.grid_extent;
        hi[a] = c + 0.5 * e.grid_extent;
      }
      padding = 0;
    }
    add_object_grid({o}, lo, hi, dx, padding);
  }
}

// A grid from lo to hi (world, at rest) plus `padding` cells each side, its surface and its
// initial velocity.
template <class T, int D>
void EolSimulation<T, D>::add_object_grid(const std::vector<int>& shapes, const Vec3d& lo,
                                          const Vec3d& hi, double dx, int padding) {
  EolObject<T, D> o;
  o.shapes = shapes;
  place_object_grid(o, lo, hi, dx, padding);
  add_plastic_samples(o);
  // The surface at half the cell (Sec 3.8); at rest X = p + y, so y_s = X_s − p exactly.
  for (int s : shapes) append_rest_surface<D>(rest_[std::size_t(s)], s, 0.5 * dx, o.surface);
  for (const Vec<double, D>& Xs : o.surface.X)
    o.surface_y.push_back(Vec<T, D>(Xs.template cast<T>() - o.frame.p));
  set_initial_velocity(o);
  objects_.push_back(std::move(o));
}

// eol: the grid centred on the frame origin p = (lo + hi)/2; eulerian: the frame is the world,
// node 0 at lo. Material coordinates are the world positions at t = 0 (R = I).
template <class T, int D>
void EolSimulation<T, D>::place_object_grid(EolObject<T, D>& o, const Vec3d& lo, const Vec3d& hi,
                                            double dx, int padding) const {
  std::array<int, D> n;
  for (int a = 0; a < D; ++a)
    n[std::size_t(a)] = int(std::ceil((hi[a] - lo[a]) / dx - 1e-9)) + 1 + 2 * padding;
  o.grid.resize(n);
  o.grid.dx = T(dx);
  for (int a = 0; a < D; ++a) {
    if (lagrangian_) {
      o.frame.p[a] = T(0.5 * (lo[a] + hi[a]));
      o.grid.origin[a] = -T(0.5 * dx * (n[std::size_t(a)] - 1));
    } else {
      o.frame.p[a] = T(lo[a]);
      o.grid.origin[a] = T(0);
    }
  }
  const std::size_t count = o.grid.size();
  for (auto* f : {&o.r, &o.x, &o.u, &o.force, &o.scratch, &o.vstar})
    f->assign(count, Vec<T, D>::Zero());
  o.owner.assign(count, -1);
  for (std::size_t i = 0; i < count; ++i) o.grid.X[i] = o.frame.p + o.grid.y(i);
}

// Initial velocity of object s at world x: V + ω × (x − center), and ω.
template <class T, int D>
std::pair<Vec<T, D>, Spin<T, D>> EolSimulation<T, D>::initial_velocity(int s,
                                                                       const Vec<T, D>& x) const {
  const ObjectDesc& obj = scene_.objects[std::size_t(s)];
  Vec<T, D> V, c;
  Spin<T, D> w;
  for (int a = 0; a < D; ++a) {
    V[a] = T(obj.velocity[std::size_t(a)]);
    c[a] = T(rest_[std::size_t(s)].center()[std::size_t(a)]);
  }
  if constexpr (D == 2)
    w[0] = T(obj.angular_velocity[2]);
  else
    for (int a = 0; a < 3; ++a) w[a] = T(obj.angular_velocity[std::size_t(a)]);
  return {Vec<T, D>(V + spin_cross<T, D>(w, Vec<T, D>(x - c))), w};
}

// eol: the frame moves with the object's initial velocity at its origin; eulerian: every node of
// the object's world grid takes the object's velocity field.
template <class T, int D>
void EolSimulation<T, D>::set_initial_velocity(EolObject<T, D>& o) const {
  if (lagrangian_) {
    auto [nu, w] = initial_velocity(o.shapes[0], o.frame.p);
    o.frame.nu = nu;
    o.frame.omega = w;
    return;
  }
  for (std::size_t i = 0; i < o.grid.size(); ++i) {
    Vec3d X{0, 0, 0};
    for (int a = 0; a < D; ++a) X[std::size_t(a)] = double(o.grid.X[i][a]);
    int best = o.shapes[0];
    double best_phi = 1e300;
    for (int s : o.shapes) {
      const double phi = rest_[std::size_t(s)].distance(X, D);
      if (phi < best_phi) {
        best_phi = phi;
        best = s;
      }
    }
    o.grid.v[i] = initial_velocity(best, o.grid.X[i]).first;
  }
}

// The blow-up check's energy scale: K + Ψ now plus M |g| times the domain's diagonal, at least
// the round-off energy of a body at rest (sim/mpm/implicit/round_off_floor.hpp).
template <class T, int D>
double EolSimulation<T, D>::energy_reference() const {
  DiagnosticsRow r = measure();
  double g = 0, height = 0;
  for (int a = 0; a < D; ++a) {
    g += scene_.gravity[std::size_t(a)] * scene_.gravity[std::size_t(a)];
    height += std::pow(scene_.domain.max[std::size_t(a)] - scene_.domain.min[std::size_t(a)], 2);
  }
  return std::max({r.kinetic + r.elastic + total_mass() * std::sqrt(g) * std::sqrt(height),
                   rest_energy_round_off(), 1e-300});
}

template <class T, int D>
double EolSimulation<T, D>::rest_energy_round_off() const {
  return energy_round_off<T>(total_mass() * max_wave_speed_ * max_wave_speed_, D);
}

}  // namespace apiclab::eol
