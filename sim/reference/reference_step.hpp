// One explicit MPM step written to be read, not to be fast: the equations of Jiang, Schroeder and
// Teran 2017 ("An angular momentum conserving affine-particle-in-cell method"), one labelled block
// each, 2D and 3D, with no SIMD, colouring, sorting or active box. Read this before sim/mpm*.
// The optimised step (MpmSimulation::step_fixed, symplectic integrator) agrees with it to
// round-off: tests/mpm/test_reference_step.cpp checks every scheme and kernel.
//
// The step is symplectic Euler, λ = 0 in eqs 27-30:
//   clear grid → P2G (eqs 1, 24-26, 34) → grid update (eq 29 with gravity) → boundary
//   → G2P (eqs 2, 3, 37-40; RPIC, Secs 2.1 and 5.1; lagged C for multilinear weights, Sec 5.9).
// Later schemes have a labelled block each: MLS-MPM (Hu et al. 2018), ASFLIP (Fei et al. 2021),
// XPIC(m) (Hammerquist and Nairn 2017; its grid series runs between boundary and G2P), TPIC
// (Nakamura et al. 2023) and PolyPIC (Fu et al. 2017).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "sim/materials.hpp"
#include "sim/math.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"  // the order of PolyPIC's modes only
#include "sim/scene/registry.hpp"

namespace apiclab::reference {

// Material points. C_p = B_p D_p⁻¹ is stored (eq 26); PIC and FLIP neither read nor write it.
template <class T, int D>
struct ParticleState {
  std::vector<Vec<T, D>> x, v;
  std::vector<Mat<T, D>> C, F;
  std::vector<T> mass, volume;  // m_p and the initial volume V_p⁰
  // PolyPIC: the coefficient of mode 1 + D + j of every particle in modes[j] (Fu et al. 2017).
  std::vector<std::vector<Vec<T, D>>> modes;
};

// A collider plane: nodes on or behind it (against `normal`, a unit vector) are constrained.
template <class T, int D>
struct Plane {
  Vec<T, D> point, normal;
  BoundaryCondition condition;
};

// Everything but the particles. The domain is `cells` whole cells per axis from `min`; node i
// sits at min + i Δx. A wall axis has two ghost nodes beyond each face (the cubic stencil of a
// particle on the face reaches them); a periodic axis stores node i at i mod cells.
template <class T, int D>
struct Setup {
  Vec<T, D> min;
  T dx;
  std::array<int, D> cells;
  std::array<BoundaryCondition, 2 * D> walls;  // x−, x+, y−, y+, z−, z+
  std::vector<Plane<T, D>> colliders;
  Scheme scheme;
  T flip_alpha;        // eq 3 blended with PIC: 1 = FLIP, 0 = PIC; ASFLIP's α
  T asflip_beta = 0;   // ASFLIP's position correction β (Fei et al. 2021)
  int xpic_order = 1;  // XPIC's m (Hammerquist and Nairn 2017)
  KernelType kernel;
  MaterialModel model;
  Lame<T> lame;
  Vec<T, D> gravity;
  int polypic_modes = 0;  // PolyPIC's kept modes, 0 = all
  bool periodic(int a) const { return walls[2 * a] == BoundaryCondition::periodic; }
};

// The B-spline N(d) and its derivative, d = (x_p − x_i)/Δx in cells (Sec 3.2; Steffen 2008).
// The hat's kink takes the derivative of the cell the particle is in (d ∈ [−1, 1)), so that
// Σ ∇w = 0 also for a particle exactly on a node.
template <class T>
void bspline(KernelType kernel, T d, T& N, T& dN) {
  const T a = std::abs(d), s = d < 0 ? T(-1) : T(1);
  N = dN = T(0);
  if (kernel == KernelType::linear) {
    if (d >= -1 && d < 1) N = 1 - a, dN = -s;
  } else if (kernel == KernelType::quadratic) {
    if (a < T(0.5))
      N = T(0.75) - a * a, dN = -2 * d;
    else if (a < T(1.5))
      N = T(0.5) * (T(1.5) - a) * (T(1.5) - a), dN = -s * (T(1.5) - a);
  } else {
    if (a < 1)
      N = T(0.5) * a * a * a - a * a + T(2) / 3, dN = s * (T(1.5) * a * a - 2 * a);
    else if (a < 2)
      N = (2 - a) * (2 - a) * (2 - a) / 6, dN = -s * T(0.5) * (2 - a) * (2 - a);
  }
}

// Node arrays; (mv)_i is kept apart from v_i, and v_i^n apart from ṽ_i.
template <class T, int D>
struct Nodes {
  std::array<int, D> n;  // nodes per axis
  std::vector<T> mass;
  std::vector<Vec<T, D>> momentum, v, v_new, force;
  explicit Nodes(const Setup<T, D>& s) {
    std::size_t total = 1;
    for (int a = 0; a < D; ++a)
      total *= std::size_t(n[a] = s.periodic(a) ? s.cells[a] : s.cells[a] + 5);
    mass.assign(total, T(0));
    momentum.assign(total, Vec<T, D>::Zero());
    v = v_new = force = momentum;
  }
  std::size_t index(const Setup<T, D>& s, const std::array<int, D>& i) const {
    std::size_t k = 0;
    for (int a = D - 1; a >= 0; --a)
      k = k * std::size_t(n[a]) +
          std::size_t(s.periodic(a) ? (i[a] % n[a] + n[a]) % n[a] : i[a] + 2);
    return k;
  }
  std::array<int, D> node(const Setup<T, D>& s, std::size_t k) const {  // inverse of index
    std::array<int, D> i;
    for (int a = 0; a < D; ++a) {
      i[a] = int(k % std::size_t(n[a])) - (s.periodic(a) ? 0 : 2);
      k /= std::size_t(n[a]);
    }
    return i;
  }
};

// f(node, w_ip (eq 18), ∇w_ip (eq 19), x_i) for the 4^D nodes around x_p: every node the
// kernel reaches, and for linear and quadratic weights a few with w = ∇w = 0.
template <class T, int D, class Fn>
void for_each_node(const Setup<T, D>& s, const Nodes<T, D>& g, const Vec<T, D>& xp, Fn&& f) {
  for (int c = 0; c < (D == 2 ? 16 : 64); ++c) {
    std::array<int, D> i;
    Vec<T, D> N, dN, xi;
    for (int a = 0, digit = c; a < D; ++a, digit /= 4) {
      i[a] = int(std::floor((xp[a] - s.min[a]) / s.dx)) - 1 + digit % 4;
      xi[a] = s.min[a] + T(i[a]) * s.dx;
      bspline(s.kernel, (xp[a] - xi[a]) / s.dx, N[a], dN[a]);
    }
    const T w = N.prod();
    Vec<T, D> grad;
    for (int a = 0; a < D; ++a) {
      grad[a] = dN[a] / s.dx;
      for (int b = 0; b < D; ++b)
        if (b != a) grad[a] *= N[b];
    }
    f(g.index(s, i), w, grad, xi);
  }
}

// ṽ after a boundary condition with unit normal n pointing into the free side.
template <class T, int D>
void constrain(Vec<T, D>& v, const Vec<T, D>& n, BoundaryCondition condition) {
  const T vn = v.dot(n);
  if (condition == BoundaryCondition::sticky) v.setZero();
  if (condition == BoundaryCondition::slip || (condition == BoundaryCondition::separate && vn < 0))
    v -= vn * n;
}

// D_p = kΔx² I of the quadratic (k = ¼) and cubic (k = ⅓) B-splines (eq 25 evaluated).
template <class T, int D>
T inertia_k(const Setup<T, D>& s) {
  return (s.kernel == KernelType::cubic ? T(1) / 3 : T(0.25)) * s.dx * s.dx;
}

// PolyPIC (Fu et al. 2017): the scalar mode r at x_i for a particle at x_p, a product over axes
// of 1, u = (x_i − x_p)_a / Δx, or G, the function on the axis's three nodes orthogonal to 1 and
// u under the weights: the cross product of (N_k) and (N_k u_k), scaled by 8 (k = 0, 1, 2 from
// the lowest node; zero off the three).
template <class T, int D>
T polypic_mode(const Setup<T, D>& s, int mode, const Vec<T, D>& xp, const Vec<T, D>& r) {
  T value = 1;
  for (int a = 0; a < D; ++a) {
    const int degree = polypic::mode_degrees<D>()[std::size_t(mode)][std::size_t(a)];
    const T u = r[a] / s.dx;
    if (degree == 1) value *= u;
    if (degree != 2) continue;
    const T xg = (xp[a] - s.min[a]) / s.dx;
    const int lowest = int(std::floor(xg - T(0.5)));
    const int k = int(std::lround(xg + u)) - lowest;  // this node among the three
    T N[3], dN;
    for (int m = 0; m < 3; ++m) bspline(s.kernel, xg - T(lowest + m), N[m], dN);
    const T G[3] = {8 * N[1] * N[2], -16 * N[0] * N[2], 8 * N[0] * N[1]};
    value *= k >= 0 && k < 3 ? G[k] : T(0);
  }
  return value;
}

// One step of size dt; the particles are updated in place.
template <class T, int D>
void step(const Setup<T, D>& s, ParticleState<T, D>& ps, T dt) {
  Nodes<T, D> g(s);                         // clear grid
  const bool affine = is_affine(s.scheme);  // P2G's v_p + C_p (x_i − x_p) (eq 24)
  const bool mls = s.scheme == Scheme::mls;
  const bool polypic = s.scheme == Scheme::polypic;
  const int kept = polypic::kept_modes(s.polypic_modes, D);
  const int extra = polypic ? polypic::extra_modes(kept, D) : 0;
  ps.modes.resize(std::size_t(extra), std::vector<Vec<T, D>>(ps.x.size(), Vec<T, D>::Zero()));

  // P2G. Eq 34 with the sign of a force, f = −∂Φ/∂x̃ (the paper prints it without the minus).
  for (std::size_t p = 0; p < ps.x.size(); ++p) {
    const Mat<T, D> stress =
        -ps.volume[p] * first_piola<T, D>(s.model, ps.F[p], s.lame) * ps.F[p].transpose();
    for_each_node(
        s, g, ps.x[p], [&](std::size_t i, T w, const Vec<T, D>& grad, const Vec<T, D>& xi) {
          g.mass[i] += w * ps.mass[p];  // eq 24
          const Vec<T, D> r = xi - ps.x[p];
          // eq 26 (APIC; RPIC's eq 43 with C_p = ω_p*), or eq 1 (PIC, FLIP)
          g.momentum[i] += w * ps.mass[p] * (affine ? Vec<T, D>(ps.v[p] + ps.C[p] * r) : ps.v[p]);
          // PolyPIC: plus Σ_j c_pj s_j(x_i − x_p) over the modes beyond the affine ones
          for (int j = 0; j < extra; ++j)
            g.momentum[i] += w * ps.mass[p] * polypic_mode(s, 1 + D + j, ps.x[p], r) *
                             ps.modes[std::size_t(j)][p];
          // eq 34, or MLS-MPM (Hu et al. 2018): ∇w ≈ D⁻¹ w (x_i − x_p), D = kΔx² I
          g.force[i] += mls ? Vec<T, D>(stress * (w / inertia_k(s) * r)) : Vec<T, D>(stress * grad);
        });
  }

  // Grid update.
  for (std::size_t i = 0; i < g.mass.size(); ++i) {
    if (g.mass[i] <= T(0)) continue;                                  // v_i = ṽ_i = 0
    g.v[i] = g.momentum[i] / g.mass[i];                               // eqs 1, 26
    g.v_new[i] = g.v[i] + dt * (g.force[i] / g.mass[i] + s.gravity);  // eq 29 (λ = 0), gravity
  }

  // Boundary: walls on nodes on or beyond a domain face (lower face first, axis by axis), then
  // collider planes, in that order.
  for (std::size_t k = 0; k < g.mass.size(); ++k) {
    const std::array<int, D> i = g.node(s, k);
    Vec<T, D> xi;
    for (int a = 0; a < D; ++a) xi[a] = s.min[a] + T(i[a]) * s.dx;
    for (int a = 0; a < D; ++a) {
      if (s.periodic(a)) continue;
      if (i[a] <= 0) constrain<T, D>(g.v_new[k], Vec<T, D>::Unit(a), s.walls[2 * a]);
      if (i[a] >= s.cells[a]) constrain<T, D>(g.v_new[k], -Vec<T, D>::Unit(a), s.walls[2 * a + 1]);
    }
    for (const Plane<T, D>& c : s.colliders)
      if ((xi - c.point).dot(c.normal) <= T(1e-6) * s.dx)
        constrain<T, D>(g.v_new[k], c.normal, c.condition);
  }

  // XPIC(m) (Hammerquist and Nairn 2017): v* = Σ_{r=1}^{m} (−1)^{r+1} C(m,r) A^{r−1} vⁿ
  // with A = S⁺S: interpolate to the particles, then the mass-weighted P2G. Summed as the equal
  // polynomial Σ_{k=0}^{m−1} (I − A)^k vⁿ (no binomial cancellation); e = v* − vⁿ.
  std::vector<Vec<T, D>> xpic_e(g.mass.size(), Vec<T, D>::Zero());
  if (s.scheme == Scheme::xpic) {
    std::vector<Vec<T, D>> u = g.v, Au(g.mass.size());
    for (int k = 1; k < s.xpic_order; ++k) {
      std::fill(Au.begin(), Au.end(), Vec<T, D>::Zero());
      for (std::size_t p = 0; p < ps.x.size(); ++p) {
        Vec<T, D> up = Vec<T, D>::Zero();  // S u at x_p
        for_each_node(s, g, ps.x[p], [&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) {
          up += w * u[i];
        });
        for_each_node(s, g, ps.x[p], [&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) {
          Au[i] += w * ps.mass[p] * up;  // S⁺: Σ_p w m_p u_p, divided by m_i below
        });
      }
      for (std::size_t i = 0; i < g.mass.size(); ++i) {
        if (g.mass[i] <= T(0)) continue;
        u[i] -= Au[i] / g.mass[i];  // (I − A)^k vⁿ
        xpic_e[i] += u[i];
      }
    }
  }

  // G2P. With λ = 0 the moved node is x̃_i = x_i + Δt ṽ_i (eq 30). Its blocks have the names of
  // the fast step's (sim/mpm/g2p.hpp): gather, the particle update, move the particle.
  constexpr int S = D == 2 ? 1 : 3;  // components of an angular velocity
  for (std::size_t p = 0; p < ps.x.size(); ++p) {
    const Vec<T, D> xp = ps.x[p];
    Vec<T, D> v_pic = Vec<T, D>::Zero(), flip_change = v_pic, x_new = v_pic, xpic_shift = v_pic;
    Mat<T, D> grad_v = Mat<T, D>::Zero(), Dp = grad_v;
    Vec<T, S> l = Vec<T, S>::Zero();
    Mat<T, S> K = Mat<T, S>::Zero();
    // Gather: the sums over the stencil.
    for_each_node(s, g, xp, [&](std::size_t i, T w, const Vec<T, D>& grad, const Vec<T, D>& xi) {
      const Vec<T, D> r = xi - xp, vt = g.v_new[i];
      v_pic += w * vt;                   // eqs 2, 37, 44
      flip_change += w * (vt - g.v[i]);  // eq 3
      xpic_shift += w * xpic_e[i];       // XPIC: S e
      x_new += w * (xi + dt * vt);       // eq 39: x_p^{n+1} = Σ w x̃_i
      grad_v += vt * grad.transpose();   // eq 40: Σ (x̃_i − x_i) ∇wᵀ = Δt Σ ṽ_i ∇wᵀ
      Dp += w * r * r.transpose();       // eq 25
      if constexpr (D == 2) {            // Sec 2.1: l_p = Σ w r × ṽ (eq 45 per unit mass)
        l[0] += w * (r[0] * vt[1] - r[1] * vt[0]);
        K(0, 0) += w * r.squaredNorm();  // and K_p = Σ w r* r*ᵀ
      } else {
        l += w * r.cross(vt);
        K += w * (r.squaredNorm() * Mat<T, 3>::Identity() - r * r.transpose());
      }
    });

    // The particle update: velocity and affine matrix per scheme.
    const Vec<T, D> v_old = v_pic - flip_change;  // Σ w v_i^n
    const Vec<T, D> v_n = ps.v[p];
    if (s.scheme == Scheme::pic) {
      ps.v[p] = v_pic;  // eq 2
    } else if (s.scheme == Scheme::xpic) {
      ps.v[p] = v_pic + xpic_shift;  // XPIC: S (ṽ − vⁿ + v*)
    } else if (s.scheme == Scheme::flip) {
      ps.v[p] =
          s.flip_alpha * (ps.v[p] + flip_change) + (1 - s.flip_alpha) * v_pic;  // eq 3, blended
    } else if (s.scheme == Scheme::tpic) {
      ps.v[p] = v_pic;   // eq 37
      ps.C[p] = grad_v;  // TPIC: C = ∇v_p = Σ ṽ_i ∇w_ipᵀ, every kernel
    } else if (s.scheme == Scheme::apic || mls || polypic || s.scheme == Scheme::asflip) {
      ps.v[p] = v_pic;  // eq 37 (MLS-MPM and PolyPIC's linear modes: APIC's transfers)
      // ASFLIP (Fei et al. 2021): v_p^{n+1} = v^PIC + α (v_p^n − Σ w v_i^n), C as APIC
      if (s.scheme == Scheme::asflip) ps.v[p] += s.flip_alpha * (v_n - v_old);
      if (s.kernel == KernelType::linear) {
        ps.C[p] = grad_v;  // Sec 5.9: C^{n+1} = Σ ṽ_i ∇w_ipᵀ = B^{n+1} (D_p^n)⁻¹, lagged
      } else {
        Mat<T, D> B = Mat<T, D>::Zero();  // eq 38, with x̃_i and x_p^{n+1} from eqs 30 and 39
        for_each_node(s, g, xp, [&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>& xi) {
          const Vec<T, D> vt = g.v_new[i], xt = xi + dt * vt;
          B += T(0.5) * w *
               (vt * (xi - xp + xt - x_new).transpose() + (xi - xp - xt + x_new) * vt.transpose());
        });
        ps.C[p] = B * Dp.inverse();  // eq 26: C = B D⁻¹, D_p = kΔx² I (quadratic ¼, cubic ⅓)
      }
      if (polypic) {
        // PolyPIC: the linear modes beyond the kept ones dropped; each higher mode by projection,
        // c_j = Σ w ṽ_i s_j / Σ w s_j².
        for (int c = polypic::linear_modes(kept, D); c < D; ++c) ps.C[p].col(c).setZero();
        for (int j = 0; j < extra; ++j) {
          Vec<T, D> num = Vec<T, D>::Zero();
          T den = 0;
          for_each_node(s, g, xp, [&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>& xi) {
            const T mode = polypic_mode(s, 1 + D + j, xp, Vec<T, D>(xi - xp));
            num += w * mode * g.v_new[i];
            den += w * mode * mode;
          });
          // a mode the grid cannot see (a weight exactly 0) gets 0 (schemes/polypic_modes.hpp)
          ps.modes[std::size_t(j)][p] = den > T(0) ? Vec<T, D>(num / den) : Vec<T, D>::Zero();
        }
      }
    } else {
      ps.v[p] = v_pic;  // eq 44
      // eq 42: ω_p = K_p⁻¹ l_p, with K_p at x_p^n: for linear weights (K_p not constant) this
      // lags K_p as Sec 5.9 lags D_p; quadratic and cubic K_p = 2kΔx² I is constant.
      const Vec<T, S> omega = K.inverse() * l;
      if constexpr (D == 2)
        ps.C[p] << 0, -omega[0], omega[0], 0;  // C_p = ω_p*
      else
        ps.C[p] << 0, -omega[2], omega[1], omega[2], 0, -omega[0], -omega[1], omega[0], 0;
    }

    // Move the particle. F by eq 40; MLS-MPM: the new C is the velocity gradient
    ps.F[p] = (Mat<T, D>::Identity() + dt * (mls ? ps.C[p] : grad_v)) * ps.F[p];

    // ASFLIP's position correction: x += Δt β α (v_p^n − Σ w v_i^n) for a particle that is not
    // being compressed (ln det F^{n+1} ≥ −10⁻³, the authors' pyasflip threshold); β_min = 0.
    if (s.scheme == Scheme::asflip && std::log(std::max(ps.F[p].determinant(), T(1e-15))) >= -1e-3)
      x_new += dt * s.asflip_beta * s.flip_alpha * (v_n - v_old);

    // Positions: a wall keeps the particle in the domain, a periodic axis wraps it.
    for (int a = 0; a < D; ++a) {
      const T lo = s.min[a], L = T(s.cells[a]) * s.dx, hi = lo + L;
      if (!s.periodic(a)) {
        x_new[a] = std::min(std::max(x_new[a], lo), hi);
      } else if (x_new[a] < lo || x_new[a] >= hi) {
        x_new[a] -= L * std::floor((x_new[a] - lo) / L);
        if (x_new[a] >= hi) x_new[a] = lo;  // round-off of the line above
      }
    }
    ps.x[p] = x_new;
  }
}

// Compiled once, in sim/reference/reference_step.cpp, for the tests and `apiclab bench
// --reference`.
extern template void step<float, 2>(const Setup<float, 2>&, ParticleState<float, 2>&, float);
extern template void step<double, 2>(const Setup<double, 2>&, ParticleState<double, 2>&, double);
extern template void step<float, 3>(const Setup<float, 3>&, ParticleState<float, 3>&, float);
extern template void step<double, 3>(const Setup<double, 3>&, ParticleState<double, 3>&, double);

}  // namespace apiclab::reference
