#include "roundtrip.hpp"

#include <cmath>
#include <stdexcept>

#include "grid.hpp"
#include "sampling.hpp"
#include "stencil.hpp"

namespace apiclab {
namespace {

template <class K>
RoundTripResult run(Scheme scheme, int n, std::uint64_t seed) {
  using T = double;
  constexpr int D = 2;
  SceneDesc s;
  s.dim = 2;
  s.domain.min = {0, 0, 0};
  s.domain.max = {2 * M_PI, 2 * M_PI, 0};
  s.domain.dx = 2 * M_PI / n;
  s.domain.walls.fill(BoundaryCondition::periodic);
  Grid<T, D> g;
  g.init(s);
  std::vector<Vec<T, D>> v0(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    Vec<T, D> x = g.node_position(i);
    v0[i] = Vec<T, D>(1.1 * std::sin(x[0]), 0.9 * std::cos(x[1]));
  }
  std::vector<Vec3d> pts = poisson_disk(s.domain.min, s.domain.max, s.domain.dx / 3, 2, seed, true);
  const T k = inertia_factor(K::type) * s.domain.dx * s.domain.dx;
  const bool affine = scheme != Scheme::pic;
  std::vector<T> mass(g.size(), 0.0);
  std::vector<Vec<T, D>> mom(g.size(), Vec<T, D>::Zero());
  Stencil<T, D, K> st;
  for (const Vec3d& p : pts) {
    Vec<T, D> x(p[0], p[1]);
    st.compute(x, g);
    // G2P at Δt = 0: v_p = Σ w v_i (eq 37), B_p = Σ w v_i rᵀ (eq 38 with x̃ = x).
    Vec<T, D> v = Vec<T, D>::Zero();
    Mat<T, D> B = Mat<T, D>::Zero(), G = Mat<T, D>::Zero();
    st.for_each([&](std::size_t i, T w, const Vec<T, D>& grad, const Vec<T, D>& r) {
      v += w * v0[i];
      B += w * v0[i] * r.transpose();
      G += v0[i] * grad.transpose();
    });
    Mat<T, D> C = Mat<T, D>::Zero();
    if (affine) C = K::type == KernelType::linear ? G : Mat<T, D>(B / k);
    if (scheme == Scheme::rpic) C = (0.5 * (C - C.transpose())).eval();  // eval: C aliases Cᵀ
    // P2G with unit particle mass (eqs 24, 26).
    st.for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>& r) {
      mass[i] += w;
      mom[i] += w * (v + C * r);
    });
  }
  double err2 = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    Vec<T, D> v = mass[i] > 0 ? Vec<T, D>(mom[i] / mass[i]) : Vec<T, D>::Zero();
    err2 += (v - v0[i]).squaredNorm() * s.domain.dx * s.domain.dx;
  }
  return {n, s.domain.dx, std::sqrt(err2), pts.size()};
}

}  // namespace

RoundTripResult roundtrip_error(KernelType kernel, Scheme scheme, int resolution, std::uint64_t seed) {
  if (scheme == Scheme::flip)
    throw std::invalid_argument("the round trip starts from the grid; FLIP needs prior particle velocities (use pic, apic or rpic)");
  if (resolution < 4) throw std::invalid_argument("resolution must be at least 4");
  switch (kernel) {
    case KernelType::linear: return run<LinearKernel>(scheme, resolution, seed);
    case KernelType::quadratic: return run<QuadraticKernel>(scheme, resolution, seed);
    case KernelType::cubic: return run<CubicKernel>(scheme, resolution, seed);
  }
  return {};
}

}  // namespace apiclab
