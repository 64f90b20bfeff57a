// The stencils of a few consecutive particles at once, the particles across SIMD lanes: one
// particle's Stencil::compute is a floor, three int/float conversions and a dozen dependent
// products per axis, about a fifth of G2P in 2D float when done per particle.
// Same operations per lane as Stencil::compute; the results agree to the rounding of x / Δx,
// not bit for bit, because GCC fuses (x − origin) / Δx into the following adds (FMA) in one and
// not always in the other (tests/mpm/simd/test_stencil_batch.cpp). G2P, P2G and the stencils P2G
// keeps for the implicit solve and mesh forces come from here; XPIC's and PolyPIC's extra passes
// and the diagnostics still use Stencil::compute. In 3D the rows' products are formed here too.
#pragma once
#include <algorithm>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "sim/mpm/simd/lanes.hpp"
#include "sim/mpm/simd/soa_transpose.hpp"
#include "sim/mpm/stencil.hpp"

namespace apiclab {

template <class T, int D, class K>
struct StencilBatch {
  // Particles per batch: 16 float, 4 double, the fastest measured with both the native and the
  // x86-64-v3 build (docs/performance.md).
  static constexpr int L = sizeof(T) == 4 ? 16 : 4;
  static constexpr int W = K::width;
  alignas(64) T w[D][W][L], dw[D][W][L], r[D][W][L];
  alignas(64) std::int64_t off[D][W][L];
  // 3D: the rows of Stencil::for_each_row (k outer, j inner), their products formed here across
  // the lanes instead of five scalar products and broadcasts a row per particle in P2G and G2P.
  // Plain arrays: GCC compiled the same tables as a member struct ([[no_unique_address]], empty
  // in 2D) into slower 3D float code.
  static constexpr int rows = D == 3 ? W * W : 0;
  alignas(64) T row_w[rows][L], row_dw1[rows][L], row_dw2[rows][L], row_wr1[rows][L],
      row_wr2[rows][L];
  alignas(64) std::int64_t row_off[rows][L];

  // Particles x[0..count) (count ≤ L); lanes past count repeat the last particle.
  void compute(const Vec<T, D>* x, int count, const GridGeometry<T, D>& g) {
    using One = Stencil<T, D, K>;
    // x's entries per axis. A whole float batch a register of particles at a time
    // (sim/mpm/simd/soa_transpose.hpp): copied lane by lane, they were 16 scalar copies and
    // compares an axis, and the vector loads of the axis loop below waited on those stores (a
    // failed store forward). Double keeps the copies: GCC floors its 4 lanes one by one from the
    // scalars, which forward, and the register loads were slower there.
    alignas(64) T xs[D][L];
    const bool by_registers = sizeof(T) == 4 && count == L;
    if constexpr (sizeof(T) == 4) {
      if (by_registers) {
        constexpr int P = std::min(L, simd_register_bytes / int(sizeof(T)));
        using V = typename SimdVector<T, P>::type;
        static_assert(sizeof(Vec<T, D>) == D * sizeof(T) && L % P == 0);
        const T* entries = reinterpret_cast<const T*>(x);  // Eigen's vectors are their scalars
        for (int l = 0; l < L; l += P) {
          V regs[D];
          load_entries<D>(entries + D * l, regs);
          for (int a = 0; a < D; ++a) store_register(&xs[a][l], regs[a]);
        }
      }
    }
    for (int a = 0; a < D; ++a) {
      T copies[L];
      const T* xa = xs[a];
      if (!by_registers) {
        for (int l = 0; l < L; ++l) copies[l] = x[l < count ? l : count - 1][a];
        xa = copies;
      }
      const T origin = g.origin[a], inv_dx = g.inv_dx, dx = g.dx;
      std::int32_t base[L];
      for (int l = 0; l < L; ++l) {
        T wl[W], dwl[W], rl[W];
        base[l] = One::axis(xa[l], origin, inv_dx, dx, wl, dwl, rl, TruncatingFloor{});
#pragma GCC unroll 4
        for (int k = 0; k < W; ++k) {
          w[a][k][l] = wl[k];
          dw[a][k][l] = dwl[k];
          r[a][k][l] = rl[k];
        }
      }
      // Off a periodic axis, One::offset without its branch, in 64 bits as the lanes need: one
      // multiply a lane, the stencil's next nodes a stride on, and where the stride fits 32 bits
      // (any grid below 2³¹ nodes a plane) a 32 × 32 → 64-bit multiply, one instruction on
      // x86-64-v3, which has no 64-bit vector multiply (GCC stands in six instructions a node).
      const std::int64_t lo = g.lo[a], stride = std::int64_t(g.stride[a]);
      if (stride <= std::numeric_limits<std::int32_t>::max()) {
        const std::int32_t lo32 = std::int32_t(lo), stride32 = std::int32_t(stride);
        for (int l = 0; l < L; ++l) {
          const std::int64_t first = std::int64_t(base[l] - lo32) * std::int64_t(stride32);
          for (int k = 0; k < W; ++k) off[a][k][l] = first + k * stride;
        }
      } else {
        for (int l = 0; l < L; ++l) {
          const std::int64_t first = (std::int64_t(base[l]) - lo) * stride;
          for (int k = 0; k < W; ++k) off[a][k][l] = first + k * stride;
        }
      }
      if (g.periodic[a])  // rare: the wrap's modulo stays scalar
        for (int l = 0; l < L; ++l)
          for (int k = 0; k < W; ++k) off[a][k][l] = std::int64_t(One::offset(base[l] + k, a, g));
    }
    if constexpr (D == 3)
      for (int k = 0; k < W; ++k)
        for (int j = 0; j < W; ++j) {
          const int row = k * W + j;
          for (int l = 0; l < L; ++l) {  // the products of Stencil::for_each_row, in its order
            row_w[row][l] = w[1][j][l] * w[2][k][l];
            row_dw1[row][l] = dw[1][j][l] * w[2][k][l];
            row_dw2[row][l] = w[1][j][l] * dw[2][k][l];
            row_wr1[row][l] = row_w[row][l] * r[1][j][l];
            row_wr2[row][l] = row_w[row][l] * r[2][k][l];
            row_off[row][l] = off[1][j][l] + off[2][k][l];
          }
        }
  }

  // A 3D row with Stencil::Row's fields, row.w (x_i − x_p) formed already.
  struct BatchRow {
    std::size_t off;
    T w;
    Vec<T, D> dw, w_r;
    T wr(int a) const { return w_r[a]; }
  };
  using Row = std::conditional_t<D == 3, BatchRow, typename Stencil<T, D, K>::Row>;
  // Particle l's rows, as its stencil's for_each_row gives them (get(l)'s copy), read from the
  // batch in place. P2G and G2P read the x-axis weights the same way, with no copy of the stencil:
  // copied, GCC loaded its 24 entries and 6 offsets into registers at the top of each particle
  // and spilled them (16 registers on x86-64-v3), about 45 instructions of P2G's 195 a particle;
  // read in place they are broadcasts from memory (x86-64-v3, 2D float P2G: 150 a particle).
  template <class Fn>
  __attribute__((always_inline)) void for_each_row(int l, Fn&& f) const {
    if constexpr (D == 2) {
      typename Stencil<T, D, K>::Row row;
      for (int j = 0; j < W; ++j) {
        row.off = std::size_t(off[1][j][l]);
        row.w = w[1][j][l];
        row.dw = Vec<T, 2>(row.w, dw[1][j][l]);
        row.r = Vec<T, 2>(T(0), r[1][j][l]);
        f(row);
      }
    } else {
      BatchRow row;
      for (int k = 0; k < rows; ++k) {
        row.off = std::size_t(row_off[k][l]);
        row.w = row_w[k][l];
        row.dw = Vec<T, 3>(row.w, row_dw1[k][l], row_dw2[k][l]);
        row.w_r = Vec<T, 3>(T(0), row_wr1[k][l], row_wr2[k][l]);
        f(row);
      }
    }
  }

  // Particle l's stencil, as Stencil::compute would have made it.
  void get(int l, Stencil<T, D, K>& st) const {
    for (int a = 0; a < D; ++a)
      for (int k = 0; k < W; ++k) {
        st.w[a][k] = w[a][k][l];
        st.dw[a][k] = dw[a][k][l];
        st.r[a][k] = r[a][k][l];
        st.off[a][k] = std::size_t(off[a][k][l]);
      }
  }
};

}  // namespace apiclab
