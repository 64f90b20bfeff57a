// MpmSimulation's construction: particles sampled from the scene's objects, triangulated
// objects (Sec 6.7), the wall and collider rules, and the energy the blow-up check compares to.
#pragma once
#include <algorithm>
#include <cmath>

#include "sim/geometry/sampling.hpp"
#include "sim/mpm/implicit/round_off_floor.hpp"
#include "sim/mpm/kernel_dispatch.hpp"
#include "sim/mpm/mpm.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"

namespace apiclab {

template <class T, int D>
MpmSimulation<T, D>::MpmSimulation(const SceneDesc& scene) : scene_(scene) {
  if (scene.dim != D) throw SceneError(scene.source + ": key 'dim': internal dimension mismatch");
  grid_.init(scene);
  for (auto& m : scene.materials) {
    materials_.push_back({m.model, {T(m.mu()), T(m.lambda())}, {}});
    if (m.model == MaterialModel::plastic)
      materials_.back().plastic = {T(m.yield_stress.value_or(HUGE_VAL)), T(m.flow_rate)};
    max_wave_speed_ = std::max(max_wave_speed_, m.wave_speed());
  }
  for (int o = 0; o < int(scene.objects.size()); ++o) {
    if (scene.objects[size_t(o)].sampling.type == SamplingType::triangulated) {
      if constexpr (D == 2) add_triangulated_object(o);
      continue;
    }
    SampledParticles s = sample_object(scene, o);
    const MaterialDesc& mat = scene.materials[size_t(scene.objects[size_t(o)].material)];
    std::size_t start = p_.size();
    p_.resize(start + s.positions.size());
    for (std::size_t k = 0; k < s.positions.size(); ++k) {
      std::size_t q = start + k;
      for (int a = 0; a < D; ++a) {
        p_.x[q][a] = T(s.positions[k][a]);
        p_.v[q][a] = T(s.velocities[k][a]);
      }
      p_.C[q].setZero();
      p_.F[q].setIdentity();
      p_.volume0[q] = T(s.volumes[k]);
      p_.mass[q] = T(s.volumes[k] * mat.rho);
      p_.material[q] = scene.objects[size_t(o)].material;
      p_.object[q] = o;
      p_.id[q] = std::int32_t(q);
      radius_.push_back(float(0.5 * s.spacing));
    }
  }
  // A rigidly rotating object has the affine velocity C = ω* (APIC/RPIC start with it, Sec 6.1).
  if (is_affine(scene.solver.scheme)) {
    for (std::size_t q = 0; q < p_.size(); ++q) {
      const Vec3d& w = scene.objects[size_t(p_.object[q])].angular_velocity;
      if constexpr (D == 2) {
        p_.C[q] << T(0), T(-w[2]), T(w[2]), T(0);
      } else {
        p_.C[q] << T(0), T(-w[2]), T(w[1]), T(w[2]), T(0), T(-w[0]), T(-w[1]), T(w[0]), T(0);
      }
    }
  }
  allocate_polypic_modes();
  if (std::any_of(materials_.begin(), materials_.end(),
                  [](const MaterialParams<T>& m) { return m.model == MaterialModel::plastic; }))
    p_.fp_inv.assign(p_.size(), Mat<T, D>::Identity());
  rebuild_index_of_id();
  boundary_.init(scene);
  energy_ref_ = energy_reference();
  const DiagnosticsRow start = measure();
  velocity_scale_ =
      std::sqrt(2 * std::max(start.kinetic + start.elastic, 0.0) / std::max(total_mass(), 1e-300));
}

// PolyPIC's higher modes exist only while the scheme is polypic; its C keeps only the linear
// modes among the kept ones (1 mode: C = 0, PIC).
template <class T, int D>
void MpmSimulation<T, D>::allocate_polypic_modes() {
  if (scene_.solver.scheme != Scheme::polypic) {
    p_.set_mode_count(0);
    scratch_.set_mode_count(0);
    return;
  }
  const int kept = polypic::kept_modes(scene_.solver.polypic_modes, D);
  p_.set_mode_count(std::size_t(polypic::extra_modes(kept, D)));
  for (auto& C : p_.C) polypic::keep_linear_modes<T, D>(C, kept);
}

// Particle index of every id (tests may build particles by hand, so ids are not trusted to be
// a permutation: the table is sized by the largest id).
template <class T, int D>
void MpmSimulation<T, D>::rebuild_index_of_id() {
  std::int32_t max_id = -1;
  for (std::int32_t id : p_.id) max_id = std::max(max_id, id);
  index_of_id_.assign(std::size_t(max_id + 1), 0);
  for (std::size_t q = 0; q < p_.size(); ++q)
    if (p_.id[q] >= 0) index_of_id_[std::size_t(p_.id[q])] = std::uint32_t(q);
}

// A 2D box as a regular triangulation (Sec 6.7): a particle per vertex, mass ρ × ⅓ of the
// adjacent triangles' area; elasticity lives on the triangles, so volume0 = 0 on the particles.
template <class T, int D>
void MpmSimulation<T, D>::add_triangulated_object(int o) {
  if constexpr (D == 2) {
    const ObjectDesc& obj = scene_.objects[size_t(o)];
    const MaterialDesc& mat = scene_.materials[size_t(obj.material)];
    const double h = obj.sampling.spacing;
    const int nx = std::max(1, int(std::lround((obj.shape.max[0] - obj.shape.min[0]) / h)));
    const int ny = std::max(1, int(std::lround((obj.shape.max[1] - obj.shape.min[1]) / h)));
    const double hx = (obj.shape.max[0] - obj.shape.min[0]) / nx,
                 hy = (obj.shape.max[1] - obj.shape.min[1]) / ny;
    const std::size_t start = p_.size();
    p_.resize(start + std::size_t(nx + 1) * std::size_t(ny + 1));
    auto vertex = [&](int i, int j) {
      return start + std::size_t(j) * std::size_t(nx + 1) + std::size_t(i);
    };
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        std::size_t q = vertex(i, j);
        p_.x[q] = Vec<T, D>(T(obj.shape.min[0] + i * hx), T(obj.shape.min[1] + j * hy));
        Eigen::Vector3d r(double(p_.x[q][0]) - obj.shape.center[0],
                          double(p_.x[q][1]) - obj.shape.center[1], 0);
        Eigen::Vector3d v = Eigen::Vector3d(obj.velocity[0], obj.velocity[1], 0) +
                            Eigen::Vector3d(0, 0, obj.angular_velocity[2]).cross(r);
        p_.v[q] = Vec<T, D>(T(v[0]), T(v[1]));
        p_.C[q].setZero();
        p_.F[q].setIdentity();
        p_.volume0[q] = T(0);
        p_.mass[q] = T(0);
        p_.material[q] = obj.material;
        p_.object[q] = o;
        p_.id[q] = std::int32_t(q);
        radius_.push_back(float(0.5 * std::min(hx, hy)));
      }
    const MaterialParams<T>& params = materials_[size_t(obj.material)];
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        std::size_t c[4] = {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)};
        for (auto tri : {std::array<std::size_t, 3>{c[0], c[1], c[2]},
                         std::array<std::size_t, 3>{c[0], c[2], c[3]}}) {
          mesh_.add_triangle({std::int32_t(tri[0]), std::int32_t(tri[1]), std::int32_t(tri[2])},
                             p_.x[tri[0]], p_.x[tri[1]], p_.x[tri[2]], params.model, params.lame);
          for (std::size_t q : tri) p_.mass[q] += T(mat.rho * 0.5 * hx * hy / 3.0);
        }
      }
    for (const std::string& row : obj.anchors)
      for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
          bool on = (row == "bottom" && j == 0) || (row == "top" && j == ny) ||
                    (row == "left" && i == 0) || (row == "right" && i == nx);
          if (on)
            mesh_.add_anchor(std::int32_t(vertex(i, j)), p_.x[vertex(i, j)],
                             T(obj.anchor_stiffness));
        }
  }
}
template <class T, int D>
T MpmSimulation<T, D>::inertia_scale() const {
  return T(inertia_factor(scene_.solver.kernel)) * grid_.dx * grid_.dx;
}

// Largest energy the scene can hold without a blow-up: initial kinetic + elastic energy plus
// what gravity can release across the whole domain, and at least what round-off shows in a body
// at rest (sim/mpm/implicit/round_off_floor.hpp), which is no blow-up.
template <class T, int D>
double MpmSimulation<T, D>::energy_reference() const {
  DiagnosticsRow r = measure();
  double g = 0, height = 0;
  for (int a = 0; a < D; ++a) {
    g += scene_.gravity[a] * scene_.gravity[a];
    height += std::pow(scene_.domain.max[a] - scene_.domain.min[a], 2);
  }
  return std::max({r.kinetic + r.elastic + total_mass() * std::sqrt(g) * std::sqrt(height),
                   rest_energy_round_off(), 1e-300});
}

template <class T, int D>
double MpmSimulation<T, D>::rest_energy_round_off() const {
  return energy_round_off<T>(total_mass() * max_wave_speed_ * max_wave_speed_, D);
}

}  // namespace apiclab
