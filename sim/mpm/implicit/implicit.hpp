// Implicit grid updates (Jiang et al. 2017, Secs 3.4, 4.1-4.2): the λ-family of eqs 27-30 for
// λ in (0, 1) (midpoint at λ = ½) and backward Euler, solved as a minimisation.
// Included by phases.hpp only.
//
// With Δv_i = ṽ_i − v_i the forces are evaluated at y_i = x_i + Δt (a v_i + b Δv_i):
//   λ-family: a = λ, b = λ(1 − λ)   (F^{n+λ} of eq 28, written through x̃ of eq 30)
//   backward: a = 1, b = 1           (x̃ = x + Δt ṽ)
// and m_i Δv_i = Δt (f_i(y) + m_i g) is the stationarity condition of
//   E(Δv) = Σ ½ m_i |Δv_i|² − Δt Σ m_i g·Δv_i + Φ(y(Δv)) / b        (Sec 4.1 scaled by 1/b)
// whose Hessian is M + b Δt² K, K = ∂²Φ/∂y². Newton with a backtracking line search on E
// (Gast et al. 2015); each Newton system is solved by preconditioned conjugate gradients:
// solver.preconditioner mass is CG on M⁻¹H in the mass inner product (Algorithm 1, Sec 4.2:
// every CG vector velocity-like, Σ m v kept however early CG stops when no external force
// acts), block-jacobi inverts H's node blocks and deflates the uniform velocities (Σ m v kept
// with gravity too). The Newton-CG loop itself is generic (sim/mpm/implicit/newton_cg.hpp); its
// state lives in ImplicitSolveState (sim/mpm/implicit/implicit_state.hpp).
#pragma once
#include "sim/mpm/implicit/round_off_floor.hpp"
#include "sim/mpm/implicit/stress_hessian.hpp"
#include "sim/mpm/mpm.hpp"

namespace apiclab {

template <class T, int D>
void project_on_constraint(Vec<T, D>& v, const ConstrainedNode<T, D>& c);

template <class T, int D>
template <class K>
void MpmSimulation<T, D>::implicit_begin(T dt) {
  const bool backward = scene_.solver.integrator == Integrator::backward;
  const T lambda = T(scene_.solver.integrator_lambda());
  imp_.dt = dt;
  imp_.a = backward ? T(1) : lambda;
  imp_.b = backward ? T(1) : lambda * (T(1) - lambda);
  const std::size_t nn = grid_.size();
  for (int ax = 0; ax < D; ++ax) imp_.gravity[ax] = T(scene_.gravity[ax]);

  // The weights P2G cached this step (stencils<K>()) serve every product below.
  // Active nodes and the velocity v_i^n.
  // Only the active box can hold mass (see set_active_box); outside it everything stays zero.
  imp_.active.clear();
  for (const auto& [start, length] : blocks_.box_rows())
    for (std::size_t i = start; i < start + length; ++i)
      if (has_mass(i)) imp_.active.push_back(std::uint32_t(i));
  double kinetic = 0, vref2 = 0;
  imp_.mass_sum = 0;
  for (std::uint32_t i : imp_.active) {
    kinetic += 0.5 * double(grid_.mass[i]) * double(grid_.velocity[i].squaredNorm());
    vref2 += double(grid_.mass[i]) * double(grid_.velocity[i].squaredNorm());
    imp_.mass_sum += double(grid_.mass[i]);
  }
  kinetic_grid_ = kinetic;
  imp_.velocity_ref = std::sqrt(vref2 / std::max(imp_.mass_sum, 1e-300));
  for (auto* v : {&imp_.dv, &imp_.grad, &imp_.cg.direction, &imp_.cg.residual, &imp_.cg.precond,
                  &imp_.cg.search, &imp_.cg.product, &imp_.cg.trial}) {
    if (v->size() != nn) v->assign(nn, Vec<T, D>::Zero());
    for_each_box_node([&](std::size_t i) { (*v)[i].setZero(); });
  }
  imp_.Fy.resize(p_.size());
  imp_.stiffness.resize(p_.size());
  if (scene_.solver.preconditioner == CgPreconditioner::block_jacobi &&
      imp_.block_inverse.size() != nn)
    imp_.block_inverse.resize(nn);

  // Boundary conditions as linear constraints on ṽ: Δv = P z + d. Separating walls act as slip
  // where the material moves into them at the start of the step, and are free otherwise.
  imp_.constraints.clear();
  for (const auto& c : blocks_.box_constraints()) {
    if (grid_.mass[c.node] <= T(0)) continue;
    if (c.condition == BoundaryCondition::separate &&
        (grid_.velocity[c.node] - c.body).dot(c.normal) >= T(0))
      continue;
    imp_.constraints.push_back(c);
  }
  for (const auto& c : imp_.constraints) {  // d: makes ṽ = v + d satisfy the constraints
    Vec<T, D> v = grid_.velocity[c.node] + imp_.dv[c.node];
    if (c.condition == BoundaryCondition::sticky)  // the body's velocity, relative to it
      v = c.body;
    else
      v -= (v - c.body).dot(c.normal) * c.normal;
    imp_.dv[c.node] = v - grid_.velocity[c.node];
  }
}

// An active constraint as a projection: sticky removes the velocity, slip (and a separating
// wall being pushed into) its normal component.
template <class T, int D>
void project_on_constraint(Vec<T, D>& v, const ConstrainedNode<T, D>& c) {
  if (c.condition == BoundaryCondition::sticky)
    v.setZero();
  else
    v -= v.dot(c.normal) * c.normal;
}

template <class T, int D>
void MpmSimulation<T, D>::implicit_project(std::vector<Vec<T, D>>& z) const {
  for (const auto& c : imp_.constraints) project_on_constraint(z[c.node], c);
}

// E(Δv) with F evaluated at the force position y (kept in imp_.Fy); fills imp_.grad when asked.
template <class T, int D>
template <class K>
double MpmSimulation<T, D>::implicit_energy(const std::vector<Vec<T, D>>& dv, bool gradient) {
  const auto& st = stencils<K>();
  const T a = imp_.a, b = imp_.b, dt = imp_.dt;
  const std::ptrdiff_t np = std::ptrdiff_t(p_.size());
  double phi = 0, phi_terms = 0;  // Σ V Ψ, and the size of the terms it sums (its round-off)
  bool inverted = false;
  const bool mesh = !mesh_.empty();
  if constexpr (D == 2)
    if (mesh) mesh_x_.resize(p_.size());
#pragma omp parallel for schedule(static) reduction(+ : phi, phi_terms) reduction(|| : inverted) if (parallel_worthwhile())
  for (std::ptrdiff_t q = 0; q < np; ++q) {
    Mat<T, D> G = Mat<T, D>::Zero();
    Vec<T, D> u = Vec<T, D>::Zero();
    st[std::size_t(q)].for_each([&](std::size_t i, T w, const Vec<T, D>& gw, const Vec<T, D>&) {
      const Vec<T, D> ui = a * grid_.velocity[i] + b * dv[i];
      for (int c = 0; c < D; ++c) G.col(c) += gw[c] * ui;  // not ui gwᵀ: see gradient_gather
      u += w * ui;
    });
    if constexpr (D == 2)
      if (mesh) mesh_x_[std::size_t(q)] = p_.x[std::size_t(q)] + dt * u;  // x_p(y) = Σ w_ip y_i
    Mat<T, D> F = (Mat<T, D>::Identity() + dt * G) * p_.F[std::size_t(q)];
    imp_.Fy[std::size_t(q)] = F;
    if (p_.volume0[std::size_t(q)] == T(0)) continue;  // mesh vertices carry no particle elasticity
    const MaterialParams<T>& mat = materials_[std::size_t(p_.material[std::size_t(q)])];
    T psi = energy_density<T, D>(mat.model, F, mat.lame);
    if (!std::isfinite(double(psi))) inverted = true;
    phi += double(p_.volume0[std::size_t(q)]) * double(psi);
    phi_terms += double(p_.volume0[std::size_t(q)]) *
                 (double(mat.lame.lambda + 2 * mat.lame.mu) * double(F.squaredNorm() + 1) +
                  std::abs(double(psi)));
  }
  if constexpr (D == 2)
    if (mesh) {
      if (gradient) mesh_g_.assign(p_.size(), Vec<T, 2>::Zero());
      phi += mesh_.energy(mesh_x_, index_of_id_, gradient ? &mesh_g_ : nullptr, &phi_terms);
      if (!std::isfinite(phi)) inverted = true;
    }
  if (inverted) return std::numeric_limits<double>::infinity();
  double e = b > T(0) ? phi / double(b) : 0.0;
  double kinetic_terms = 0;
  for (std::uint32_t i : imp_.active) {
    const double half_dv2 = 0.5 * double(dv[i].squaredNorm());
    const double work = double(dt) * double(imp_.gravity.dot(dv[i]));
    e += double(grid_.mass[i]) * (half_dv2 - work);
    kinetic_terms += double(grid_.mass[i]) * (half_dv2 + std::abs(work));
  }
  // Each term is off by ε_T of its size (sim/mpm/implicit/round_off_floor.hpp): E is known to no
  // better.
  imp_.energy_round_off = double(std::numeric_limits<T>::epsilon()) *
                          ((b > T(0) ? phi_terms / double(b) : 0.0) + kinetic_terms);
  if (gradient) {
    // g = M Δv − Δt M g − Δt f(y), f_i = −Σ V P(F_y) F^nᵀ ∇w (eq 34).
    for (std::uint32_t i : imp_.active) imp_.grad[i] = grid_.mass[i] * (dv[i] - dt * imp_.gravity);
    for_each_particle_coloured([&](std::uint32_t q) {
      const MaterialParams<T>& mat = materials_[std::size_t(p_.material[q])];
      Mat<T, D> stress = (dt * p_.volume0[q]) * first_piola<T, D>(mat.model, imp_.Fy[q], mat.lame) *
                         p_.F[q].transpose();
      st[q].gradient_scatter(stress, imp_.grad.data());
    });
    if constexpr (D == 2)
      if (mesh)  // ∂(Φ_mesh / b)/∂Δv_i = Δt Σ_p w_ip ∂Φ/∂x_p
        for_each_particle_coloured([&](std::uint32_t q) {
          const Vec<T, 2> gq = dt * mesh_g_[q];
          st[q].for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) {
            imp_.grad[i] += w * gq;
          });
        });
  }
  return e;
}

// ∂P/∂F at F^y (projected to be positive definite when asked). In 2D it is folded with this
// step's b Δt² V_p and Fⁿ into the operator S_p that implicit_hessian_apply reads: with
// G = Σ_i δ_i ∇wᵀ, vec(s) = S_p vec(G) for s = Δt V_p ∂P/∂F[b Δt G Fⁿ] Fⁿᵀ, i.e.
// S_p = b Δt² V_p (Fⁿ ⊗ I) ∂P/∂F (Fⁿᵀ ⊗ I), formed once a Newton iteration, where the two D×D
// products and scalings it saves were per particle and CG iteration (rotating-disk takes ~60 CG
// iterations a Newton one; docs/performance.md). 3D keeps ∂P/∂F: S_p costs 486 multiply-adds a
// Newton iteration and saves 72 a CG iteration, and sphere-impact-3d's contact takes ~10 CG a
// Newton, too few to pay for it.
template <class T, int D>
void MpmSimulation<T, D>::implicit_update_hessian(bool project_definite) {
  if constexpr (D == 2)
    if (!mesh_.empty()) mesh_.update_hessian(mesh_x_, index_of_id_, project_definite);
  const std::ptrdiff_t np = std::ptrdiff_t(p_.size());
  constexpr int N = D * D;
  const T b_dt2 = imp_.b * imp_.dt * imp_.dt;
#pragma omp parallel for schedule(static) if (parallel_worthwhile())
  for (std::ptrdiff_t q = 0; q < np; ++q) {
    const MaterialParams<T>& mat = materials_[std::size_t(p_.material[std::size_t(q)])];
    const Mat<T, D>& F = imp_.Fy[std::size_t(q)];
    const Eigen::Matrix<T, N, N> dPdF =
        project_definite ? projected_stress_hessian<T, D>(mat.model, F, mat.lame)
                         : stress_differential_matrix<T, D>(mat.model, F, mat.lame);
    if constexpr (!folded_stiffness) {
      imp_.stiffness[std::size_t(q)] = dPdF;
      continue;
    }
    // The Kronecker factors by blocks, 2 D⁵ multiply-adds.
    const Mat<T, D>& Fn = p_.F[std::size_t(q)];
    Eigen::Matrix<T, N, N> right;  // ∂P/∂F (Fⁿᵀ ⊗ I): column a + D l is Σ_m F_lm column a + D m
    for (int a = 0; a < D; ++a)
      for (int l = 0; l < D; ++l) {
        right.col(a + D * l) = Fn(l, 0) * dPdF.col(a);
        for (int m = 1; m < D; ++m) right.col(a + D * l) += Fn(l, m) * dPdF.col(a + D * m);
      }
    const T scale = b_dt2 * p_.volume0[std::size_t(q)];
    auto& S = imp_.stiffness[std::size_t(q)];  // (Fⁿ ⊗ I) right: row block j is Σ_m F_jm block m
    for (int j = 0; j < D; ++j) {
      Eigen::Matrix<T, D, N> rows = Fn(j, 0) * right.template middleRows<D>(0);
      for (int m = 1; m < D; ++m) rows += Fn(j, m) * right.template middleRows<D>(D * m);
      S.template middleRows<D>(D * j) = scale * rows;
    }
  }
}

// The block-Jacobi preconditioner: each active node's D×D block of H = M + b Δt² K, from the
// per-particle ∂P/∂F (the diagonal of implicit_hessian_apply's operator): with c = Fᵀ∇w_ip,
//   H_ii[k][a] = m_i δ_ka + b Δt² Σ_p V_p Σ_{m,l} ∂P_km/∂F_al c_m c_l,
// which with 2D's S_p is Σ_p Σ_{j,l} S_p[k + D j][a + D l] ∇w_j ∇w_l; positive definite since each
// ∂P/∂F is projected to be. The 2D mesh's stiffness is left out (a weaker preconditioner there,
// never a wrong one).
template <class T, int D>
template <class K>
void MpmSimulation<T, D>::implicit_block_jacobi() {
  const auto& st = stencils<K>();
  const T scale = imp_.b * imp_.dt * imp_.dt;
  for (std::uint32_t i : imp_.active) imp_.block_inverse[i] = grid_.mass[i] * Mat<T, D>::Identity();
  for_each_particle_coloured([&](std::uint32_t q) {
    const auto& H = imp_.stiffness[q];  // S_p in 2D, ∂P/∂F in 3D
    const Mat<T, D>& F = p_.F[q];
    const T s = folded_stiffness ? T(1) : scale * p_.volume0[q];
    st[q].for_each([&](std::size_t i, T, const Vec<T, D>& gw, const Vec<T, D>&) {
      const Vec<T, D> c = folded_stiffness ? gw : Vec<T, D>(F.transpose() * gw);
      // Column a of the block, Σ_l c_l Σ_m c_m H[D m .. D m + D)[a + D l], as D-vectors: an
      // Eigen D²×D temporary here was stored in halves and reloaded whole (store-forwarding
      // stalls, as gradient_gather's comment in sim/mpm/stencil.hpp says).
      for (int a = 0; a < D; ++a) {
        Vec<T, D> column = Vec<T, D>::Zero();
        for (int l = 0; l < D; ++l) {
          Vec<T, D> hc = c[0] * H.col(a + D * l).template head<D>();
          for (int m = 1; m < D; ++m) hc += c[m] * H.col(a + D * l).template segment<D>(D * m);
          column += c[l] * hc;
        }
        imp_.block_inverse[i].col(a) += s * column;
      }
    });
  });
  for (std::uint32_t i : imp_.active)
    imp_.block_inverse[i] = imp_.block_inverse[i].inverse().eval();
}

// z = C r: the block-Jacobi inverse or M⁻¹, then the constraints' projection (C = P B⁻¹ P).
template <class T, int D>
void MpmSimulation<T, D>::implicit_precondition(const std::vector<Vec<T, D>>& r,
                                                std::vector<Vec<T, D>>& z) const {
  if (scene_.solver.preconditioner == CgPreconditioner::block_jacobi) {
    for (std::uint32_t i : imp_.active) z[i] = imp_.block_inverse[i] * r[i];
    implicit_project(z);
  } else {
    for (std::uint32_t i : imp_.active) z[i] = r[i] / grid_.mass[i];
  }
}

// out = H in = M in + b Δt² K in (eqs 35-36), the elastic part through each particle's S_p.
template <class T, int D>
template <class K>
void MpmSimulation<T, D>::implicit_hessian_apply(const std::vector<Vec<T, D>>& in,
                                                 std::vector<Vec<T, D>>& out) {
  constexpr int N = D * D;
  const auto& st = stencils<K>();
  const T b = imp_.b, dt = imp_.dt;
  for (std::uint32_t i : imp_.active) out[i] = grid_.mass[i] * in[i];
  for_each_particle_coloured([&](std::uint32_t q) {
    const Mat<T, D> G = st[q].gradient_gather(in.data());
    Mat<T, D> s;  // Δt V_p ∂P/∂F[b Δt G Fⁿ] Fⁿᵀ
    if constexpr (folded_stiffness) {
      Eigen::Map<Eigen::Matrix<T, N, 1>>(s.data()) =
          imp_.stiffness[q] * Eigen::Map<const Eigen::Matrix<T, N, 1>>(G.data());
    } else {
      Mat<T, D> dF = (b * dt) * G * p_.F[q];
      Mat<T, D> dP;
      Eigen::Map<Eigen::Matrix<T, N, 1>>(dP.data()) =
          imp_.stiffness[q] * Eigen::Map<const Eigen::Matrix<T, N, 1>>(dF.data());
      s = (dt * p_.volume0[q]) * dP * p_.F[q].transpose();
    }
    st[q].gradient_scatter(s, out.data());
  });
  if constexpr (D == 2)
    if (!mesh_.empty()) {  // b Δt² Σ_p w_ip (K δx)_p with δx_p = Σ_j w_jp δ_j
      mesh_dx_.assign(p_.size(), Vec<T, 2>::Zero());
      mesh_kx_.assign(p_.size(), Vec<T, 2>::Zero());
      for (std::size_t q = 0; q < p_.size(); ++q)
        st[q].for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) {
          mesh_dx_[q] += w * in[i];
        });
      mesh_.apply_hessian(mesh_dx_, index_of_id_, mesh_kx_);
      for_each_particle_coloured([&](std::uint32_t q) {
        const Vec<T, 2> k = (b * dt * dt) * mesh_kx_[q];
        st[q].for_each(
            [&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) { out[i] += w * k; });
      });
    }
}

template <class T, int D>
template <class K>
void MpmSimulation<T, D>::implicit_velocity_update(T dt) {
  implicit_begin<K>(dt);
  if (imp_.b == T(0)) {  // λ = 1: explicit, forces at y = x + Δt v
    implicit_energy<K>(imp_.dv, true);
    for (std::uint32_t i : imp_.active) imp_.dv[i] = -imp_.grad[i] / grid_.mass[i];
    implicit_project(imp_.dv);
    for_each_box_node(
        [&](std::size_t i) { grid_.velocity_new[i] = grid_.velocity[i] + imp_.dv[i]; });
    last_solve_ = NewtonCgReport{};
    return;
  }
  // E of this step as newton_cg_minimise's problem (sim/mpm/implicit/newton_cg.hpp).
  struct Problem {
    MpmSimulation& sim;
    double energy(const std::vector<Vec<T, D>>& dv, bool gradient) {
      return sim.template implicit_energy<K>(dv, gradient);
    }
    void update_hessian() {
      sim.implicit_update_hessian(true);
      if (block_jacobi()) sim.template implicit_block_jacobi<K>();
    }
    void precondition(const std::vector<Vec<T, D>>& r, std::vector<Vec<T, D>>& z) const {
      sim.implicit_precondition(r, z);
    }
    // Uniform velocities are null directions of the elastic forces unless a wall holds a node.
    bool deflate_translation() const { return block_jacobi() && sim.imp_.constraints.empty(); }
    bool block_jacobi() const {
      return sim.scene_.solver.preconditioner == CgPreconditioner::block_jacobi;
    }
    void hessian_apply(const std::vector<Vec<T, D>>& in, std::vector<Vec<T, D>>& out) {
      sim.template implicit_hessian_apply<K>(in, out);
    }
    void project(std::vector<Vec<T, D>>& z) const { sim.implicit_project(z); }
    double energy_round_off() const { return sim.imp_.energy_round_off; }
  } problem{*this};
  // The tolerance is relative to the scene's velocity scale, not only this step's: a motion that
  // has decayed (PIC's damping) would hold the residual to a fraction of its own round-off.
  const double vref =
      std::max({imp_.velocity_ref, velocity_scale_, double(imp_.gravity.norm() * dt)});
  const SolverDesc& sv = scene_.solver;
  // Tolerances below the scalar type's round-off are raised to it
  // (sim/mpm/implicit/round_off_floor.hpp).
  const RoundOffFloor floor = implicit_round_off_floor<T>(vref, double(dt), scene_.domain.dx,
                                                          max_wave_speed_, double(imp_.b));
  NewtonCgOptions options{std::max(sv.newton_tolerance * vref, floor.newton),
                          sv.newton_max_iterations, std::max(sv.cg_tolerance, floor.cg),
                          sv.cg_max_iterations};
  if (on_solver_iteration_) options.on_iteration = &on_solver_iteration_;
  last_solve_ = newton_cg_minimise<T, D>(problem, imp_.dv, imp_.grad, imp_.active, grid_.mass,
                                         imp_.mass_sum, options, imp_.cg, imp_.residuals);
  for_each_box_node([&](std::size_t i) { grid_.velocity_new[i] = grid_.velocity[i] + imp_.dv[i]; });
}

}  // namespace apiclab
