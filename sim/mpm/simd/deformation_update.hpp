// F ← (I + Δt ∇u) F (eq 40) for one particle in 3D, a column at a time from ∇u's columns held as
// lanes, as G2P's gather leaves them: column b of the result is F_b + Σ_k g_k F_kb with
// g_k = Δt (∇u)_k, the scalar loop's sums in its order (bit-identical results). Written in
// lanes because the compiler's version transposed the gathered columns into a 3×3 matrix and
// back: about 20 shuffles a particle in 3D float, a fifth of G2P's epilogue (perf annotate).
#pragma once
#include <cstring>

#include "sim/mpm/simd/lanes.hpp"

namespace apiclab {

// F: 9 scalars, column-major (Eigen's Matrix3); g: the columns of Δt ∇u in lanes 0..2. The
// register width is a parameter so that tests check both forms on any machine.
template <class T, int register_bytes>
inline void update_deformation_3d(T* F, const Lanes<T, 3, register_bytes> g[3]) {
  using L = Lanes<T, 3, register_bytes>;
  if constexpr (L::parts != 1 || L::per_part != 4) {
    // Registers narrower than four lanes (an SSE-only build: the fuzzers', double in two
    // parts): the scalar loop.
    T f[9];
    std::memcpy(f, F, sizeof f);
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        T s = f[3 * b + a];
        for (int k = 0; k < 3; ++k) s += g[k][a] * f[3 * b + k];
        F[3 * b + a] = s;
      }
  } else {
    using V = typename L::Part;
    // The columns as four-lane loads inside the 9 scalars: columns 0 and 1 carry the next
    // column's first entry in lane 3 (unused); column 2 is loaded from F + 5 and moved down a lane.
    const V c0 = load_register<V>(F), c1 = load_register<V>(F + 3),
            c2_at5 = load_register<V>(F + 5);
    const V c2 = shuffle_lanes<1, 2, 3, 3>(c2_at5, c2_at5);
    T f[9];
    std::memcpy(f, F, sizeof f);
    const V g0 = g[0].part[0], g1 = g[1].part[0], g2 = g[2].part[0];
    const V out0 = ((c0 + g0 * f[0]) + g1 * f[1]) + g2 * f[2];
    const V out1 = ((c1 + g0 * f[3]) + g1 * f[4]) + g2 * f[5];
    const V out2 = ((c2 + g0 * f[6]) + g1 * f[7]) + g2 * f[8];
    // Stores in order, each over the last one's unused lane: F_0 (+ junk in F(0,1)), F_1 (+ junk
    // in F(0,2)), then (F(2,1), F_2) at F + 5.
    const V tail = shuffle_lanes<2, 4, 5, 6>(out1, out2);
    store_register(F, out0);
    store_register(F + 3, out1);
    store_register(F + 5, tail);
  }
}

}  // namespace apiclab
