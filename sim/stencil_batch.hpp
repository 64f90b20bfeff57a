// The stencils of a few consecutive particles at once, the particles across SIMD lanes
// (issue 12): one particle's Stencil::compute is a floor, three int/float conversions and a
// dozen dependent products per axis, about a fifth of G2P in 2D float when done per particle.
// Same operations per lane as Stencil::compute; the results agree to the rounding of x / Δx,
// not bit for bit, because GCC fuses (x − origin) / Δx into the following adds (FMA) in one and
// not always in the other (tests/test_stencil_batch.cpp). G2P, P2G and the stencils P2G keeps
// for the implicit solve and mesh forces come from here; XPIC's and PolyPIC's extra passes and
// the diagnostics still use Stencil::compute.
#pragma once
#include <cstdint>

#include "stencil.hpp"

namespace apiclab {

template <class T, int D, class K>
struct StencilBatch {
  // Particles per batch, the fastest measured on an Intel Xeon (AVX-512) with both the native and
  // the x86-64-v3 build: 16 float (2D float 26.1 / 24.4 M particle-steps/s against 24.2 / 23.4
  // with 8), 4 double (16.7 / 16.4 M against 16.2 / 16.6 with 8 and 15.9 / 15.9 with 16).
  static constexpr int L = sizeof(T) == 4 ? 16 : 4;
  static constexpr int W = K::width;
  alignas(64) T w[D][W][L], dw[D][W][L], r[D][W][L];
  alignas(64) std::int64_t off[D][W][L];

  // Particles x[0..count) (count ≤ L); lanes past count repeat the last particle.
  void compute(const Vec<T, D>* x, int count, const GridGeometry<T, D>& g) {
    using One = Stencil<T, D, K>;
    for (int a = 0; a < D; ++a) {
      T xa[L];
      for (int l = 0; l < L; ++l) xa[l] = x[l < count ? l : count - 1][a];
      const T origin = g.origin[a], inv_dx = g.inv_dx, dx = g.dx;
      // Off a periodic axis, One::offset without its branch, in 64 bits as the lanes need.
      const std::int64_t lo = g.lo[a], stride = std::int64_t(g.stride[a]);
      std::int32_t base[L];
      for (int l = 0; l < L; ++l) {
        T wl[W], dwl[W], rl[W];
        const int b = One::axis(xa[l], origin, inv_dx, dx, wl, dwl, rl, TruncatingFloor{});
        base[l] = b;
#pragma GCC unroll 4
        for (int k = 0; k < W; ++k) {
          w[a][k][l] = wl[k];
          dw[a][k][l] = dwl[k];
          r[a][k][l] = rl[k];
          off[a][k][l] = (std::int64_t(b + k) - lo) * stride;
        }
      }
      if (g.periodic[a])  // rare: the wrap's modulo stays scalar
        for (int l = 0; l < L; ++l)
          for (int k = 0; k < W; ++k) off[a][k][l] = std::int64_t(One::offset(base[l] + k, a, g));
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
