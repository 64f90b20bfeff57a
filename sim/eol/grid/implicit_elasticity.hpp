// Backward Euler for an object's elastic forces on its own grid (solver.elasticity implicit; a
// departure: Fan et al. 2013 treat elasticity explicitly and name implicit integration as the
// next step, Sec 5). The nodes move by Δt (w − w_f) (frame axes: w_f the frame's rigid velocity,
// which moves no F) with X held, as the forces' reference elastic_energy_moved does, and the
// step's velocity w minimises
//   E(w) = Σ ½ mᵢ |wᵢ − ũᵢ|² + Ψ(y + Δt (w − w_f)),   ũ = Rᵀ(u + Δt M⁻¹ f_other),
// whose stationarity is m (w − ũ) = Δt f_e(y + Δt w): backward Euler. f_other (gravity, f_qvv)
// stays explicit. Solved by the MPM family's Newton–CG (sim/mpm/implicit/newton_cg.hpp) with
// ∂P/∂F projected positive semi-definite (stress_hessian.hpp) and block-Jacobi CG, deflated (a
// uniform w moves no F). Per Gauss point (cell_points.hpp), with A = ∂X/∂ξ:
//   F = (Δx I + Δt Σₖ (wₖ − w_fₖ) ∇_ξNₖᵀ) A⁻¹,   ∂Ψ/∂wₖ = Δt V₀ P(F) A⁻ᵀ ∇_ξNₖ.
// (Moving the nodes by the frame's rotation too, F = (I + Δt W)·F is no rotation: at ω Δt = 0.16
// it strained a spinning disk by 1.2 % and raised eol-spin's energy 2.5× in its first step.)
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "sim/eol/grid/forces.hpp"
#include "sim/mpm/implicit/newton_cg.hpp"
#include "sim/mpm/implicit/round_off_floor.hpp"
#include "sim/mpm/implicit/stress_hessian.hpp"

namespace apiclab::eol {

// The solve's tolerances (the MPM family's solver keys and defaults) and scales.
struct ImplicitSettings {
  double newton_tolerance = 1e-6;  // relative to the velocity scale
  int newton_max_iterations = 50;
  double cg_tolerance = 1e-6;
  int cg_max_iterations = 200;
  double wave_speed = 0;      // the fastest P-wave speed (round-off floor)
  double velocity_scale = 0;  // the scene's speed scale, besides this step's RMS speed
};

template <class T, int D>
class ImplicitElasticity {
  static constexpr int P = 1 << D, N = D * D;

 public:
  // force (world axes) holds the step's forces with the explicit elastic force of the state now;
  // on return it holds the forces whose explicit update u + Δt M⁻¹ f is backward Euler's
  // velocity, so the impulse, contact and split stages run unchanged.
  NewtonCgReport solve(const EulerianGrid<T, D>& g,
                       const std::vector<ElasticMaterial<T>>& materials, const Mat<T, D>& R,
                       const std::vector<Vec<T, D>>& u, std::vector<Vec<T, D>>& force, T dt,
                       const ImplicitSettings& s) {
    begin(g, materials, R, u, force, dt, s);
    const NewtonCgReport report = minimise();
    finish(u, force);
    return report;
  }
  // solve() in three parts, so that contact (implicit_contact.hpp) can push between them: the
  // problem from the step's forces, started at ũ; the minimisation from the last w; the forces.
  void begin(const EulerianGrid<T, D>& g, const std::vector<ElasticMaterial<T>>& materials,
             const Mat<T, D>& R, const std::vector<Vec<T, D>>& u,
             const std::vector<Vec<T, D>>& force, T dt, const ImplicitSettings& s) {
    setup(g, materials, dt);
    R_ = R;
    const std::size_t n = g.size();
    if (frame_.size() != n) frame_.assign(n, Vec<T, D>::Zero());
    for (auto* v : {&w_, &grad_, &target_, &rest_target_, &cg_.direction, &cg_.residual,
                    &cg_.precond, &cg_.search, &cg_.product, &cg_.trial})
      v->assign(n, Vec<T, D>::Zero());
    // f_other = f − R f_e(now) = f + R ∂Ψ/∂y, with this quadrature's f_e: f_other + R f_e is f.
    rest_gradient();
    const Mat<T, D> Rt = R.transpose();
    // A node without mass at a cell with material (the baseline's dropped slivers) is no
    // unknown: it moves with its extrapolated u, as the advection moves it. Held at w = 0, its
    // cells would be strained by Δt |u| / Δx.
    for (std::size_t i = 0; i < n; ++i) {
      frame_[i] = Rt * frame_[i];
      w_[i] = Rt * u[i];
    }
    cg_.trial = w_;  // the line search's trial points write the unknowns only
    double v2 = 0;
    Vec<T, D> mean = Vec<T, D>::Zero();
    for (std::uint32_t i : active_) {
      const Vec<T, D> other = force[i] + R * grad_[i];
      target_[i] = Rt * (u[i] + (dt / mass_[i]) * other);
      rest_target_[i] = target_[i];
      v2 += double(mass_[i]) * double(u[i].squaredNorm());
      mean += mass_[i] * target_[i];
    }
    mean /= T(std::max(mass_sum_, 1e-300));
    // Start from ũ; where that inverts a cell, from the frame's velocity (which moves no F).
    for (std::uint32_t i : active_) w_[i] = target_[i];
    if (!std::isfinite(energy(w_, false)))
      for (std::uint32_t i : active_) w_[i] = frame_[i];
    const double vref = std::max(
        {std::sqrt(v2 / std::max(mass_sum_, 1e-300)), s.velocity_scale, double(mean.norm())});
    const RoundOffFloor floor =
        implicit_round_off_floor<T>(vref, double(dt), double(g.dx), s.wave_speed, 1.0);
    options_ =
        NewtonCgOptions{std::max(s.newton_tolerance * vref, floor.newton), s.newton_max_iterations,
                        std::max(s.cg_tolerance, floor.cg), s.cg_max_iterations};
  }
  NewtonCgReport minimise() {
    Problem problem{*this};
    return newton_cg_minimise<T, D>(problem, w_, grad_, active_, mass_, mass_sum_, options_, cg_,
                                    residuals_);
  }
  void finish(const std::vector<Vec<T, D>>& u, std::vector<Vec<T, D>>& force) const {
    for (std::uint32_t i : active_) force[i] = (mass_[i] / dt_) * (R_ * w_[i] - u[i]);
  }
  // A contact impulse p (world axes, per node) on the step: m (w − ũ) = Δt f_e − Rᵀ p, so ũ
  // becomes ũ − M⁻¹ Rᵀ p (the rows' −Jᵀλ). Replaces the last push.
  void push(const std::vector<Vec<T, D>>& impulse) {
    const Mat<T, D> Rt = R_.transpose();
    for (std::uint32_t i : active_) target_[i] = rest_target_[i] - (Rt * impulse[i]) / mass_[i];
  }
  // Node i's velocity in world axes, R w (a node with mass).
  Vec<T, D> velocity(std::size_t i) const { return R_ * w_[i]; }
  // H = M + Δt² K at the current w, for inverse_apply.
  void hessian_here() {
    energy(w_, true);
    update_hessian();
  }
  // out = R H⁻¹ Rᵀ rhs (world axes) by deflated block-Jacobi CG to `tolerance` relative to rhs
  // (its M⁻¹ norm), as newton_cg_minimise solves its Newton systems; the CG iterations.
  int inverse_apply(const std::vector<Vec<T, D>>& rhs, std::vector<Vec<T, D>>& out,
                    double tolerance, int max_iterations) {
    auto& x = cg_.direction;
    auto& r = cg_.residual;
    auto& z = cg_.precond;
    auto& p = cg_.search;
    auto& q = cg_.product;
    const Mat<T, D> Rt = R_.transpose();
    // x₀ the uniform velocity with Σ (b − M x₀) = 0 (H x₀ = M x₀), then search directions
    // without momentum (Σ m p = 0), as newton_cg_minimise's deflated CG.
    Vec<T, D> mean = Vec<T, D>::Zero();
    double rhs2 = 0;
    for (std::uint32_t i : active_) {
      r[i] = Rt * rhs[i];
      mean += r[i];
      rhs2 += double(r[i].squaredNorm()) / double(mass_[i]);
    }
    mean /= T(std::max(mass_sum_, 1e-300));
    for (std::uint32_t i : active_) {
      x[i] = mean;
      r[i] -= mass_[i] * mean;
    }
    // z = C r, then p = z − its mass-weighted mean + β p with β = (r·z)/(r·z)_old; r·z.
    auto search = [&](double gamma_old) {
      Vec<T, D> zm = Vec<T, D>::Zero();
      double gamma = 0;
      for (std::uint32_t i : active_) {
        z[i] = block_inverse_[i] * r[i];
        zm += mass_[i] * z[i];
        gamma += double(r[i].dot(z[i]));
      }
      zm /= T(std::max(mass_sum_, 1e-300));
      const T beta = gamma_old > 0 ? T(gamma / gamma_old) : T(0);
      for (std::uint32_t i : active_) p[i] = z[i] - zm + beta * p[i];
      return gamma;
    };
    double gamma = search(0);
    int k = 0;
    for (; k < max_iterations; ++k) {
      double rho = 0;
      for (std::uint32_t i : active_) rho += double(r[i].squaredNorm()) / double(mass_[i]);
      if (rho <= tolerance * tolerance * rhs2) break;
      hessian_apply(p, q);
      double pq = 0;
      for (std::uint32_t i : active_) pq += double(p[i].dot(q[i]));
      if (!(pq > 0)) break;
      const T alpha = T(gamma / pq);
      for (std::uint32_t i : active_) {
        x[i] += alpha * p[i];
        r[i] -= alpha * q[i];
      }
      gamma = search(gamma);
    }
    out.assign(x.size(), Vec<T, D>::Zero());
    for (std::uint32_t i : active_) out[i] = R_ * x[i];
    return k;
  }
  // Per node, world axes: the frame's rigid velocity ν + ω × r, which solve() leaves out of the
  // nodes' motion (zero on the Eulerian baseline); the caller fills it before each solve().
  std::vector<Vec<T, D>>& frame_velocity() { return frame_; }
  std::size_t bytes() const {
    std::size_t b =
        held_bytes(points_) + held_bytes(frame_) + held_bytes(active_) + held_bytes(block_inverse_);
    for (const auto* v : {&w_, &grad_, &target_, &rest_target_, &cg_.direction, &cg_.residual,
                          &cg_.precond, &cg_.search, &cg_.product, &cg_.trial})
      b += held_bytes(*v);
    return b;
  }

 private:
  struct Point {
    std::size_t base;  // the cell's lowest node
    int material, q;   // q: the Gauss point in its cell
    T volume;          // V₀ = det A w H
    Mat<T, D> Ainv, F;
    Eigen::Matrix<T, N, N> dPdF;
  };
  // newton_cg_minimise's problem: no constraints (contact enters as a pushed impulse).
  struct Problem {
    ImplicitElasticity& s;
    double energy(const std::vector<Vec<T, D>>& w, bool gradient) { return s.energy(w, gradient); }
    void update_hessian() { s.update_hessian(); }
    void hessian_apply(const std::vector<Vec<T, D>>& in, std::vector<Vec<T, D>>& out) {
      s.hessian_apply(in, out);
    }
    void project(std::vector<Vec<T, D>>&) const {}
    void precondition(const std::vector<Vec<T, D>>& r, std::vector<Vec<T, D>>& z) const {
      for (std::uint32_t i : s.active_) z[i] = s.block_inverse_[i] * r[i];
    }
    bool deflate_translation() const { return true; }
    double energy_round_off() const { return s.energy_round_off_; }
  };

  // The Gauss points with material (V₀ > 0), the nodes with mass.
  void setup(const EulerianGrid<T, D>& g, const std::vector<ElasticMaterial<T>>& materials, T dt) {
    materials_ = &materials;
    mass_ = g.mass;
    dt_ = dt;
    dx_ = g.dx;
    for (int k = 0; k < P; ++k) offset_[std::size_t(k)] = corner_node(g, 0, k);
    points_.clear();
    for (std::size_t base = 0; base < g.size(); ++base) {
      if (!is_cell_base(g, base)) continue;
      const int m = cell_material(g, base);
      if (m < 0) continue;
      for (int q = 0; q < P; ++q) {
        Mat<T, D> A = Mat<T, D>::Zero();
        T fill = T(0);
        for (int k = 0; k < P; ++k) {
          const std::size_t i = base + offset_[std::size_t(k)];
          A += g.X[i] * quad_.dN[std::size_t(q)][std::size_t(k)].transpose();
          fill += quad_.N[std::size_t(q)][std::size_t(k)] * g.fill[i];
        }
        const T det = A.determinant();
        if (!(fill > T(0)) || !(det > T(0))) continue;
        points_.push_back({base, m, q, det * quad_.weight * fill, A.inverse(), Mat<T, D>::Zero(),
                           Eigen::Matrix<T, N, N>::Zero()});
      }
    }
    active_.clear();
    mass_sum_ = 0;
    for (std::size_t i = 0; i < g.size(); ++i)
      if (mass_[i] > T(0)) {
        active_.push_back(std::uint32_t(i));
        mass_sum_ += double(mass_[i]);
      }
    block_inverse_.resize(g.size());
  }
  std::size_t node(const Point& p, int k) const { return p.base + offset_[std::size_t(k)]; }
  const Vec<T, D>& dN(const Point& p, int k) const {
    return quad_.dN[std::size_t(p.q)][std::size_t(k)];
  }
  // ∂Ψ/∂y at the grid as it is, into grad_: −f_e in frame axes.
  void rest_gradient() {
    for (std::uint32_t i : active_) grad_[i].setZero();
    for (const Point& p : points_) {
      const ElasticMaterial<T>& mat = (*materials_)[std::size_t(p.material)];
      T psi;
      const Mat<T, D> S = p.volume *
                          first_piola_and_energy<T, D>(mat.model, dx_ * p.Ainv, mat.lame, psi) *
                          p.Ainv.transpose();
      for (int k = 0; k < P; ++k) grad_[node(p, k)] += S * dN(p, k);
    }
  }
  double energy(const std::vector<Vec<T, D>>& w, bool gradient) {
    double psi_sum = 0, terms = 0;
    if (gradient)
      for (std::uint32_t i : active_) grad_[i] = mass_[i] * (w[i] - target_[i]);
    for (Point& p : points_) {
      Mat<T, D> Y = dx_ * Mat<T, D>::Identity();
      for (int k = 0; k < P; ++k) {
        const std::size_t i = node(p, k);
        Y += dt_ * (w[i] - frame_[i]) * dN(p, k).transpose();
      }
      const Mat<T, D> F = Y * p.Ainv;
      const ElasticMaterial<T>& mat = (*materials_)[std::size_t(p.material)];
      T psi;
      const Mat<T, D> stress = first_piola_and_energy<T, D>(mat.model, F, mat.lame, psi);
      if (!std::isfinite(double(psi))) return std::numeric_limits<double>::infinity();
      psi_sum += double(p.volume * psi);
      terms += double(p.volume) *
               (double(mat.lame.lambda + 2 * mat.lame.mu) * double(F.squaredNorm() + 1) +
                std::abs(double(psi)));
      if (!gradient) continue;
      p.F = F;
      const Mat<T, D> S = (dt_ * p.volume) * stress * p.Ainv.transpose();
      for (int k = 0; k < P; ++k) grad_[node(p, k)] += S * dN(p, k);
    }
    double e = psi_sum;
    for (std::uint32_t i : active_) {
      const double half = 0.5 * double(mass_[i]) * double((w[i] - target_[i]).squaredNorm());
      e += half;
      terms += half + 0.5 * double(mass_[i]) * double(target_[i].squaredNorm());
    }
    energy_round_off_ = double(std::numeric_limits<T>::epsilon()) * terms;
    return e;
  }
  // ∂P/∂F at each point's F, projected; the block-Jacobi inverse of H = M + Δt² K's node blocks
  // (c = A⁻ᵀ ∇_ξNₖ: H_kk[r][a] = m δ_ra + Δt² Σ V₀ Σ_{m,l} ∂P_rm/∂F_al c_m c_l).
  void update_hessian() {
    for (std::uint32_t i : active_) block_inverse_[i] = mass_[i] * Mat<T, D>::Identity();
    const T dt2 = dt_ * dt_;
    for (Point& p : points_) {
      const ElasticMaterial<T>& mat = (*materials_)[std::size_t(p.material)];
      p.dPdF = projected_stress_hessian<T, D>(mat.model, p.F, mat.lame);
      for (int k = 0; k < P; ++k) {
        const Vec<T, D> c = p.Ainv.transpose() * dN(p, k);
        Mat<T, D>& block = block_inverse_[node(p, k)];
        for (int a = 0; a < D; ++a)
          for (int l = 0; l < D; ++l)
            for (int m = 0; m < D; ++m)
              block.col(a) +=
                  (dt2 * p.volume * c[m] * c[l]) * p.dPdF.col(a + D * l).template segment<D>(D * m);
      }
    }
    for (std::uint32_t i : active_) block_inverse_[i] = block_inverse_[i].inverse().eval();
  }
  // out = M in + Δt² K in.
  void hessian_apply(const std::vector<Vec<T, D>>& in, std::vector<Vec<T, D>>& out) const {
    for (std::uint32_t i : active_) out[i] = mass_[i] * in[i];
    for (const Point& p : points_) {
      Mat<T, D> dY = Mat<T, D>::Zero();
      for (int k = 0; k < P; ++k) dY += in[node(p, k)] * dN(p, k).transpose();
      const Mat<T, D> dF = dt_ * dY * p.Ainv;
      Mat<T, D> dP;
      Eigen::Map<Eigen::Matrix<T, N, 1>>(dP.data()) =
          p.dPdF * Eigen::Map<const Eigen::Matrix<T, N, 1>>(dF.data());
      const Mat<T, D> S = (dt_ * p.volume) * dP * p.Ainv.transpose();
      for (int k = 0; k < P; ++k) out[node(p, k)] += S * dN(p, k);
    }
  }

  CellQuadrature<T, D> quad_;
  std::array<std::size_t, P> offset_{};
  const std::vector<ElasticMaterial<T>>* materials_ = nullptr;
  std::vector<Point> points_;
  std::vector<std::uint32_t> active_;
  std::vector<T> mass_;
  std::vector<Vec<T, D>> w_, grad_, target_, rest_target_, frame_;  // rest_target_: ũ unpushed
  std::vector<Mat<T, D>> block_inverse_;
  NewtonCgVectors<T, D> cg_;
  std::vector<double> residuals_;
  double mass_sum_ = 0, energy_round_off_ = 0;
  T dt_ = T(0), dx_ = T(1);
  Mat<T, D> R_ = Mat<T, D>::Identity();
  NewtonCgOptions options_{0, 0, 0, 0};
};

}  // namespace apiclab::eol
