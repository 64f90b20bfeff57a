// B-spline kernel identities (Jiang et al. 2017, Sec 3.2 and eqs 18-19): partition of unity
// Σ w = 1, linear reproduction Σ w x_i = x_p, Σ ∇w = 0 and Σ x_i ∇wᵀ = I, in 2D and 3D for the
// linear, quadratic and cubic kernels, at random positions and at periodic wrap positions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sim/mpm/grid.hpp"
#include "sim/mpm/kernels.hpp"
#include "sim/mpm/stencil.hpp"
#include "tests/mpm/test_helpers.hpp"

namespace apiclab {
namespace {

template <int D>
Grid<double, D> make_grid(bool periodic, double dx) {
  return test::unit_box_grid<double, D>(periodic, dx);
}

template <int D, class K>
void check_identities(const Grid<double, D>& g, const Vec<double, D>& xp, const char* where) {
  SCOPED_TRACE(::testing::Message()
               << where << " x_p = " << xp.transpose() << " D = " << D << " width " << K::width);
  Stencil<double, D, K> st;
  st.compute(xp, g);
  double sw = 0;
  Vec<double, D> swx = Vec<double, D>::Zero(), swr = Vec<double, D>::Zero(),
                 sg = Vec<double, D>::Zero();
  Mat<double, D> sxg = Mat<double, D>::Zero(), srg = Mat<double, D>::Zero();
  bool any_periodic = false;
  for (int a = 0; a < D; ++a) any_periodic = any_periodic || g.periodic[a];
  int count = 0;
  st.for_each([&](std::size_t node, double w, const Vec<double, D>& grad, const Vec<double, D>& r) {
    ++count;
    ASSERT_LT(node, g.size());
    EXPECT_GE(w, 0.0);
    // The node really is x_p + r (modulo the period on periodic axes).
    Vec<double, D> xi = g.node_position(node), xu = xp + r;
    for (int a = 0; a < D; ++a) {
      double d = xu[a] - xi[a];
      if (g.periodic[a]) d -= std::round(d);       // period 1
      EXPECT_NEAR(d, 0.0, 1e-14) << "axis " << a;  // |x| ≤ 1, a few roundings of x/dx·dx
    }
    sw += w;
    swx += w * xi;
    swr += w * r;
    sg += grad;
    sxg += xi * grad.transpose();
    srg += r * grad.transpose();
  });
  EXPECT_EQ(count, int(std::pow(K::width, D)));
  // Each sum has ≤ 64 terms; weights are ≤ 1, positions ≤ 1.2, gradients ≤ 2/Δx: the bounds
  // below are ~20 ulp of the largest term, far below any kernel error (which would be O(1)).
  const double eps = std::numeric_limits<double>::epsilon();
  const double gscale = 2.0 / g.dx;
  EXPECT_NEAR(sw, 1.0, 64 * eps);
  EXPECT_LE(swr.norm(), 64 * eps * g.dx) << "Σ w (x_i - x_p) = 0";
  if (!any_periodic) {
    EXPECT_LE((swx - xp).norm(), 64 * eps * 1.2) << "Σ w x_i = x_p";
  }
  EXPECT_LE(sg.norm(), 64 * eps * gscale) << "Σ ∇w = 0";
  EXPECT_LE((srg - Mat<double, D>::Identity()).norm(), 64 * eps * gscale * g.dx)
      << "Σ (x_i - x_p) ∇wᵀ = I";
  if (!any_periodic) {
    EXPECT_LE((sxg - Mat<double, D>::Identity()).norm(), 64 * eps * gscale * 1.2)
        << "Σ x_i ∇wᵀ = I";
  }
  // D_p = k Δx² I for quadratic and cubic (Sec 3.3); 1e-14: ~10 ulp of the per-axis sums.
  if (K::type != KernelType::linear) {
    Mat<double, D> Dp = st.inertia();
    double k = inertia_factor(K::type) * g.dx * g.dx;
    EXPECT_LE((Dp - k * Mat<double, D>::Identity()).norm(), 1e-14 * k);
  }
}

template <int D, class K>
void run_kernel_identities() {
  std::mt19937_64 rng(1234 + D * 10 + K::width);
  const double dx = 1.0 / 16;
  // Walls: random positions anywhere in the domain (the ghost layer keeps stencils in range).
  {
    Grid<double, D> g = make_grid<D>(false, dx);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int s = 0; s < 200; ++s) {
      Vec<double, D> x;
      for (int a = 0; a < D; ++a) x[a] = u(rng);
      check_identities<D, K>(g, x, "walls");
    }
    // Exactly on nodes and cell centres, and on the domain faces.
    for (double c : {0.0, 0.5 * dx, 3 * dx, 1.0}) {
      Vec<double, D> x = Vec<double, D>::Constant(c);
      check_identities<D, K>(g, x, "walls, special");
    }
  }
  // Periodic: random positions, and positions within a hair of the wrap on every axis.
  {
    Grid<double, D> g = make_grid<D>(true, dx);
    std::uniform_real_distribution<double> u(0.0, 1.0), edge(0.0, 1e-3);
    for (int s = 0; s < 100; ++s) {
      Vec<double, D> x;
      for (int a = 0; a < D; ++a) x[a] = u(rng);
      check_identities<D, K>(g, x, "periodic");
    }
    for (int s = 0; s < 100; ++s) {
      Vec<double, D> x;
      for (int a = 0; a < D; ++a) x[a] = (s + a) % 2 ? edge(rng) : 1.0 - edge(rng);
      check_identities<D, K>(g, x, "periodic edge");
    }
    for (double c : {0.0, 1.0 - 1e-12, 0.5 * dx, 1.0 - 0.5 * dx}) {
      Vec<double, D> x = Vec<double, D>::Constant(c);
      check_identities<D, K>(g, x, "periodic special");
    }
  }
}

TEST(Kernels, Linear2D) { run_kernel_identities<2, LinearKernel>(); }
TEST(Kernels, Quadratic2D) { run_kernel_identities<2, QuadraticKernel>(); }
TEST(Kernels, Cubic2D) { run_kernel_identities<2, CubicKernel>(); }
TEST(Kernels, Linear3D) { run_kernel_identities<3, LinearKernel>(); }
TEST(Kernels, Quadratic3D) { run_kernel_identities<3, QuadraticKernel>(); }
TEST(Kernels, Cubic3D) { run_kernel_identities<3, CubicKernel>(); }

// The implicit Hessian's stencil products by rows (Stencil::gradient_gather / gradient_scatter)
// against node-by-node sums: Σ u_i ∇w_iᵀ over for_each, an affine field u = A x + c gathering
// to A (Σ x_i ∇wᵀ = I, Σ ∇w = 0), and the scatter the gather's adjoint:
// Σ_i u_i · (s ∇w_i) = s : Σ_i u_i ∇w_iᵀ. Walls and periodic axes (wrapped offsets).
template <class T, int D, class K>
void check_gradient_rows(bool periodic) {
  SCOPED_TRACE(::testing::Message() << "D = " << D << " sizeof(T) = " << sizeof(T) << " width "
                                    << K::width << (periodic ? " periodic" : " walls"));
  const double dx = 1.0 / 16;
  const Grid<T, D> g = test::unit_box_grid<T, D>(periodic, dx);
  std::mt19937_64 rng(77 + D * 10 + K::width);
  std::uniform_real_distribution<double> u01(0.0, 1.0), u11(-1.0, 1.0);
  Mat<T, D> A, s;
  Vec<T, D> c;
  for (int a = 0; a < D; ++a) {
    c[a] = T(u11(rng));
    for (int b = 0; b < D; ++b) A(a, b) = T(u11(rng)), s(a, b) = T(u11(rng));
  }
  std::vector<Vec<T, D>> field(g.size()), affine(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    for (int a = 0; a < D; ++a) field[i][a] = T(u11(rng));
    affine[i] = A * g.node_position(i).template cast<T>() + c;
  }
  // Terms ≤ 1 (fields) times ≤ 2/Δx (gradients), ≤ 64 of them: 64 ε of 2/Δx bounds a regrouping.
  const double tol = 64 * double(std::numeric_limits<T>::epsilon()) * 2 / dx;
  Stencil<T, D, K> st;
  for (int n = 0; n < 50; ++n) {
    Vec<T, D> xp;
    for (int a = 0; a < D; ++a) xp[a] = T(periodic || n % 2 ? u01(rng) : 0.2 + 0.6 * u01(rng));
    st.compute(xp, g);
    Mat<T, D> by_node = Mat<T, D>::Zero();
    std::vector<Vec<T, D>> scattered(g.size(), Vec<T, D>::Zero()),
        by_node_scatter(g.size(), Vec<T, D>::Zero());
    st.for_each([&](std::size_t i, T, const Vec<T, D>& gw, const Vec<T, D>&) {
      by_node += field[i] * gw.transpose();
      by_node_scatter[i] += s * gw;
    });
    const Mat<T, D> rows = st.gradient_gather(field.data());
    EXPECT_LE(double((rows - by_node).norm()), tol) << "x_p = " << xp.transpose();
    st.gradient_scatter(s, scattered.data());
    double dot = 0, worst = 0;
    for (std::size_t i = 0; i < g.size(); ++i) {
      dot += double(field[i].dot(scattered[i]));
      worst = std::max(worst, double((scattered[i] - by_node_scatter[i]).norm()));
    }
    EXPECT_LE(worst, tol) << "x_p = " << xp.transpose();
    EXPECT_NEAR(dot, double((s.cwiseProduct(rows)).sum()), D * D * tol) << "adjoint";
    if (!periodic) {  // an affine field is not periodic
      EXPECT_LE(double((st.gradient_gather(affine.data()) - A).norm()), 4 * tol) << "affine";
    }
  }
}

template <class T, int D>
void check_gradient_rows_all_kernels() {
  for (bool periodic : {false, true}) {
    check_gradient_rows<T, D, LinearKernel>(periodic);
    check_gradient_rows<T, D, QuadraticKernel>(periodic);
    check_gradient_rows<T, D, CubicKernel>(periodic);
  }
}

TEST(Kernels, GradientRows2D) {
  check_gradient_rows_all_kernels<double, 2>();
  check_gradient_rows_all_kernels<float, 2>();
}
TEST(Kernels, GradientRows3D) {
  check_gradient_rows_all_kernels<double, 3>();
  check_gradient_rows_all_kernels<float, 3>();
}

// The 1D weights and derivatives against the B-spline formulas and finite differences.
template <class K>
void check_1d_derivatives() {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int s = 0; s < 500; ++s) {
    double x = u(rng);
    double w[4], dw[4], wp[4], dwp[4], wm[4], dwm[4];
    int base = K::weights(x, w, dw);
    const double h = 1e-6;
    int bp = K::weights(x + h, wp, dwp), bm = K::weights(x - h, wm, dwm);
    if (bp != base || bm != base) continue;  // the stencil shifted between the samples
    for (int k = 0; k < K::width; ++k) {
      // Central differences of a piecewise polynomial of degree ≤ 3: error h²/6·|w'''| ≤ 1e-12,
      // rounding ε/h ≈ 1e-10; the kernel derivative is O(1).
      EXPECT_NEAR(dw[k], (wp[k] - wm[k]) / (2 * h), 1e-8) << "x = " << x << " node " << k;
      // Support: |x - node| < width/2 (in grid units).
      EXPECT_LT(std::abs(x - (base + k)), 0.5 * K::width + 1e-12);
    }
  }
}

TEST(Kernels, DerivativesMatchFiniteDifferences) {
  check_1d_derivatives<LinearKernel>();
  check_1d_derivatives<QuadraticKernel>();
  check_1d_derivatives<CubicKernel>();
}

}  // namespace
}  // namespace apiclab
