// PolyPIC (Fu, Guo, Gast, Jiang and Teran 2017, "A polynomial particle-in-cell method", ACM TOG
// 36(6), 222): each particle carries a velocity field v_p(x) = Σ_r c_pr s_r(x_i − x_p) over scalar
// modes s_r that are orthogonal under the kernel weights, Σ_i w_ip s_r s_t = 0 (r ≠ t). Then
//   G2P: c_pr = Σ_i w_ip ṽ_i s_r(x_i − x_p) / Σ_i w_ip s_r²   (a projection per mode)
//   P2G: (m v)_i = Σ_p w_ip m_p Σ_r c_pr s_r(x_i − x_p).
// For the quadratic B-spline the stencil has 3 nodes per axis; the 1D functions on them are
// spanned by {1, u, G(u)}, u = (x_i − x_p)/Δx, with G the quadratic orthogonal to 1 and u under
// the axis weights (the paper's G_x, G_y: unique up to scale, built here by Gram-Schmidt). The
// tensor products give 9 modes in 2D and 27 in 3D, which span every function on the stencil.
// (G here is the cross-product form, AxisBasis, equal to u² − a u − b up to a positive scale.)
//
// Modes 0..D are 1, x, y[, z]: the constant is v_p, the linear ones APIC's C_p (kept in
// Particles::C, the same B D⁻¹ as APIC's eq 38). Only the modes beyond them live in
// Particles::modes, allocated only for this scheme. Linear momentum is conserved because every
// mode but 1 has Σ w s_r = 0; angular momentum as APIC's, because a mode orthogonal to the
// linear ones adds Σ_i w (x_i − x_p) × c s_r = 0 to the grid's.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <tuple>
#include <vector>

#include "sim/math.hpp"
#include "sim/mpm/simd/lanes.hpp"

namespace apiclab::polypic {

// The full basis of the quadratic B-spline: 3 functions per axis.
constexpr int full_modes(int dim) { return dim == 2 ? 9 : 27; }
// solver.polypic_modes: 0 means all. The scene reader refuses more than the full basis for a
// polypic scene; a scene of another scheme switched to polypic live (the GUI) keeps at most all.
constexpr int kept_modes(int setting, int dim) {
  return setting == 0 ? full_modes(dim) : std::min(setting, full_modes(dim));
}
// Modes stored beyond the constant and linear ones (Particles::modes).
constexpr int extra_modes(int kept, int dim) { return std::max(0, kept - 1 - dim); }
// Whether the kept modes reach the G's (past the 2^dim multilinear ones): those blow up on
// impacts, a property of the method (docs/transfer-schemes.md; the projection reads a
// node of kernel weight w -> 0 at weight 1/2, tests/mpm/test_polypic_g_modes.cpp).
constexpr bool keeps_g_modes(int kept, int dim) { return kept > (1 << dim); }
// How many of C's columns (the linear modes x, y, z in order) are kept.
constexpr int linear_modes(int kept, int dim) { return std::clamp(kept - 1, 0, dim); }

// Each mode as per-axis degrees (0: 1, 1: u, 2: G(u)), ordered by the number of G factors,
// then total degree, then axis order: 2D 1, x, y, xy, Gx, Gy, Gx y, x Gy, Gx Gy (the paper's
// order); in 3D the trilinear eight come first, then the modes with one, two and three G's.
template <int D>
const std::array<std::array<int, D>, full_modes(D)>& mode_degrees() {
  static const auto table = [] {
    std::array<std::array<int, D>, full_modes(D)> t;
    for (int c = 0; c < full_modes(D); ++c)
      for (int a = 0, rest = c; a < D; ++a, rest /= 3) t[std::size_t(c)][std::size_t(a)] = rest % 3;
    auto key = [](const std::array<int, D>& m) {
      int gs = 0, sum = 0;
      for (int d : m) gs += d == 2, sum += d;
      return std::make_tuple(gs, sum);
    };
    std::sort(t.begin(), t.end(), [&](const auto& a, const auto& b) {
      if (key(a) != key(b)) return key(a) < key(b);
      return a > b;  // axis 0 first: x before y, Gx before Gy
    });
    return t;
  }();
  return table;
}

// The 1D functions 1, u, G at the three nodes of one axis (u = −f, 1 − f, 2 − f: unit
// spacing), and their norms Σ_k w_k f². G must satisfy Σ w G = Σ w u G = 0: it is the cross
// product of (w_k) and (w_k u_k), G_k = w_{k+1} w_{k+2} (u_{k+2} − u_{k+1}) (indices mod 3), i.e.
// 8 (w_1 w_2, −2 w_0 w_2, w_0 w_1), scaled by 8 to equal u² − ¼ for a particle on a node. This
// form has no cancellation: the textbook u² − a u − b subtracts O(1) terms to an O(w) result
// next to a vanishing weight, where the projection then amplifies round-off by 1/w.
template <class T, int W>
struct AxisBasis {
  static_assert(W == 3, "PolyPIC's basis is the quadratic B-spline's");
  T value[3][W];
  T norm[3];
  // w: the axis weights, r: x_i − x_p per node (length), inv_dx = 1/Δx.
  void compute(const T* w, const T* r, T inv_dx) {
    value[2][0] = T(8) * w[1] * w[2];
    value[2][1] = T(-16) * w[0] * w[2];
    value[2][2] = T(8) * w[0] * w[1];
    for (int f = 0; f < 3; ++f) norm[f] = 0;
    for (int k = 0; k < W; ++k) {
      value[0][k] = T(1);
      value[1][k] = r[k] * inv_dx;
      for (int f = 0; f < 3; ++f) norm[f] += w[k] * value[f][k] * value[f][k];
    }
  }
};

// The per-axis bases of one particle's stencil (Stencil<T, D, QuadraticKernel>).
template <class T, int D, class St>
std::array<AxisBasis<T, St::W>, D> axis_bases(const St& st, T inv_dx) {
  std::array<AxisBasis<T, St::W>, D> b;
  for (int a = 0; a < D; ++a) b[std::size_t(a)].compute(st.w[a], st.r[a], inv_dx);
  return b;
}

// f(node offset, w_ip, per-axis node index) over the stencil.
template <class T, int D, class St, class Fn>
void for_each_indexed_node(const St& st, Fn&& f) {
  constexpr int W = St::W;
  constexpr int count = D == 2 ? W * W : W * W * W;
  std::array<int, D> k;
  for (int c = 0; c < count; ++c) {
    std::size_t off = 0;
    T w = T(1);
    for (int a = 0, rest = c; a < D; ++a, rest /= W) {
      k[std::size_t(a)] = rest % W;
      off += st.off[a][k[std::size_t(a)]];
      w *= st.w[a][k[std::size_t(a)]];
    }
    f(off, w, k);
  }
}

// s_r at stencil node k, and Σ_i w_ip s_r² (a product of the axis norms).
template <class T, int D, int W>
T mode_value(const std::array<AxisBasis<T, W>, D>& b, int mode, const std::array<int, D>& k) {
  const auto& deg = mode_degrees<D>()[std::size_t(mode)];
  T s = T(1);
  for (int a = 0; a < D; ++a) s *= b[std::size_t(a)].value[deg[std::size_t(a)]][k[std::size_t(a)]];
  return s;
}
template <class T, int D, int W>
T mode_norm(const std::array<AxisBasis<T, W>, D>& b, int mode) {
  const auto& deg = mode_degrees<D>()[std::size_t(mode)];
  T n = T(1);
  for (int a = 0; a < D; ++a) n *= b[std::size_t(a)].norm[deg[std::size_t(a)]];
  return n;
}

// A particle exactly where one of an axis's weights vanishes (|x_p − x_i| = 1.5 Δx) sees two
// nodes on that axis: its modes with G are invisible to the grid (norm exactly 0) and get 0.
// The modes beyond the linear ones after G2P: c_r = Σ w ṽ_i s_r / Σ w s_r² for stored mode j
// (basis mode 1 + D + j), written to modes[j][q]. `velocity` is the grid's ṽ.
template <class T, int D, class St>
void gather_modes(const St& st, T inv_dx, const std::vector<Vec<T, D>>& velocity, int extra,
                  std::vector<std::vector<Vec<T, D>>>& modes, std::size_t q) {
  if (extra == 0) return;
  const auto b = axis_bases<T, D>(st, inv_dx);
  Vec<T, D> sum[full_modes(3)];
  for (int j = 0; j < extra; ++j) sum[j].setZero();
  for_each_indexed_node<T, D>(st, [&](std::size_t off, T w, const std::array<int, D>& k) {
    const Vec<T, D> wv = w * velocity[off];
    for (int j = 0; j < extra; ++j) sum[j] += mode_value<T, D>(b, 1 + D + j, k) * wv;
  });
  for (int j = 0; j < extra; ++j) {
    const T norm = mode_norm<T, D>(b, 1 + D + j);
    modes[std::size_t(j)][q] = norm > T(0) ? Vec<T, D>(sum[j] / norm) : Vec<T, D>::Zero();
  }
}

// The higher modes' velocity at every node of one particle's stencil: f(offset, Σ_j c_j s_j).
template <class T, int D, class St, class Fn>
void scatter_modes(const St& st, T inv_dx, const std::vector<std::vector<Vec<T, D>>>& modes,
                   std::size_t q, Fn&& f) {
  const int extra = int(modes.size());
  if (extra == 0) return;
  const auto b = axis_bases<T, D>(st, inv_dx);
  for_each_indexed_node<T, D>(st, [&](std::size_t off, T w, const std::array<int, D>& k) {
    Vec<T, D> v = Vec<T, D>::Zero();
    for (int j = 0; j < extra; ++j)
      v += mode_value<T, D>(b, 1 + D + j, k) * modes[std::size_t(j)][q];
    f(off, w, v);
  });
}

// The same transfers in the row form of P2G and G2P (sim/mpm/stencil.hpp, sim/mpm/simd/lanes.hpp),
// used by the step. A mode is a product of per-axis functions, s_r(k) = Π_a b_a[f_a][k_a], so the
// sums over the 3^D stencil nodes factorise axis by axis (sum factorisation): the projections of
// every mode at once cost D contractions of F × 3 terms per node row, not (modes × nodes)
// products, and each term is one multiply-add on a node's lane group. F is the number of
// per-axis functions the kept modes reach: 2 (1, u) up to the multilinear modes, 3 with the G's.
// Coefficient tables are indexed f_0 + F f_1 + F² f_2.
// Weighted = false keeps the bare axis functions b_f(k) (a velocity at the nodes, not a
// momentum contribution): the CFL rule's speed bound, max_modes_speed_rows.
template <class T, int D, int F, int W, bool Weighted = true>
struct RowBasis {
  static constexpr int count = D == 2 ? F * F : F * F * F;
  T a[D][F][W];  // w_k b_f(k) per axis: the weight folded into the axis functions
  T norm[D][F];
  template <class St>
  RowBasis(const St& st, T inv_dx) {
    for (int ax = 0; ax < D; ++ax) {
      AxisBasis<T, W> b;
      b.compute(st.w[ax], st.r[ax], inv_dx);
      for (int f = 0; f < F; ++f) {
        norm[ax][f] = b.norm[f];
        for (int k = 0; k < W; ++k)
          a[ax][f][k] = Weighted ? st.w[ax][k] * b.value[f][k] : b.value[f][k];
      }
    }
  }
  // Table index and Σ_i w s² of stored mode j (basis mode 1 + D + j).
  static int index(int j) {
    const auto& deg = mode_degrees<D>()[std::size_t(1 + D + j)];
    int idx = 0;
    for (int ax = D - 1; ax >= 0; --ax) idx = idx * F + deg[std::size_t(ax)];
    return idx;
  }
  T mode_norm(int j) const {
    const auto& deg = mode_degrees<D>()[std::size_t(1 + D + j)];
    T n = T(1);
    for (int ax = 0; ax < D; ++ax) n *= norm[ax][deg[std::size_t(ax)]];
    return n;
  }
};

// gather_modes in row form: `node(offset)` gives a node's lane group with ṽ in lanes 0..D−1.
template <class T, int D, int F, class L, class St, class NodeAt>
void gather_modes_rows(const St& st, T inv_dx, NodeAt&& node, int extra,
                       std::vector<std::vector<Vec<T, D>>>& modes, std::size_t q) {
  constexpr int W = St::W;
  const RowBasis<T, D, F, W> rb(st, inv_dx);
  L coef[RowBasis<T, D, F, W>::count] = {};
  // Σ_i a0[f0][i] ṽ(i, row): the row's F sums along axis 0.
  auto row_sums = [&](std::size_t row_off, L* t) {
    for (int i = 0; i < W; ++i) {
      const L n = node(st.off[0][i] + row_off);
      for (int f = 0; f < F; ++f) t[f] += rb.a[0][f][i] * n;
    }
  };
  if constexpr (D == 2) {
    for (int j = 0; j < W; ++j) {
      L t[F] = {};
      row_sums(st.off[1][j], t);
      for (int f1 = 0; f1 < F; ++f1)
        for (int f0 = 0; f0 < F; ++f0) coef[f0 + F * f1] += rb.a[1][f1][j] * t[f0];
    }
  } else {
    for (int k = 0; k < W; ++k) {
      L u[F * F] = {};
      for (int j = 0; j < W; ++j) {
        L t[F] = {};
        row_sums(st.off[1][j] + st.off[2][k], t);
        for (int f1 = 0; f1 < F; ++f1)
          for (int f0 = 0; f0 < F; ++f0) u[f0 + F * f1] += rb.a[1][f1][j] * t[f0];
      }
      for (int f2 = 0; f2 < F; ++f2)
        for (int e = 0; e < F * F; ++e) coef[e + F * F * f2] += rb.a[2][f2][k] * u[e];
    }
  }
  for (int j = 0; j < extra; ++j) {
    const L& c = coef[RowBasis<T, D, F, W>::index(j)];
    const T norm = rb.mode_norm(j);
    Vec<T, D>& out = modes[std::size_t(j)][q];
    for (int a = 0; a < D; ++a) out[a] = norm > T(0) ? c[a] / norm : T(0);
  }
}

// The stencil's node values of a coefficient table c (indexed f_0 + F f_1 + F² f_2) over the
// axis functions a[axis][f][k]: emit(offset, Σ_f c_f Π_ax a[ax][f_ax][k_ax]) for every node, in
// row form: per row r[f0] = Σ_{f1} a1[f1][j] u[f0 + F f1], then each node Σ_{f0} a0[f0][i] r[f0].
template <class T, int D, int F, int W, class L, class St, class Emit>
void expand_rows(const T (&a)[D][F][W], const St& st, const L* c, Emit&& emit) {
  auto row = [&](std::size_t row_off, int j, const L* u) {
    L r[F] = {};
    for (int f1 = 0; f1 < F; ++f1)
      for (int f0 = 0; f0 < F; ++f0) r[f0] += a[1][f1][j] * u[f0 + F * f1];
    for (int i = 0; i < W; ++i) {
      L v = a[0][0][i] * r[0];
      for (int f0 = 1; f0 < F; ++f0) v += a[0][f0][i] * r[f0];
      emit(st.off[0][i] + row_off, v);
    }
  };
  if constexpr (D == 2) {
    for (int j = 0; j < W; ++j) row(st.off[1][j], j, c);
  } else {
    for (int k = 0; k < W; ++k) {
      L u[F * F] = {};
      for (int f2 = 0; f2 < F; ++f2)
        for (int e = 0; e < F * F; ++e) u[e] += a[2][f2][k] * c[e + F * F * f2];
      for (int j = 0; j < W; ++j) row(st.off[1][j] + st.off[2][k], j, u);
    }
  }
}

// scatter_modes in row form, weighted by the particle mass for P2G: add(offset, lanes) with
// lanes (0, m w_ip Σ_j c_j s_j) in the P2G accumulator's layout [m, m v (D), …].
template <class T, int D, int F, class L, class St, class Add>
void scatter_modes_rows(const St& st, T inv_dx, const std::vector<std::vector<Vec<T, D>>>& modes,
                        std::size_t q, T mass, Add&& add) {
  constexpr int W = St::W;
  const RowBasis<T, D, F, W> rb(st, inv_dx);
  L c[RowBasis<T, D, F, W>::count] = {};
  for (int j = 0; j < int(modes.size()); ++j) {
    const Vec<T, D> mc = mass * modes[std::size_t(j)][q];
    if constexpr (D == 2)
      c[RowBasis<T, D, F, W>::index(j)] = L::of(T(0), mc[0], mc[1]);
    else
      c[RowBasis<T, D, F, W>::index(j)] = L::of(T(0), mc[0], mc[1], mc[2]);
  }
  expand_rows<T, D, F, W>(rb.a, st, c, add);
}

// The largest speed the higher modes give a node of the stencil, max_i |Σ_j c_j s_j(x_i − x_p)|
// over all 3^D nodes whatever their weight (the PolyPIC term of the CFL rule, choose_dt in
// sim/time_step_rules.hpp): scatter_modes_rows' expansion with the bare axis functions, on
// lane groups of 4 values (the velocity, no mass lane; 4, not D: there is no 2-float register).
template <class T, int D, int F, class St>
T max_modes_speed_rows(const St& st, T inv_dx, const std::vector<std::vector<Vec<T, D>>>& modes,
                       std::size_t q) {
  constexpr int W = St::W;
  using L = Lanes<T, 4>;
  const RowBasis<T, D, F, W, false> rb(st, inv_dx);
  L c[RowBasis<T, D, F, W, false>::count] = {};
  for (int j = 0; j < int(modes.size()); ++j) {
    const Vec<T, D>& m = modes[std::size_t(j)][q];
    if constexpr (D == 2)
      c[RowBasis<T, D, F, W, false>::index(j)] = L::of(m[0], m[1]);
    else
      c[RowBasis<T, D, F, W, false>::index(j)] = L::of(m[0], m[1], m[2]);
  }
  T speed2 = 0;
  expand_rows<T, D, F, W>(rb.a, st, c, [&](std::size_t, const L& v) {
    T s = 0;
    for (int a = 0; a < D; ++a) s += v[a] * v[a];
    speed2 = std::max(speed2, s);
  });
  return std::sqrt(speed2);
}

// Σ_j |c_j|² Σ_i w s_j²: the higher modes' share of Σ_i w_ip |v_p(x_i)|² (the modes are
// orthogonal, so kinetic energy splits mode by mode).
template <class T, int D, class St>
T modes_energy_density(const St& st, T inv_dx, const std::vector<std::vector<Vec<T, D>>>& modes,
                       std::size_t q) {
  if (modes.empty()) return T(0);
  const auto b = axis_bases<T, D>(st, inv_dx);
  T e = 0;
  for (int j = 0; j < int(modes.size()); ++j)
    e += modes[std::size_t(j)][q].squaredNorm() * mode_norm<T, D>(b, 1 + D + j);
  return e;
}

// C with the linear modes beyond the kept ones zeroed (1 mode: PIC, C = 0).
template <class T, int D>
void keep_linear_modes(Mat<T, D>& C, int kept) {
  for (int c = linear_modes(kept, D); c < D; ++c) C.col(c).setZero();
}

}  // namespace apiclab::polypic
