// Newton's method for a minimisation over velocity-like node vectors (Gast et al. 2015;
// Jiang et al. 2017, Sec 4.2, Algorithm 1). Each Newton system P H P d = −P g is solved by
// preconditioned conjugate gradients: with C = M⁻¹ that is CG on M⁻¹ P H P in the mass inner
// product <u, w> = Σ_i m_i u_i·w_i (the paper's), with C = the inverse of H's node blocks it
// is block-Jacobi CG; either way every search direction is velocity-like. The CG stops on
// the residual's M⁻¹ norm relative to g's. A backtracking (Armijo) line search on E then
// takes the step, never accepting E = +∞. Near the minimum E's change, ½ g·H⁻¹g, falls below
// E's own round-off before the residual meets its tolerance: there E cannot judge a step, and
// the full Newton step is taken when E rose by no more than its round-off and the residual fell.
// Only the nodes in `active` are read or written.
#pragma once
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "sim/math.hpp"

namespace apiclab {

template <class T, int D>
struct NewtonCgVectors {
  std::vector<Vec<T, D>> direction, residual, precond, search, product, trial;
};

struct NewtonCgOptions {
  double tolerance;  // on the mass-weighted RMS of M⁻¹ P g, a velocity
  int max_newton_iterations;
  double cg_tolerance;  // relative to the first CG residual
  int max_cg_iterations;
  // Called at every Newton and every CG iteration with the Newton iteration, the CG iterations
  // so far and the last Newton residual (the progress of a long solve).
  const std::function<void(int newton_iteration, int cg_iterations, double residual)>*
      on_iteration = nullptr;
};

struct NewtonCgReport {
  int newton_iterations = 0, cg_iterations = 0;
  double residual = 0, tolerance = 0;  // the last residual and the tolerance it was held to
  bool converged = true;
};

// Problem: energy(x, gradient) → E(x), writing ∇E into `grad` when gradient is true (+∞ for an
// inadmissible x); update_hessian() at the last x whose gradient was taken; hessian_apply(in,
// out) → out = H in; project(z) applies P, the constraints; precondition(r, z) → z = C r, C
// symmetric positive definite on P's range (M⁻¹ for the paper's CG); deflate_translation()
// whether uniform velocities u are null directions of the forces (H u = M u, no constraints),
// to be solved exactly; energy_round_off() the absolute round-off of the last E evaluated.
// x holds the start and the result.
template <class T, int D, class Problem>
NewtonCgReport newton_cg_minimise(Problem& problem, std::vector<Vec<T, D>>& x,
                                  std::vector<Vec<T, D>>& grad,
                                  const std::vector<std::uint32_t>& active,
                                  const std::vector<T>& mass, double mass_sum,
                                  const NewtonCgOptions& options, NewtonCgVectors<T, D>& v,
                                  std::vector<double>& residuals) {
  auto dot = [&](const std::vector<Vec<T, D>>& a, const std::vector<Vec<T, D>>& b) {
    double s = 0;
    for (std::uint32_t i : active) s += double(a[i].dot(b[i]));
    return s;
  };
  auto norm_minv = [&](const std::vector<Vec<T, D>>& r) {  // Σ |r_i|² / m_i: |M⁻¹r| in the M norm
    double s = 0;
    for (std::uint32_t i : active) s += double(r[i].squaredNorm()) / double(mass[i]);
    return s;
  };
  // search ← z + β search; deflated, z loses its mass-weighted mean first, so that every search
  // direction carries no momentum (Σ m p = 0) and Σ r stays 0 (deflated CG, Saad et al. 2000).
  auto set_search = [&](const std::vector<Vec<T, D>>& z, bool deflate, T beta) {
    Vec<T, D> mean = Vec<T, D>::Zero();
    if (deflate) {
      for (std::uint32_t i : active) mean += mass[i] * z[i];
      mean /= T(mass_sum);
    }
    for (std::uint32_t i : active) v.search[i] = z[i] - mean + beta * v.search[i];
  };
  auto& dir = v.direction;
  double energy = problem.energy(x, true);
  NewtonCgReport report;
  residuals.clear();
  auto residual_of = [&](std::vector<Vec<T, D>>& g) {  // mass-weighted RMS of M⁻¹ P g
    problem.project(g);
    double r2 = 0;
    for (std::uint32_t i : active) r2 += double(g[i].squaredNorm()) / double(mass[i]);
    return std::sqrt(r2 / std::max(mass_sum, 1e-300));
  };
  for (;; ++report.newton_iterations) {
    report.residual = residual_of(grad);
    residuals.push_back(report.residual);
    if (options.on_iteration)
      (*options.on_iteration)(report.newton_iterations, report.cg_iterations, report.residual);
    if (report.residual <= options.tolerance ||
        report.newton_iterations >= options.max_newton_iterations)
      break;
    problem.update_hessian();
    // Preconditioned CG on P H P d = −P g (Algorithm 1): r is force-like, z = C r and every
    // search direction velocity-like. C = M⁻¹ is the paper's CG in the mass inner product.
    const bool deflate = problem.deflate_translation();
    for (std::uint32_t i : active) {
      dir[i].setZero();
      v.residual[i] = -grad[i];
    }
    const double rhs_norm = std::sqrt(norm_minv(v.residual));
    if (deflate) {  // d₀ = the uniform velocity u with Σ (−g − H d₀) = 0, since H u = M u
      Vec<T, D> u = Vec<T, D>::Zero();
      for (std::uint32_t i : active) u += v.residual[i];
      u /= T(mass_sum);
      for (std::uint32_t i : active) {
        dir[i] = u;
        v.residual[i] -= mass[i] * u;
      }
    }
    problem.precondition(v.residual, v.precond);
    set_search(v.precond, deflate, T(0));
    double gamma = dot(v.residual, v.precond), rho = norm_minv(v.residual);
    for (int k = 0; k < options.max_cg_iterations; ++k) {
      if (std::sqrt(rho) <= options.cg_tolerance * rhs_norm) break;
      problem.hessian_apply(v.search, v.product);
      problem.project(v.product);
      double ps = dot(v.search, v.product);
      ++report.cg_iterations;
      if (options.on_iteration)
        (*options.on_iteration)(report.newton_iterations, report.cg_iterations, report.residual);
      if (!(ps > 0)) break;
      T alpha = T(gamma / ps);
      rho = 0;
      for (std::uint32_t i : active) {
        dir[i] += alpha * v.search[i];
        v.residual[i] -= alpha * v.product[i];
        rho += double(v.residual[i].squaredNorm()) / double(mass[i]);
      }
      problem.precondition(v.residual, v.precond);
      double kappa = dot(v.residual, v.precond);
      set_search(v.precond, deflate, T(kappa / gamma));
      gamma = kappa;
    }
    // Backtracking line search on E (Armijo), never accepting an inverted F (E = +∞).
    double slope = 0;
    for (std::uint32_t i : active) slope += double(grad[i].dot(dir[i]));
    if (!(slope < 0)) {  // not a descent direction: fall back to steepest descent in M⁻¹
      for (std::uint32_t i : active) dir[i] = -grad[i] / mass[i];
      slope = 0;
      for (std::uint32_t i : active) slope += double(grad[i].dot(dir[i]));
    }
    double step = 1, trial = 0, full = 0, full_round_off = 0;
    for (int ls = 0; ls < 30; ++ls, step *= 0.5) {
      for (std::uint32_t i : active) v.trial[i] = x[i] + T(step) * dir[i];
      trial = problem.energy(v.trial, false);
      if (ls == 0) {
        full = trial;
        full_round_off = problem.energy_round_off();
      }
      if (trial <= energy + 1e-4 * step * slope) break;
    }
    if (!(trial <= energy + 1e-4 * step * slope)) {
      // E cannot tell the full step from x within its round-off: the residual judges it.
      if (!(full <= energy + full_round_off)) break;  // E rose: no progress at this precision
      for (std::uint32_t i : active) v.trial[i] = x[i] + dir[i];
      const double e_full = problem.energy(v.trial, true);
      if (!(residual_of(grad) < report.residual)) {
        energy = problem.energy(x, true);  // grad back to x's
        break;
      }
      for (std::uint32_t i : active) x[i] = v.trial[i];
      energy = e_full;
      continue;
    }
    for (std::uint32_t i : active) x[i] = v.trial[i];
    energy = problem.energy(x, true);
  }
  report.tolerance = options.tolerance;
  report.converged = report.residual <= options.tolerance;
  return report;
}

}  // namespace apiclab
