// The kernel stencil of one particle: per-axis weights, gradients, node offsets and
// x_i − x_p, computed once and visited node by node (eqs 18-19).
#pragma once
#include <cstddef>

#include "sim/mpm/grid.hpp"
#include "sim/mpm/kernels.hpp"

namespace apiclab {

template <class T, int D, class K>
struct Stencil {
  static constexpr int W = K::width;
  T w[D][W], dw[D][W];    // dw already in 1/length units
  T r[D][W];              // (x_i − x_p) per axis
  std::size_t off[D][W];  // stored-node index contribution per axis (wrapped, re-based × stride)

  void compute(const Vec<T, D>& x, const GridGeometry<T, D>& g) {
    for (int a = 0; a < D; ++a) {
      const int base = axis(x[a], g.origin[a], g.inv_dx, g.dx, w[a], dw[a], r[a]);
      for (int k = 0; k < W; ++k) off[a][k] = offset(base + k, a, g);
    }
  }

  // Along one axis (grid origin, 1/Δx, Δx), for the W nodes from the returned base: w, dw
  // (1/length) and x_i − x_p at the coordinate x (shared with StencilBatch, whose lanes take
  // the vectorisable floor; the grid's values passed by value, which its vector loop needs).
  template <class Floor = StdFloor>
  static int axis(T x, T origin, T inv_dx, T dx, T* w, T* dw, T* r, Floor floor = {}) {
    const T xg = (x - origin) * inv_dx;
    const int base = K::weights(xg, w, dw, floor);
    for (int k = 0; k < W; ++k) {
      dw[k] *= inv_dx;
      r[k] = (T(base + k) - xg) * dx;
    }
    return base;
  }
  // Stored-node index contribution of domain node `node` along axis a (wrapped, re-based × stride).
  static std::size_t offset(int node, int a, const GridGeometry<T, D>& g) {
    const int idx = g.periodic[a] ? g.wrap(node, a) : node;
    return std::size_t(idx - g.lo[a]) * g.stride[a];
  }

  // f(node, w_ip, ∇w_ip, x_i − x_p) for every node of the stencil.
  template <class Fn>
  void for_each(Fn&& f) const {
    if constexpr (D == 2) {
      for (int j = 0; j < W; ++j)
        for (int i = 0; i < W; ++i) {
          T wij = w[0][i] * w[1][j];
          Vec<T, 2> grad(dw[0][i] * w[1][j], w[0][i] * dw[1][j]);
          Vec<T, 2> rr(r[0][i], r[1][j]);
          f(off[0][i] + off[1][j], wij, grad, rr);
        }
    } else {
      for (int k = 0; k < W; ++k)
        for (int j = 0; j < W; ++j) {
          T wjk = w[1][j] * w[2][k];
          for (int i = 0; i < W; ++i) {
            T wijk = w[0][i] * wjk;
            Vec<T, 3> grad(dw[0][i] * wjk, w[0][i] * dw[1][j] * w[2][k],
                           w[0][i] * w[1][j] * dw[2][k]);
            Vec<T, 3> rr(r[0][i], r[1][j], r[2][k]);
            f(off[0][i] + off[1][j] + off[2][k], wijk, grad, rr);
          }
        }
    }
  }

  // The stencil as rows along axis 0: f(row) for every combination of the other axes, where
  // row.off is the node offset of those axes, row.w = Π_{a≥1} w_a, row.dw[0] = row.w and
  // row.dw[a] = row.w with axis a differentiated, row.r[a] = (x_i − x_p)_a (row.r[0] = 0).
  // Tensor-product loops then cost a few operations per node (the hot P2G/G2P path).
  struct Row {
    std::size_t off;
    T w;
    Vec<T, D> dw, r;
    T wr(int a) const { return w * r[a]; }  // row.w (x_i − x_p)_a, as StencilBatch::Row has it
  };
  // Forced inline (with the row bodies in g2p.hpp): GCC 12 otherwise keeps it out of line on
  // x86-64-v3 in 3D double, and the caller's sums then go through memory at every row.
  template <class Fn>
  __attribute__((always_inline)) void for_each_row(Fn&& f) const {
    Row row;
    if constexpr (D == 2) {
      for (int j = 0; j < W; ++j) {
        row.off = off[1][j];
        row.w = w[1][j];
        row.dw = Vec<T, 2>(w[1][j], dw[1][j]);
        row.r = Vec<T, 2>(T(0), r[1][j]);
        f(row);
      }
    } else {
      for (int k = 0; k < W; ++k)
        for (int j = 0; j < W; ++j) {
          row.off = off[1][j] + off[2][k];
          row.w = w[1][j] * w[2][k];
          row.dw = Vec<T, 3>(row.w, dw[1][j] * w[2][k], w[1][j] * dw[2][k]);
          row.r = Vec<T, 3>(T(0), r[1][j], r[2][k]);
          f(row);
        }
    }
  }

  // Σ_i u_i ∇w_ipᵀ over the stencil's nodes of `u` (the implicit Hessian's δF, eq 36), by rows:
  // ∇w_i = (dw₀ row.w, w₀ row.dw₁, …), so per row two sums over axis 0 and D column updates.
  // Column by column, not Eigen's outer product: GCC 12 stored that product's two 128-bit halves
  // and reloaded them as one 256-bit value per node, a store-forwarding stall each time.
  Mat<T, D> gradient_gather(const Vec<T, D>* u) const {
    Mat<T, D> G = Mat<T, D>::Zero();
    for_each_row([&](const Row& row) {
      Vec<T, D> along = Vec<T, D>::Zero(), across = Vec<T, D>::Zero();  // Σ dw₀ u, Σ w₀ u
      for (int i = 0; i < W; ++i) {
        const Vec<T, D>& ui = u[row.off + off[0][i]];
        along += dw[0][i] * ui;
        across += w[0][i] * ui;
      }
      G.col(0) += row.dw[0] * along;
      for (int a = 1; a < D; ++a) G.col(a) += row.dw[a] * across;
    });
    return G;
  }
  // out_i += s ∇w_ip for the stencil's nodes (eq 35's force on a node), by the same rows.
  void gradient_scatter(const Mat<T, D>& s, Vec<T, D>* out) const {
    for_each_row([&](const Row& row) {
      const Vec<T, D> along = row.dw[0] * s.col(0);
      Vec<T, D> across = row.dw[1] * s.col(1);
      for (int a = 2; a < D; ++a) across += row.dw[a] * s.col(a);
      for (int i = 0; i < W; ++i) out[row.off + off[0][i]] += dw[0][i] * along + w[0][i] * across;
    });
  }

  // D_p = Σ w (x_i − x_p)(x_i − x_p)ᵀ (eq 25); diagonal for tensor-product kernels.
  Mat<T, D> inertia() const {
    Mat<T, D> Dp = Mat<T, D>::Zero();
    for (int a = 0; a < D; ++a) {
      T s = 0;
      for (int k = 0; k < W; ++k) s += w[a][k] * r[a][k] * r[a][k];
      Dp(a, a) = s;
    }
    return Dp;
  }
};

}  // namespace apiclab
