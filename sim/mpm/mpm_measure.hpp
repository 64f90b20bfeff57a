// Energies and momenta of the particle and grid state (the diagnostics CSV's columns).
#pragma once
#include "sim/mpm/kernel_dispatch.hpp"
#include "sim/mpm/mpm.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"

namespace apiclab {

template <class T, int D>
double MpmSimulation<T, D>::elastic_energy() const {
  double e = 0;
  if (stress_of_current_F_) {
    e = particle_elastic_energy_;  // summed by the explicit step's stress pass
  } else {
    const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
#pragma omp parallel for reduction(+ : e) if (parallel_worthwhile())
    for (std::ptrdiff_t q = 0; q < n; ++q) {
      if (p_.volume0[q] == T(0)) continue;  // mesh vertices: their elasticity is on the triangles
      const MaterialParams<T>& mat = materials_[std::size_t(p_.material[q])];
      e += double(p_.volume0[q]) * double(energy_density<T, D>(mat.model, p_.F[q], mat.lame));
    }
  }
  if constexpr (D == 2)
    if (!mesh_.empty()) e += mesh_.energy(p_.x, index_of_id_, nullptr);
  return e;
}

// Energies and momenta of the particle state, with the affine terms ½ m tr(C D Cᵀ) and
// m (Bᵀ : ε), B = C D_p (docs/architecture.md, Diagnostics CSV), and PolyPIC's higher modes.
// A pass of its own over the particles: the readable form of the sums that a step asked for its
// row takes from G2P instead (sim/mpm/particle_sums.hpp); tests hold the two to each other.
template <class T, int D>
ParticleSums MpmSimulation<T, D>::particle_sums() const {
  const bool affine = is_affine(scene_.solver.scheme);
  double kin = 0, grav = 0, px = 0, py = 0, pz = 0, Lx = 0, Ly = 0, Lz = 0;
  const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
  const KernelType kernel = scene_.solver.kernel;
  const Vec3d g = scene_.gravity;
#pragma omp parallel for reduction(+ : kin, grav, px, py, pz, Lx, Ly, Lz) if (parallel_worthwhile())
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const double m = double(p_.mass[q]);
    const Vec<T, D>& v = p_.v[q];
    kin += 0.5 * m * double(v.squaredNorm());
    Vec<T, D> mv = p_.mass[q] * v;
    px += double(mv[0]);
    py += double(mv[1]);
    if constexpr (D == 3) pz += double(mv[2]);
    Eigen::Vector3d L = cross_moment<T, D>(p_.x[q], mv);
    for (int a = 0; a < D; ++a) grav -= m * g[a] * double(p_.x[q][a]);
    if (affine) {
      Mat<T, D> Dp;
      if (kernel == KernelType::linear) {
        Stencil<T, D, LinearKernel> st;
        st.compute(p_.x[q], grid_);
        Dp = st.inertia();
      } else {
        Dp = inertia_scale() * Mat<T, D>::Identity();
      }
      const Mat<T, D>& C = p_.C[q];
      kin += 0.5 * m * double((C * Dp * C.transpose()).trace());
      L += m * permutation_contract<T, D>(Mat<T, D>((C * Dp).transpose()));
    }
    if (!p_.modes.empty()) {
      // PolyPIC's higher modes: ½ m Σ_j |c_j|² Σ_i w s_j² (orthogonal modes); they add no
      // angular momentum, being orthogonal to the linear modes (sim/mpm/schemes/polypic_modes.hpp).
      Stencil<T, D, QuadraticKernel> st;
      st.compute(p_.x[q], grid_);
      kin +=
          0.5 * m *
          double(polypic::modes_energy_density<T, D>(st, grid_.inv_dx, p_.modes, std::size_t(q)));
    }
    Lx += L[0];
    Ly += L[1];
    Lz += L[2];
  }
  ParticleSums s;
  s.kinetic = kin;
  s.gravity = grav;
  s.p = {px, py, pz};
  s.L = {Lx, Ly, Lz};
  return s;
}

template <class T, int D>
DiagnosticsRow MpmSimulation<T, D>::row_of(const ParticleSums& s) const {
  DiagnosticsRow r;
  r.step = steps_;
  r.t = time_;
  r.kinetic_grid = kinetic_grid_;
  r.newton_iters = last_solve_.newton_iterations;
  r.cg_iters = last_solve_.cg_iterations;
  r.residual = last_solve_.residual;
  r.converged = last_solve_.converged;
  r.kinetic = s.kinetic;
  r.elastic = elastic_energy();
  r.potential = r.elastic + s.gravity;
  r.total = r.kinetic + r.potential;
  r.p = s.p;
  r.L = s.L;
  r.ledger = scene_.solver.ledger;  // its stages are the step's (with_ledger), zero for a state
  return r;
}

template <class T, int D>
DiagnosticsRow MpmSimulation<T, D>::measure() const {
  return row_of(particle_sums());
}

template <class T, int D>
void MpmSimulation<T, D>::grid_momentum(bool updated, Eigen::Vector3d& p,
                                        Eigen::Vector3d& L) const {
  p.setZero();
  L.setZero();
  const auto& vel = updated ? grid_.velocity_new : grid_.velocity;
  for (std::size_t i = 0; i < grid_.size(); ++i) {
    if (grid_.mass[i] <= T(0)) continue;
    Vec<T, D> mv = grid_.mass[i] * vel[i];
    for (int a = 0; a < D; ++a) p[a] += double(mv[a]);
    L += cross_moment<T, D>(grid_.node_position(i), mv);
  }
}

template <class T, int D>
Eigen::Vector3d MpmSimulation<T, D>::total_force() const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < grid_.size(); ++i)
    for (int a = 0; a < D; ++a) f[a] += double(grid_.force[i][a]);
  return f;
}

}  // namespace apiclab
