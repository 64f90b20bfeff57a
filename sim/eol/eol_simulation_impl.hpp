// EolSimulation's definitions (declared in eol_simulation.hpp), instantiated in eol_2d.cpp and
// eol_3d.cpp.
#pragma once
#include <chrono>
#include <cmath>
#include <sstream>

#include "sim/eol/advection.hpp"
#include "sim/eol/eol_simulation.hpp"
#include "sim/eol/least_squares_split.hpp"
#include "sim/eol/rest_shape.hpp"
#include "sim/eol/surface_placement.hpp"
#include "sim/mpm/implicit/round_off_floor.hpp"

namespace apiclab::eol {
namespace detail {
inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace detail

template <class T, int D>
EolSimulation<T, D>::EolSimulation(const SceneDesc& scene, bool lagrangian)
    : scene_(scene), lagrangian_(lagrangian) {
  if (scene.dim != D) throw SceneError(scene.source + ": key 'dim': internal dimension mismatch");
  for (const MaterialDesc& m : scene.materials) {
    materials_.push_back({m.model, {T(m.mu()), T(m.lambda())}});
    density_.push_back(T(m.rho));
    max_wave_speed_ = std::max(max_wave_speed_, m.wave_speed());
  }
  planes_ = scene_planes<T, D>(scene);
  const EolSolverDesc& e = scene.solver.eol;
  const double cell = lagrangian && e.cell > 0 ? e.cell : scene.domain.dx;
  for (int o = 0; o < int(scene.objects.size()); ++o)
    rest_.push_back(make_rest_shape(scene, o, cell));
  if (lagrangian) {
    const double dx = cell;
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
  } else {
    std::vector<int> all;
    for (int o = 0; o < int(scene.objects.size()); ++o) all.push_back(o);
    add_object_grid(all, scene.domain.min, scene.domain.max, scene.domain.dx, 0);
  }
  std::size_t nodes = 0;
  for (const auto& o : objects_) nodes += o.grid.size();
  parallel_ = nodes >= scene.solver.parallel_min_particles;
  for (auto& o : objects_) {
    update_mass(o, false);
    update_spatial(o);
  }
  energy_ref_ = energy_reference();
}

// A grid from lo to hi (world, at rest) plus `padding` cells each side. eol: centred on the
// frame origin p = (lo + hi)/2; eulerian: the frame is the world, node 0 at lo.
template <class T, int D>
void EolSimulation<T, D>::add_object_grid(const std::vector<int>& shapes, const Vec3d& lo,
                                          const Vec3d& hi, double dx, int padding) {
  EolObject<T, D> o;
  o.shapes = shapes;
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
  // Material coordinates are the world positions at t = 0 (R = I).
  for (std::size_t i = 0; i < count; ++i) o.grid.X[i] = o.frame.p + o.grid.y(i);
  // Initial velocity of object s at world x: V + ω × (x − center).
  auto initial_velocity = [&](int s, const Vec<T, D>& x) {
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
    return std::pair<Vec<T, D>, Spin<T, D>>(V + spin_cross<T, D>(w, Vec<T, D>(x - c)), w);
  };
  // The surface at half the cell (Sec 3.8); at rest X = p + y, so y_s = X_s − p exactly.
  for (int s : shapes) append_rest_surface<D>(rest_[std::size_t(s)], s, 0.5 * dx, o.surface);
  for (const Vec<double, D>& Xs : o.surface.X)
    o.surface_y.push_back(Vec<T, D>(Xs.template cast<T>() - o.frame.p));
  if (lagrangian_) {
    auto [nu, w] = initial_velocity(shapes[0], o.frame.p);
    o.frame.nu = nu;
    o.frame.omega = w;
  } else {
    // The world grid: each node takes the velocity field of the nearest rest shape.
    for (std::size_t i = 0; i < count; ++i) {
      Vec3d X{0, 0, 0};
      for (int a = 0; a < D; ++a) X[std::size_t(a)] = double(o.grid.X[i][a]);
      int best = shapes[0];
      double best_phi = 1e300;
      for (int s : shapes) {
        const double phi = rest_[std::size_t(s)].distance(X, D);
        if (phi < best_phi) {
          best_phi = phi;
          best = s;
        }
      }
      o.grid.v[i] = initial_velocity(best, o.grid.X[i]).first;
    }
  }
  objects_.push_back(std::move(o));
}

template <class T, int D>
void EolSimulation<T, D>::update_mass(EolObject<T, D>& o) {
  forces_ready_ = false;
  update_mass(o, false);
}

// after_extrapolation: only the nodes without mass changed X since the last call (extrapolation
// writes nothing else), so only they and the cells touching them are evaluated again.
template <class T, int D>
void EolSimulation<T, D>::update_mass(EolObject<T, D>& o, bool after_extrapolation) {
  EulerianGrid<T, D>& g = o.grid;
  const std::ptrdiff_t n = std::ptrdiff_t(g.size());
#pragma omp parallel for if (parallel_)
  for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
    const std::size_t i = std::size_t(ii);
    if (after_extrapolation && g.mass[i] > T(0)) continue;
    Vec3d X{0, 0, 0};
    for (int a = 0; a < D; ++a) X[std::size_t(a)] = double(g.X[i][a]);
    double best = 1e300;
    int owner = -1;
    for (int s : o.shapes) {
      const double phi = rest_[std::size_t(s)].distance(X, D);
      if (phi < best) {
        best = phi;
        owner = s;
      }
    }
    const T fill = std::isfinite(best) ? smoothed_inside<T>(best, double(g.dx)) : T(0);
    g.fill[i] = fill;
    o.owner[i] = fill > T(0) ? owner : -1;
    g.material[i] = fill > T(0) ? scene_.objects[std::size_t(owner)].material : -1;
  }
  o.elastic.lumped_mass(g, density_, g.mass, parallel_, after_extrapolation ? &g.mass : nullptr);
}

template <class T, int D>
void EolSimulation<T, D>::spatial_state(EolObject<T, D>& o) {
  forces_ready_ = false;
  update_spatial(o);
}

template <class T, int D>
void EolSimulation<T, D>::update_spatial(EolObject<T, D>& o) const {
  const Mat<T, D> R = o.frame.rotation();
  for (std::size_t i = 0; i < o.grid.size(); ++i) {
    o.r[i] = R * o.grid.y(i);
    o.x[i] = o.r[i] + o.frame.p;
    o.u[i] = o.frame.nu + spin_cross<T, D>(o.frame.omega, o.r[i]) + R * o.grid.v[i];
  }
}

template <class T, int D>
void EolSimulation<T, D>::compute_forces(EolObject<T, D>& o) {
  forces_ready_ = false;
  forces(o);
}

template <class T, int D>
void EolSimulation<T, D>::forces(EolObject<T, D>& o) {
  const auto start = std::chrono::steady_clock::now();
  const Mat<T, D> R = o.frame.rotation();
  Vec<T, D> g;
  for (int a = 0; a < D; ++a) g[a] = T(scene_.gravity[std::size_t(a)]);
  // Elasticity in frame axes, then per node (in the same parallel region) rotated to world axes
  // with gravity and f_qvv added.
  o.elastic.compute(o.grid, materials_, o.force, parallel_, [&](std::size_t i) {
    const T m = o.grid.mass[i];
    o.force[i] = R * o.force[i] + m * g;
    if (lagrangian_ && m > T(0))
      o.force[i] +=
          quadratic_velocity_force<T, D>(m, o.frame.omega, o.r[i], Vec<T, D>(R * o.grid.v[i]));
  });
  stages_.forces += detail::seconds_since(start);
}

template <class T, int D>
double EolSimulation<T, D>::choose_dt(double t_limit, DtLimit* limit) {
  const TimeDesc& tm = scene_.time;
  double dt = tm.dt;
  DtLimit lim = tm.rule == DtRule::fixed ? DtLimit::fixed : DtLimit::max;
  if (tm.rule != DtRule::fixed) {
    const auto start = std::chrono::steady_clock::now();
    for (auto& o : objects_) {
      const auto& mass = o.grid.mass;
      const double dx = double(o.grid.dx);
      // One pass for max|u|, and for eq 32's two fields u (v₀) and M⁻¹f (v₁) either their
      // rates (eulerian: v* is the field) or the sums of their splits (eq 23).
      const DtSums sums =
          sum_node_blocks(o.grid.size(), parallel_, dt_partial_, [&](DtSums& acc, std::size_t i) {
            if (!(mass[i] > T(0))) return;
            const Vec<T, D> a = o.force[i] / mass[i];
            acc.umax = std::max(acc.umax, double(o.u[i].norm()));
            if (lagrangian_) {
              acc.split.template add<T>(o.r[i], {o.u[i], a});
            } else {
              acc.gamma0 = std::max(acc.gamma0, double(o.u[i].template lpNorm<1>()) / dx);
              acc.gamma1 = std::max(acc.gamma1, double(a.template lpNorm<1>()) / dx);
            }
          });
      const double umax = sums.umax;
      double gamma0 = sums.gamma0, gamma1 = sums.gamma1;
      if (lagrangian_) {
        // Eq 32: v* = v₀* + Δt v₁*, each the split (eq 24) of its own field; eq 33's γ are
        // maxima (the same in any order), so a plain parallel max.
        const std::array<FrameVec<T, D>, 2> q = sums.split.template solve<T>();
        const Mat<T, D> Rt = o.frame.rotation().transpose();
        const std::ptrdiff_t n = std::ptrdiff_t(o.grid.size());
        double g0 = 0, g1 = 0;
#pragma omp parallel for reduction(max : g0, g1) if (parallel_)
        for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
          const std::size_t i = std::size_t(ii);
          if (!(mass[i] > T(0))) continue;
          const Vec<T, D> a = o.force[i] / mass[i];
          const Vec<T, D> v0 = eulerian_velocity<T, D>(o.u[i], o.r[i], q[0], Rt);
          const Vec<T, D> v1 = eulerian_velocity<T, D>(a, o.r[i], q[1], Rt);
          g0 = std::max(g0, double(v0.template lpNorm<1>()) / dx);
          g1 = std::max(g1, double(v1.template lpNorm<1>()) / dx);
        }
        gamma0 = g0;
        gamma1 = g1;
      }
      const double advection = advection_limit(gamma0, gamma1, scene_.solver.eol.alpha);
      const double elastic = tm.nu * dx / (max_wave_speed_ + umax);
      if (advection < dt) {
        dt = advection;
        lim = DtLimit::advection;
      }
      if (elastic < dt) {
        dt = elastic;
        lim = DtLimit::elastic;
      }
    }
    stages_.split += detail::seconds_since(start);
  }
  if (1.0 / tm.fps < dt) {
    dt = 1.0 / tm.fps;
    lim = DtLimit::frame;
  }
  const double to_frame = t_limit - time_;
  if (to_frame < 1.001 * dt) {  // land on the frame time, avoiding a sliver step
    dt = to_frame;
    lim = DtLimit::frame;
  } else if (to_frame < 2.0 * dt) {
    dt = 0.5 * to_frame;
    lim = DtLimit::frame;
  }
  if (limit) *limit = lim;
  return dt;
}

template <class T, int D>
void EolSimulation<T, D>::finish_step(double dt_in) {
  forces_ready_ = false;
  const T dt = T(dt_in);
  EnergyLedger ledger;
  ledger.steps = 1;
  for (auto& o : objects_) {
    LedgerEnergies before;
    if (ledger_on_) {
      before = ledger_energies(o);
      ledger.elastic_change -= o.elastic.energy();  // Ψ of this state (its forces' pass)
    }
    auto start = std::chrono::steady_clock::now();
    // Eqs 16 and 29 node by node and, in the same pass, the sums of the split's normal
    // equations (eq 23), which read the u just written: one pass over the nodes, not two.
    // Surface rows (eqs 27-29) need the impulse of every node before their QP, so a pass of
    // its own; only while the object's grid box reaches a plane, else no row can exist and the
    // impulse stays in this pass, with no node rows.
    static const std::vector<PlaneConstraint<T, D>> no_planes;
    const bool surface = scene_.solver.eol.contact == EolSolverDesc::Contact::surface;
    const bool surface_rows = surface && !planes_.empty() && may_touch_planes(o);
    if (surface_rows) impulse_surface_contact(o, dt);
    const auto& node_planes = surface ? no_planes : planes_;
    const SplitSums<D, 1> sums = sum_node_blocks(
        o.grid.size(), parallel_, split_partial_, [&](SplitSums<D, 1>& acc, std::size_t i) {
          const T m = o.grid.mass[i];
          if (!(m > T(0))) return;
          if (!surface_rows) impulse_update(o.u[i], o.force[i], m, o.x[i], node_planes, dt);
          if (lagrangian_) acc.template add<T>(o.r[i], {o.u[i]});
        });
    stages_.assembly += detail::seconds_since(start);
    LedgerEnergies pushed;  // after the impulse and plane rows
    if (ledger_on_) {
      const double work_before = ledger.elastic_work + ledger.gravity_work + ledger.qvv_work;
      ledger_work(o, dt_in, ledger);  // before the split changes the frame's ω
      pushed = ledger_energies(o);
      const double work = ledger.elastic_work + ledger.gravity_work + ledger.qvv_work;
      ledger.impulse_loss += work - work_before - (pushed.kinetic - before.kinetic);
    }
    start = std::chrono::steady_clock::now();
    if (lagrangian_) {
      const Mat<T, D> R = o.frame.rotation();
      const FrameVec<T, D> q1 = sums.template solve<T>()[0];  // eq 23
      o.frame.set_velocity(q1);
      eulerian_remainder(o.u, o.r, q1, R, o.vstar, parallel_);  // eq 24
      o.frame.advance(dt);
    } else {
      o.vstar = o.u;
    }
    stages_.split += detail::seconds_since(start);
    start = std::chrono::steady_clock::now();
    // Eq 15 for X (Algorithm 1 step 4) and v (step 2), both by v*.
    advect_pair(o.grid, o.vstar, dt, o.grid.X, o.scratch, o.vstar, o.grid.v, parallel_);
    std::swap(o.grid.X, o.scratch);
    update_mass(o, false);
    o.extrapolation.apply(o.grid);
    update_mass(o, true);
    update_spatial(o);
    stages_.advection += detail::seconds_since(start);
    if (ledger_on_) {
      const LedgerEnergies after = ledger_energies(o);
      ledger.transport_kinetic_change += after.kinetic - pushed.kinetic;
      ledger.gravity_change += after.gravity - before.gravity;
      ledger.elastic_change += elastic_energy_moved(o.grid, materials_);
    }
  }
  if (ledger_on_) {
    last_ledger_ = ledger;
    ledger_.add(ledger);
  }
  surfaces_placed_ = false;
  time_ += dt_in;
  ++steps_;
}

// Whether any corner of the object's grid box is on or behind a plane (the surface lies inside
// the box, so otherwise no row can exist). The eulerian grid spans the domain: always.
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
  return false;
}

// Eq 16 for every node with mass, then eqs 27-29: the surface placed now (Algorithm 2), its rows
// against the planes, and the QP on them. finish_step calls it only when may_touch_planes.
template <class T, int D>
void EolSimulation<T, D>::impulse_surface_contact(EolObject<T, D>& o, T dt) {
  const std::ptrdiff_t n = std::ptrdiff_t(o.grid.size());
#pragma omp parallel for if (parallel_)
  for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
    const std::size_t i = std::size_t(ii);
    const T m = o.grid.mass[i];
    if (m > T(0)) impulse_update(o.u[i], o.force[i], m, o.x[i], {}, dt);
  }
  place_surface(o);
  const T cell = scene_.solver.eol.contact_cell > 0 ? T(scene_.solver.eol.contact_cell) : o.grid.dx;
  contact_rows_.clear();
  assemble_surface_rows(o.grid, o.surface_y, o.surface.simplex, o.frame.rotation(), o.frame.p,
                        planes_, cell, contact_rows_);
  contact_stats_ = contact_solver_.solve(contact_rows_, o.grid.mass, o.u);
}

// K and G of one object as measure() counts them.
template <class T, int D>
typename EolSimulation<T, D>::LedgerEnergies EolSimulation<T, D>::ledger_energies(
    const EolObject<T, D>& o) const {
  LedgerEnergies e;
  for (std::size_t i = 0; i < o.grid.size(); ++i) {
    const double m = double(o.grid.mass[i]);
    if (!(m > 0)) continue;
    e.kinetic += 0.5 * m * double(o.u[i].squaredNorm());
    for (int a = 0; a < D; ++a) e.gravity -= m * scene_.gravity[std::size_t(a)] * double(o.x[i][a]);
  }
  return e;
}

// Adds the forces' work Δt Σ f·u⁺ (u⁺ after the impulse and plane rows) to `step`, split into
// gravity m g, f_qvv (from the frame's ω and the v this step's forces saw) and elasticity, the
// rest of f. The impulse's loss is what the work leaves over ΔK (finish_step).
template <class T, int D>
void EolSimulation<T, D>::ledger_work(const EolObject<T, D>& o, double dt,
                                      EnergyLedger& step) const {
  const Mat<T, D> R = o.frame.rotation();
  Vec<T, D> g;
  for (int a = 0; a < D; ++a) g[a] = T(scene_.gravity[std::size_t(a)]);
  for (std::size_t i = 0; i < o.grid.size(); ++i) {
    const T m = o.grid.mass[i];
    if (!(m > T(0))) continue;
    const Vec<T, D> fg = m * g;
    const Vec<T, D> fq = lagrangian_ ? quadratic_velocity_force<T, D>(m, o.frame.omega, o.r[i],
                                                                      Vec<T, D>(R * o.grid.v[i]))
                                     : Vec<T, D>::Zero();
    const Vec<T, D>& u = o.u[i];
    step.gravity_work += dt * double(fg.dot(u));
    step.qvv_work += dt * double(fq.dot(u));
    step.elastic_work += dt * double((o.force[i] - fg - fq).dot(u));
  }
}

template <class T, int D>
void EolSimulation<T, D>::place_surface(EolObject<T, D>& o) {
  const auto start = std::chrono::steady_clock::now();
  o.surface_misses = eol::place_surface(o.grid, o.surface.X, o.surface_y, parallel_);
  stages_.surface += detail::seconds_since(start);
}

template <class T, int D>
void EolSimulation<T, D>::place_surfaces() {
  if (surfaces_placed_) return;
  for (auto& o : objects_) place_surface(o);
  surfaces_placed_ = true;
}

template <class T, int D>
std::vector<Vec<T, D>> EolSimulation<T, D>::placed_surface(const EolObject<T, D>& o) const {
  std::vector<Vec<T, D>> y = o.surface_y;
  if (!surfaces_placed_) eol::place_surface(o.grid, o.surface.X, y, parallel_);
  return y;
}

template <class T, int D>
void EolSimulation<T, D>::step_fixed(double dt) {
  for (auto& o : objects_) compute_forces(o);
  finish_step(dt);
}

template <class T, int D>
std::optional<Failure> EolSimulation<T, D>::step(double t_limit, DiagnosticsRow* row) {
  if (failure_) return failure_;
  if (!(t_limit > time_)) return std::nullopt;
  const auto start = std::chrono::steady_clock::now();
  if (!forces_ready_)
    for (auto& o : objects_) forces(o);
  const double dt = choose_dt(t_limit, &last_limit_);
  finish_step(dt);
  // The next step's forces now, from the state they would see then; their Ψ gives the
  // diagnostics' elastic energy without another pass over the cells.
  for (auto& o : objects_) forces(o);
  forces_ready_ = true;
  if (t_limit - time_ < 1e-12 * std::max(1.0, std::abs(t_limit))) time_ = t_limit;
  if (time_ == t_limit) place_surfaces();  // a frame time: the surface is drawn or recorded
  DiagnosticsRow r = measure();
  r.dt = dt;
  r.dt_limit = dt_limit_name(last_limit_);
  r.wall_seconds = detail::seconds_since(start);
  if (row) *row = r;
  failure_ = energy_failure(r, steps_, time_, "grid state", scene_.solver.blowup_energy_factor,
                            energy_ref_);
  return failure_;
}

template <class T, int D>
double EolSimulation<T, D>::elastic_energy() const {
  double e = 0;
  for (const auto& o : objects_)
    e += forces_ready_ ? o.elastic.energy() : elastic_energy_moved(o.grid, materials_);
  return e;
}

template <class T, int D>
double EolSimulation<T, D>::occupied_volume() const {
  double v = 0;
  for (const auto& o : objects_) {
    double fill = 0;
    for (T h : o.grid.fill) fill += double(h);
    v += fill * std::pow(double(o.grid.dx), D);
  }
  return v;
}

template <class T, int D>
double EolSimulation<T, D>::total_mass() const {
  double m = 0;
  for (const auto& o : objects_)
    for (T x : o.grid.mass) m += double(x);
  return m;
}

// Energies and momenta from the grid fields (the diagnostics CSV's columns): kinetic ½ Σ m|u|²,
// elastic Σ V₀ Ψ, gravity −Σ m g·x, p = Σ m u, L = Σ x × m u about the origin.
template <class T, int D>
DiagnosticsRow EolSimulation<T, D>::measure() const {
  DiagnosticsRow r;
  r.step = steps_;
  r.t = time_;
  double kin = 0, grav = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), L = Eigen::Vector3d::Zero();
  for (const auto& o : objects_)
    for (std::size_t i = 0; i < o.grid.size(); ++i) {
      const T m = o.grid.mass[i];
      if (!(m > T(0))) continue;
      const Vec<T, D> mv = m * o.u[i];
      kin += 0.5 * double(m) * double(o.u[i].squaredNorm());
      for (int a = 0; a < D; ++a) {
        p[a] += double(mv[a]);
        grav -= double(m) * scene_.gravity[std::size_t(a)] * double(o.x[i][a]);
      }
      L += cross_moment<T, D>(o.x[i], mv);
    }
  r.kinetic = kin;
  r.kinetic_grid = kin;
  r.elastic = elastic_energy();
  r.potential = r.elastic + grav;
  r.total = r.kinetic + r.potential;
  r.p = {p[0], p[1], p[2]};
  r.L = {L[0], L[1], L[2]};
  r.dt_limit = dt_limit_name(last_limit_);
  for (const auto& o : objects_) {
    r.grid_nodes += double(o.grid.size());
    r.grid_bytes += double(o.grid_bytes());
  }
  return r;
}

template <class T, int D>
double EolSimulation<T, D>::energy_reference() const {
  DiagnosticsRow r = measure();
  double g = 0, height = 0;
  for (int a = 0; a < D; ++a) {
    g += scene_.gravity[std::size_t(a)] * scene_.gravity[std::size_t(a)];
    height += std::pow(scene_.domain.max[std::size_t(a)] - scene_.domain.min[std::size_t(a)], 2);
  }
  // A body at rest shows round-off energy, no blow-up (sim/mpm/implicit/round_off_floor.hpp).
  const double rest = energy_round_off<T>(total_mass() * max_wave_speed_ * max_wave_speed_, D);
  return std::max(
      {r.kinetic + r.elastic + total_mass() * std::sqrt(g) * std::sqrt(height), rest, 1e-300});
}

}  // namespace apiclab::eol
