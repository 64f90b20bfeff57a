// Implicit grid updates (Jiang et al. 2017, Secs 3.4, 4.1-4.2): the λ-family of eqs 27-30 for
// λ in (0, 1) (midpoint at λ = ½) and backward Euler, solved as a minimisation.
// Included by mpm_impl.hpp only.
//
// With Δv_i = ṽ_i − v_i the forces are evaluated at y_i = x_i + Δt (a v_i + b Δv_i):
//   λ-family: a = λ, b = λ(1 − λ)   (F^{n+λ} of eq 28, written through x̃ of eq 30)
//   backward: a = 1, b = 1           (x̃ = x + Δt ṽ)
// and m_i Δv_i = Δt (f_i(y) + m_i g) is the stationarity condition of
//   E(Δv) = Σ ½ m_i |Δv_i|² − Δt Σ m_i g·Δv_i + Φ(y(Δv)) / b        (Sec 4.1 scaled by 1/b)
// whose Hessian is M + b Δt² K, K = ∂²Φ/∂y². Newton with a backtracking line search on E
// (Gast et al. 2015); each Newton system is solved by conjugate gradients on M⁻¹H in the
// mass inner product (Algorithm 1), so every CG vector is velocity-like and linear momentum
// is conserved however early CG stops (Sec 4.2).
#pragma once
#include <Eigen/Eigenvalues>

#include "mpm.hpp"

namespace apiclab {

template <class T, int D>
template <class Fn>
void MpmSimulation<T, D>::for_each_particle_coloured(Fn&& fn) {
  for (const auto& blocks : color_blocks_) {
    const std::ptrdiff_t nb = std::ptrdiff_t(blocks.size());
// Contiguous chunks: neighbouring same-coloured blocks share cache lines, so they go to one thread.
#pragma omp parallel for schedule(static) if (parallel_worthwhile())
    for (std::ptrdiff_t bi = 0; bi < nb; ++bi) {
      const std::uint32_t b = blocks[std::size_t(bi)];
      for (std::uint32_t q = block_start_[b]; q < block_start_[b + 1]; ++q) fn(q);
    }
  }
}

template <class T, int D>
void project_on_constraint(Vec<T, D>& v, const ConstrainedNode<T, D>& c);

// Per-particle ∂P/∂F as a D²×D² matrix at F, symmetrised and projected to be positive
// semi-definite (negative eigenvalues clamped to zero, as Stomakhin et al. 2012 and Teran et
// al. 2005 do per particle), so CG always sees a positive definite M + bΔt²K.
template <class T, int D>
Eigen::Matrix<T, D * D, D * D> projected_stress_hessian(MaterialModel model, const Mat<T, D>& F, Lame<T> l) {
  constexpr int N = D * D;
  Eigen::Matrix<T, N, N> H;
  for (int c = 0; c < N; ++c) {
    Mat<T, D> E = Mat<T, D>::Zero();
    E(c % D, c / D) = T(1);  // column-major vec
    Mat<T, D> dP = first_piola_differential<T, D>(model, F, E, l);
    H.col(c) = Eigen::Map<const Eigen::Matrix<T, N, 1>>(dP.data());
  }
  H = (T(0.5) * (H + H.transpose())).eval();  // eval: H aliases Hᵀ
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<T, N, N>> eig(H);
  Eigen::Matrix<T, N, 1> ev = eig.eigenvalues();
  if (ev.minCoeff() >= T(0)) return H;
  ev = ev.cwiseMax(T(0));
  return eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose();
}

template <class T, int D>
template <class K>
void MpmSimulation<T, D>::implicit_begin(T dt) {
  const bool backward = scene_.solver.integrator == Integrator::backward;
  const T lambda = T(scene_.solver.integrator_lambda());
  imp_dt_ = dt;
  imp_a_ = backward ? T(1) : lambda;
  imp_b_ = backward ? T(1) : lambda * (T(1) - lambda);
  const std::size_t nn = grid_.size();
  for (int ax = 0; ax < D; ++ax) imp_gravity_[ax] = T(scene_.gravity[ax]);

  // The weights P2G cached this step (stencils<K>()) serve every product below.
  // Active nodes and the velocity v_i^n.
  // Only the active box can hold mass (see set_active_box); outside it everything stays zero.
  active_.clear();
  for (const auto& [start, length] : box_rows_)
    for (std::size_t i = start; i < start + length; ++i) {
      if (grid_.mass[i] > T(0)) {
        grid_.velocity[i] /= grid_.mass[i];
        active_.push_back(std::uint32_t(i));
      } else {
        grid_.velocity[i].setZero();
      }
    }
  double kinetic = 0, vref2 = 0;
  imp_msum_ = 0;
  for (std::uint32_t i : active_) {
    kinetic += 0.5 * double(grid_.mass[i]) * double(grid_.velocity[i].squaredNorm());
    vref2 += double(grid_.mass[i]) * double(grid_.velocity[i].squaredNorm());
    imp_msum_ += double(grid_.mass[i]);
  }
  kinetic_grid_ = kinetic;
  imp_vref_ = std::sqrt(vref2 / std::max(imp_msum_, 1e-300));
  for (auto* v : {&dv_, &grad_, &dir_, &cg_r_, &cg_p_, &cg_s_, &work_}) {
    if (v->size() != nn) v->assign(nn, Vec<T, D>::Zero());
    for_each_box_node([&](std::size_t i) { (*v)[i].setZero(); });
  }
  Fy_.resize(p_.size());
  hess_.resize(p_.size());

  // Boundary conditions as linear constraints on ṽ: Δv = P z + d. Separating walls act as slip
  // where the material moves into them at the start of the step, and are free otherwise.
  active_constraints_.clear();
  for (const auto& c : constraints_) {
    if (grid_.mass[c.node] <= T(0)) continue;
    if (c.condition == BoundaryCondition::separate && grid_.velocity[c.node].dot(c.normal) >= T(0)) continue;
    active_constraints_.push_back(c);
  }
  for (const auto& c : active_constraints_) {  // d: makes ṽ = v + d satisfy the constraints
    Vec<T, D> v = grid_.velocity[c.node] + dv_[c.node];
    project_on_constraint(v, c);
    dv_[c.node] = v - grid_.velocity[c.node];
  }
}

// An active constraint as a projection: sticky removes the velocity, slip (and a separating
// wall being pushed into) its normal component.
template <class T, int D>
void project_on_constraint(Vec<T, D>& v, const ConstrainedNode<T, D>& c) {
  if (c.condition == BoundaryCondition::sticky) v.setZero();
  else v -= v.dot(c.normal) * c.normal;
}

template <class T, int D>
void MpmSimulation<T, D>::implicit_project(std::vector<Vec<T, D>>& z) const {
  for (const auto& c : active_constraints_) project_on_constraint(z[c.node], c);
}

// E(Δv) with F evaluated at the force position y (kept in Fy_); fills grad_ when asked.
template <class T, int D>
template <class K>
double MpmSimulation<T, D>::implicit_energy(const std::vector<Vec<T, D>>& dv, bool gradient) {
  const auto& st = stencils<K>();
  const T a = imp_a_, b = imp_b_, dt = imp_dt_;
  const std::ptrdiff_t np = std::ptrdiff_t(p_.size());
  double phi = 0;
  bool inverted = false;
  const bool mesh = !mesh_.empty();
  if constexpr (D == 2)
    if (mesh) mesh_x_.resize(p_.size());
#pragma omp parallel for schedule(static) reduction(+ : phi) reduction(|| : inverted) if (parallel_worthwhile())
  for (std::ptrdiff_t q = 0; q < np; ++q) {
    Mat<T, D> G = Mat<T, D>::Zero();
    Vec<T, D> u = Vec<T, D>::Zero();
    st[std::size_t(q)].for_each([&](std::size_t i, T w, const Vec<T, D>& gw, const Vec<T, D>&) {
      const Vec<T, D> ui = a * grid_.velocity[i] + b * dv[i];
      G += ui * gw.transpose();
      u += w * ui;
    });
    if constexpr (D == 2)
      if (mesh) mesh_x_[std::size_t(q)] = p_.x[std::size_t(q)] + dt * u;  // x_p(y) = Σ w_ip y_i
    Mat<T, D> F = (Mat<T, D>::Identity() + dt * G) * p_.F[std::size_t(q)];
    Fy_[std::size_t(q)] = F;
    if (p_.volume0[std::size_t(q)] == T(0)) continue;  // mesh vertices carry no particle elasticity
    const MaterialParams<T>& mat = materials_[std::size_t(p_.material[std::size_t(q)])];
    T psi = energy_density<T, D>(mat.model, F, mat.lame);
    if (!std::isfinite(double(psi))) inverted = true;
    phi += double(p_.volume0[std::size_t(q)]) * double(psi);
  }
  if constexpr (D == 2)
    if (mesh) {
      if (gradient) mesh_g_.assign(p_.size(), Vec<T, 2>::Zero());
      phi += mesh_.energy(mesh_x_, index_of_id_, gradient ? &mesh_g_ : nullptr);
      if (!std::isfinite(phi)) inverted = true;
    }
  if (inverted) return std::numeric_limits<double>::infinity();
  double e = b > T(0) ? phi / double(b) : 0.0;
  for (std::uint32_t i : active_)
    e += double(grid_.mass[i]) * (0.5 * double(dv[i].squaredNorm()) - double(dt) * double(imp_gravity_.dot(dv[i])));
  if (gradient) {
    // g = M Δv − Δt M g − Δt f(y), f_i = −Σ V P(F_y) F^nᵀ ∇w (eq 34).
    for (std::uint32_t i : active_) grad_[i] = grid_.mass[i] * (dv[i] - dt * imp_gravity_);
    for_each_particle_coloured([&](std::uint32_t q) {
      const MaterialParams<T>& mat = materials_[std::size_t(p_.material[q])];
      Mat<T, D> stress = (dt * p_.volume0[q]) * first_piola<T, D>(mat.model, Fy_[q], mat.lame) * p_.F[q].transpose();
      st[q].for_each([&](std::size_t i, T, const Vec<T, D>& gw, const Vec<T, D>&) { grad_[i] += stress * gw; });
    });
    if constexpr (D == 2)
      if (mesh)  // ∂(Φ_mesh / b)/∂Δv_i = Δt Σ_p w_ip ∂Φ/∂x_p
        for_each_particle_coloured([&](std::uint32_t q) {
          const Vec<T, 2> gq = dt * mesh_g_[q];
          st[q].for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) { grad_[i] += w * gq; });
        });
  }
  return e;
}

template <class T, int D>
void MpmSimulation<T, D>::implicit_update_hessian(bool project_definite) {
  if constexpr (D == 2)
    if (!mesh_.empty()) mesh_.update_hessian(mesh_x_, index_of_id_, project_definite);
  const std::ptrdiff_t np = std::ptrdiff_t(p_.size());
  constexpr int N = D * D;
#pragma omp parallel for schedule(static) if (parallel_worthwhile())
  for (std::ptrdiff_t q = 0; q < np; ++q) {
    const MaterialParams<T>& mat = materials_[std::size_t(p_.material[std::size_t(q)])];
    const Mat<T, D>& F = Fy_[std::size_t(q)];
    if (project_definite) {
      hess_[std::size_t(q)] = projected_stress_hessian<T, D>(mat.model, F, mat.lame);
    } else {
      for (int c = 0; c < N; ++c) {
        Mat<T, D> E = Mat<T, D>::Zero();
        E(c % D, c / D) = T(1);
        Mat<T, D> dP = first_piola_differential<T, D>(mat.model, F, E, mat.lame);
        hess_[std::size_t(q)].col(c) = Eigen::Map<const Eigen::Matrix<T, N, 1>>(dP.data());
      }
    }
  }
}

// out = H in = M in + b Δt² K in with the per-particle ∂P/∂F in hess_ (eqs 35-36).
template <class T, int D>
template <class K>
void MpmSimulation<T, D>::implicit_hessian_apply(const std::vector<Vec<T, D>>& in, std::vector<Vec<T, D>>& out) {
  constexpr int N = D * D;
  const auto& st = stencils<K>();
  const T b = imp_b_, dt = imp_dt_;
  for (std::uint32_t i : active_) out[i] = grid_.mass[i] * in[i];
  for_each_particle_coloured([&](std::uint32_t q) {
    Mat<T, D> G = Mat<T, D>::Zero();
    st[q].for_each([&](std::size_t i, T, const Vec<T, D>& gw, const Vec<T, D>&) { G += in[i] * gw.transpose(); });
    Mat<T, D> dF = (b * dt) * G * p_.F[q];
    Mat<T, D> dP;
    Eigen::Map<Eigen::Matrix<T, N, 1>>(dP.data()) = hess_[q] * Eigen::Map<const Eigen::Matrix<T, N, 1>>(dF.data());
    Mat<T, D> s = (dt * p_.volume0[q]) * dP * p_.F[q].transpose();
    st[q].for_each([&](std::size_t i, T, const Vec<T, D>& gw, const Vec<T, D>&) { out[i] += s * gw; });
  });
  if constexpr (D == 2)
    if (!mesh_.empty()) {  // b Δt² Σ_p w_ip (K δx)_p with δx_p = Σ_j w_jp δ_j
      mesh_dx_.assign(p_.size(), Vec<T, 2>::Zero());
      mesh_kx_.assign(p_.size(), Vec<T, 2>::Zero());
      for (std::size_t q = 0; q < p_.size(); ++q)
        st[q].for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) { mesh_dx_[q] += w * in[i]; });
      mesh_.apply_hessian(mesh_dx_, index_of_id_, mesh_kx_);
      for_each_particle_coloured([&](std::uint32_t q) {
        const Vec<T, 2> k = (b * dt * dt) * mesh_kx_[q];
        st[q].for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) { out[i] += w * k; });
      });
    }
}

template <class T, int D>
template <class K>
void MpmSimulation<T, D>::implicit_velocity_update(T dt) {
  implicit_begin<K>(dt);
  if (imp_b_ == T(0)) {  // λ = 1: explicit, forces at y = x + Δt v
    implicit_energy<K>(dv_, true);
    for (std::uint32_t i : active_) dv_[i] = -grad_[i] / grid_.mass[i];
    implicit_project(dv_);
    for_each_box_node([&](std::size_t i) { grid_.velocity_new[i] = grid_.velocity[i] + dv_[i]; });
    last_newton_iters_ = last_cg_iters_ = 0;
    last_residual_ = 0;
    last_converged_ = true;
    return;
  }
  auto dot_m = [&](const std::vector<Vec<T, D>>& u, const std::vector<Vec<T, D>>& w) {
    double s = 0;
    for (std::uint32_t i : active_) s += double(grid_.mass[i]) * double(u[i].dot(w[i]));
    return s;
  };
  const double vref = std::max({imp_vref_, double(imp_gravity_.norm() * dt), 1e-12});
  const double tol = scene_.solver.newton_tolerance * vref;
  double energy = implicit_energy<K>(dv_, true);
  int newton = 0, cg_total = 0;
  double residual = 0;
  residuals_.clear();
  for (;; ++newton) {
    implicit_project(grad_);
    // Residual: mass-weighted RMS of M⁻¹g, a velocity.
    double r2 = 0;
    for (std::uint32_t i : active_) r2 += double(grad_[i].squaredNorm()) / double(grid_.mass[i]);
    residual = std::sqrt(r2 / std::max(imp_msum_, 1e-300));
    residuals_.push_back(residual);
    if (residual <= tol || newton >= scene_.solver.newton_max_iterations) break;
    implicit_update_hessian(true);
    // CG on A = M⁻¹ P H P, rhs = −M⁻¹ P g, inner product <u, w> = uᵀ M w (Algorithm 1).
    for (std::uint32_t i : active_) { dir_[i].setZero(); cg_r_[i] = -grad_[i] / grid_.mass[i]; cg_p_[i] = cg_r_[i]; }
    double gamma = dot_m(cg_r_, cg_r_), rhs_norm = std::sqrt(gamma);
    for (int k = 0; k < scene_.solver.cg_max_iterations; ++k) {
      if (std::sqrt(gamma) <= scene_.solver.cg_tolerance * rhs_norm) break;
      implicit_hessian_apply<K>(cg_p_, cg_s_);
      for (std::uint32_t i : active_) cg_s_[i] /= grid_.mass[i];
      implicit_project(cg_s_);
      double ps = dot_m(cg_p_, cg_s_);
      ++cg_total;
      if (!(ps > 0)) break;
      T alpha = T(gamma / ps);
      for (std::uint32_t i : active_) { dir_[i] += alpha * cg_p_[i]; cg_r_[i] -= alpha * cg_s_[i]; }
      double kappa = dot_m(cg_r_, cg_r_);
      T beta = T(kappa / gamma);
      for (std::uint32_t i : active_) cg_p_[i] = cg_r_[i] + beta * cg_p_[i];
      gamma = kappa;
    }
    // Backtracking line search on E (Armijo), never accepting an inverted F (E = +∞).
    double slope = 0;
    for (std::uint32_t i : active_) slope += double(grad_[i].dot(dir_[i]));
    if (!(slope < 0)) {  // not a descent direction: fall back to steepest descent in M⁻¹
      for (std::uint32_t i : active_) dir_[i] = -grad_[i] / grid_.mass[i];
      slope = 0;
      for (std::uint32_t i : active_) slope += double(grad_[i].dot(dir_[i]));
    }
    double step = 1, trial = 0;
    for (int ls = 0; ls < 30; ++ls, step *= 0.5) {
      for (std::uint32_t i : active_) work_[i] = dv_[i] + T(step) * dir_[i];
      trial = implicit_energy<K>(work_, false);
      if (trial <= energy + 1e-4 * step * slope) break;
    }
    if (!(trial <= energy + 1e-4 * step * slope)) break;  // no progress possible at this precision
    for (std::uint32_t i : active_) dv_[i] = work_[i];
    energy = implicit_energy<K>(dv_, true);
  }
  last_newton_iters_ = newton;
  last_cg_iters_ = cg_total;
  last_residual_ = residual;
  last_converged_ = residual <= tol;
  for_each_box_node([&](std::size_t i) { grid_.velocity_new[i] = grid_.velocity[i] + dv_[i]; });
}

}  // namespace apiclab
