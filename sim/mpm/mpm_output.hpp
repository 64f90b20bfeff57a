// What leaves the solver: scheme switching, drawing snapshots, velocity noise, particle CSV, the
// reference step on the same particles.
#pragma once
#include <iomanip>
#include <limits>
#include <ostream>

#include "sim/mpm/kernel_dispatch.hpp"
#include "sim/mpm/mpm.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"
#include "sim/reference/reference_run.hpp"

namespace apiclab {

template <class T, int D>
void MpmSimulation<T, D>::set_scheme(Scheme scheme, double flip_alpha) {
  const bool was_affine = is_affine(scene_.solver.scheme);
  scene_.solver.scheme = scheme;
  scene_.solver.flip_alpha = flip_alpha;
  ledger_.forget_start();    // the particles' sums count C by the scheme
  if (!is_affine(scheme)) {  // PIC, FLIP, XPIC: no C_p
    for (auto& C : p_.C) C.setZero();
  } else if (scheme == Scheme::rpic && was_affine) {
    for (auto& C : p_.C) C = schemes::Rpic::skew_part(C);  // returns a new matrix: C is not aliased
  }
  allocate_polypic_modes();  // zero higher modes when switching to polypic, none otherwise
  // XPIC's node arrays exist only while it runs with m > 1 ("model no more than a scene needs");
  // swapped with empty vectors, since clear() keeps the capacity.
  if (scheme != Scheme::xpic || scene_.solver.xpic_order <= 1) {
    std::vector<Vec<T, D>>().swap(xpic_term_);
    std::vector<Vec<T, D>>().swap(xpic_shift_);
  }
}

template <class T, int D>
std::size_t MpmSimulation<T, D>::state_bytes() const {
  return p_.allocated_bytes() + scratch_.allocated_bytes() + grid_.allocated_bytes() +
         xpic_capacity() * sizeof(Vec<T, D>);
}

template <class T, int D>
std::unique_ptr<ReferenceRun> MpmSimulation<T, D>::reference_run() const {
  return reference::run_of<T, D>(scene_, p_);
}

// |v_p − Σ w_ip v_i| with v_i from a fresh P2G of the current particles (this scheme's own
// transfer, so an affine field gives zero): velocity modes the grid cannot see.
template <class T, int D>
template <class K>
void MpmSimulation<T, D>::velocity_noise(std::vector<float>& out) const {
  const bool affine = is_affine(scene_.solver.scheme);
  // Its own region: the particles may have moved past the stored box since the last sort.
  GridGeometry<T, D> g = grid_;
  std::array<int, D> first, last;
  first.fill(std::numeric_limits<int>::max());
  last.fill(std::numeric_limits<int>::min());
  for (std::size_t q = 0; q < p_.size(); ++q)
    for (int a = 0; a < D; ++a) {
      const int cell = int(std::floor((p_.x[q][a] - g.origin[a]) * g.inv_dx));
      first[a] = std::min(first[a], cell - K::width);  // a stencil spans base..base+W-1 around
      last[a] = std::max(last[a], cell + K::width + 1);
    }
  for (int a = 0; a < D; ++a) {
    first[a] = std::max(first[a], 0);
    last[a] = std::min(last[a], g.n[a]);
  }
  std::vector<T> mass(p_.size() == 0 ? 0 : g.set_region(first, last), T(0));
  std::vector<Vec<T, D>> mom(mass.size(), Vec<T, D>::Zero());
  Stencil<T, D, K> st;
  for (std::size_t q = 0; q < p_.size(); ++q) {
    st.compute(p_.x[q], g);
    const T m = p_.mass[q];
    st.for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>& r) {
      mass[i] += w * m;
      mom[i] += w * m * (affine ? Vec<T, D>(p_.v[q] + p_.C[q] * r) : p_.v[q]);
    });
    if constexpr (K::type == KernelType::quadratic)  // PolyPIC's higher modes, if any
      polypic::scatter_modes<T, D>(
          st, grid_.inv_dx, p_.modes, q,
          [&](std::size_t i, T w, const Vec<T, D>& v) { mom[i] += w * m * v; });
  }
  out.assign(p_.size(), 0.f);
  for (std::size_t q = 0; q < p_.size(); ++q) {
    st.compute(p_.x[q], g);
    Vec<T, D> v = Vec<T, D>::Zero();
    st.for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) {
      if (mass[i] > T(0)) v += w * mom[i] / mass[i];
    });
    out[std::size_t(p_.id[q])] = float((p_.v[q] - v).norm());
  }
}

template <class T, int D>
std::shared_ptr<Snapshot> MpmSimulation<T, D>::snapshot() const {
  std::shared_ptr<Snapshot> s = scene_snapshot();
  s->scheme = key_of(scene_.solver.scheme);
  s->kernel = key_of(scene_.solver.kernel);
  s->integrator = integrator_label(scene_.solver);
  s->flip_alpha = scene_.solver.flip_alpha;
  s->scheme_parameters = scheme_parameters_of(scene_);
  const std::size_t n = p_.size();
  s->positions.resize(n * D);
  s->velocities.resize(n * D);
  s->material.resize(n);
  s->object.resize(n);
  for (std::size_t q = 0; q < n; ++q) {
    std::size_t k = std::size_t(p_.id[q]);
    for (int a = 0; a < D; ++a) {
      s->positions[k * D + a] = float(p_.x[q][a]);
      s->velocities[k * D + a] = float(p_.v[q][a]);
    }
    s->material[k] = p_.material[q];
    s->object[k] = p_.object[q];
  }
  s->radius = radius_;
  for (auto& o : scene_.objects) s->object_names.push_back(o.name);
  return s;
}

template <class T, int D>
void MpmSimulation<T, D>::fill_velocity_noise(Snapshot& s) const {
  with_kernel(scene_.solver.kernel,
              [&](auto kernel) { velocity_noise<decltype(kernel)>(s.noise); });
}

template <class T, int D>
ParticleTable MpmSimulation<T, D>::particle_table() const {
  ParticleTable t;
  t.dim = D;
  t.digits = std::numeric_limits<T>::max_digits10;
  t.count = p_.size();
  std::vector<std::size_t> by_id(p_.size());
  for (std::size_t q = 0; q < p_.size(); ++q) by_id[std::size_t(p_.id[q])] = q;
  const char* axis = "xyz";
  auto column = [&](std::string name, std::vector<std::string> csv, bool integer, auto get) {
    ParticleColumn c{std::move(name), std::move(csv), integer, {}};
    c.values.reserve(t.count * c.csv_names.size());
    for (std::size_t q : by_id) get(q, c.values);
    t.columns.push_back(std::move(c));
  };
  std::vector<std::string> x, v, F, C;
  for (int a = 0; a < D; ++a) {
    x.push_back(std::string(1, axis[a]));
    v.push_back("v" + std::string(1, axis[a]));
  }
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) {
      F.push_back("F" + std::to_string(i) + std::to_string(j));
      C.push_back("C" + std::to_string(i) + std::to_string(j));
    }
  column("id", {"id"}, true, [&](std::size_t q, auto& o) { o.push_back(p_.id[q]); });
  column("object", {"object"}, true, [&](std::size_t q, auto& o) { o.push_back(p_.object[q]); });
  column("position", x, false, [&](std::size_t q, auto& o) {
    for (int a = 0; a < D; ++a) o.push_back(double(p_.x[q][a]));
  });
  column("velocity", v, false, [&](std::size_t q, auto& o) {
    for (int a = 0; a < D; ++a) o.push_back(double(p_.v[q][a]));
  });
  column("mass", {"mass"}, false, [&](std::size_t q, auto& o) { o.push_back(double(p_.mass[q])); });
  column("volume0", {"volume0"}, false,
         [&](std::size_t q, auto& o) { o.push_back(double(p_.volume0[q])); });
  column("F", F, false, [&](std::size_t q, auto& o) {
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) o.push_back(double(p_.F[q](i, j)));
  });
  column("C", C, false, [&](std::size_t q, auto& o) {
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) o.push_back(double(p_.C[q](i, j)));
  });
  return t;
}

template <class T, int D>
void MpmSimulation<T, D>::write_particles_csv(std::ostream& out) const {
  apiclab::write_particles_csv(out, particle_table());
}

}  // namespace apiclab
