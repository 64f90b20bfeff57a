// 2D float G2P's gather (sim/g2p.hpp) with two 4-lane sums in each 256-bit register. A node's
// lanes [ṽ (2), vⁿ (2)] fill half a register, so the generic gather kept nine weights, three
// per-node sums and five per-particle sums in 4-lane registers: more than x86-64-v3's sixteen,
// and GCC spilled them to the stack at every node (with AVX-512VL's 32 registers it does not).
// Here the node, stored twice, is read as one register and multiplied once by [w_i | w_i r_i],
// the pairs (Σ w ṽ | Σ w r ṽ) and (∇w columns | B columns) share registers, and the sums are the
// same products added in the same order as the generic gather's (docs/performance.md).
#pragma once
#include <type_traits>

#include "lanes.hpp"

namespace apiclab {

// Whether 2D float gathers paired on this target: 256-bit registers, and 16 of them (with
// AVX-512VL's 32 the generic gather fits, and is the faster one).
inline constexpr bool paired_2d_float_gather =
    simd_register_bytes == 32 && simd_register_count == 16;

// Whether the paired gather applies to a gather into sums of type L: four float lanes in one
// register, and no Σ w (ṽ × vⁿ) (λ = 0).
template <class L>
constexpr bool paired_halves(bool moving_nodes) {
  return paired_2d_float_gather && std::is_same_v<typename L::Part, SimdVector<float, 4>::type> &&
         L::parts == 1 && !moving_nodes;
}

// The gather of g2p_impl's generic row body for particle `lane` of `batch` (stencil st, w r
// along x in wr), nodes read from `packed`: vsum = Σ w ṽ|vⁿ, grad_cols[c] = Σ ∂_c w ṽ|vⁿ,
// b_cols[c] = Σ w r_c ṽ|vⁿ. Each node's 8 floats must hold its 4 lanes twice
// (MpmSimulation::pack_velocities).
template <class Batch, class Node, class L, int W>
__attribute__((always_inline)) inline void gather_2d_paired(const Batch& batch, int lane,
                                                            const float (&wr)[W],
                                                            const Node* packed, L& vsum,
                                                            L (&grad_cols)[2], L (&b_cols)[2]) {
  using V4 = SimdVector<float, 4>::type;
  using V8 = SimdVector<float, 8>::type;
  auto pair = [](float low, float high) {
    return join_halves<V8>(splat<V4>(low), splat<V4>(high));
  };
  V8 w_wr[W];  // [w_i | w_i r_i] along x
  V4 dw[W];
  for (int i = 0; i < W; ++i) {
    w_wr[i] = pair(batch.w[0][i][lane], wr[i]);
    dw[i] = splat<V4>(batch.dw[0][i][lane]);
  }
  const Node* packed_x[W];  // each x-node's address once a particle (see sim/p2g.hpp)
  for (int i = 0; i < W; ++i) packed_x[i] = packed + batch.off[0][i][lane];
  V8 sum_b0{}, grad1_b1{};  // (Σ w ṽ | B column 0), (∇ column 1 | B column 1)
  V4 grad0{};
  batch.for_each_row(
      lane, [&](const typename Batch::Row& row) __attribute__((always_inline)) {
        V8 s{};  // (Σ_x w ṽ | Σ_x w r ṽ) of the row
        V4 g{};
        for (int i = 0; i < W; ++i) {
          // The node's lanes twice (pack_velocities): one load, no shuffle.
          const V8 node = load_register<V8>(reinterpret_cast<const float*>(&packed_x[i][row.off]));
          s += w_wr[i] * node;
          g += dw[i] * half_of<0, V4>(node);
        }
        sum_b0 += row.w * s;
        grad0 += row.w * g;
        const V4 s0 = half_of<0, V4>(s);
        grad1_b1 += pair(row.dw[1], row.wr(1)) * join_halves<V8>(s0, s0);
      });
  vsum.part[0] = half_of<0, V4>(sum_b0);
  b_cols[0].part[0] = half_of<1, V4>(sum_b0);
  grad_cols[0].part[0] = grad0;
  grad_cols[1].part[0] = half_of<0, V4>(grad1_b1);
  b_cols[1].part[0] = half_of<1, V4>(grad1_b1);
}

}  // namespace apiclab
