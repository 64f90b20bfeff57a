// XPIC(m), the extended PIC update of Hammerquist and Nairn 2017 (CMAME 318, Sec 3): the grid
// passes between the grid update and G2P.
//
// With S⁺ the mass-weighted P2G (eqs 24-26 without the affine term) and S the G2P interpolation,
// the paper's update is V^{n+1} = S ṽ − S vⁿ + S v* with
//   v* = Σ_{r=1}^{m} (−1)^{r+1} C(m, r) A^{r−1} vⁿ,   A = S⁺ S (grid → particles → grid),
// so that S v* = (I − (I − S S⁺)^m) Vⁿ: m = 1 is PIC, and m → ∞ keeps every particle velocity
// mode the grid sees (FLIP without its null-space modes). As polynomials in A,
// Σ_r (−1)^{r+1} C(m, r) A^{r−1} = Σ_{k=0}^{m−1} (I − A)^k, and the second form is what is summed
// here: its terms never grow (0 ≤ A ≤ I in the mass inner product), where the binomial
// coefficients of the first cancel catastrophically past m ≈ 30 in double.
//
// This file leaves e = v* − vⁿ = Σ_{k=1}^{m−1} (I − A)^k vⁿ per node in xpic_shift_; G2P adds
// Σ w e_i to v^PIC (sim/mpm/schemes/particle_update.hpp). Each of the m − 1 passes is one particle
// loop (gather u_p = Σ w u_i, scatter m_p w u_p, coloured as P2G) and one node loop; no allocation
// after the first step.
#pragma once
#include "sim/mpm/mpm.hpp"

namespace apiclab {

template <class T, int D>
template <class K>
void MpmSimulation<T, D>::xpic_grid_passes() {
  const int m = scene_.solver.xpic_order;
  if (m <= 1) return;  // XPIC(1) = PIC: e = 0, and G2P skips the gather
  if (xpic_term_.size() != grid_.size()) {
    xpic_term_.assign(grid_.size(), Vec<T, D>::Zero());
    xpic_shift_.assign(grid_.size(), Vec<T, D>::Zero());
  }
  // Only the active box is written; a stencil reaches no other node (sim/mpm/block_partition.hpp).
  for_each_box_node([&](std::size_t i) {
    xpic_term_[i] = grid_.velocity[i];  // (I − A)⁰ vⁿ
    xpic_shift_[i].setZero();
  });
  using Lanes = typename Grid<T, D>::NodeLanes;
  constexpr int W = K::width;
  auto* acc = grid_.node_lanes.data();  // free between P2G and G2P's pack_velocities
  const Vec<T, D>* term = xpic_term_.data();
  for (int k = 1; k < m; ++k) {
    for_each_box_node([&](std::size_t i) { acc[i] = Lanes{}; });
    // (S⁺ S u)_i m_i = Σ_p w_ip m_p Σ_j w_jp u_j, rows along axis 0 as in P2G and G2P.
    blocks_.for_each_block_coloured(
        [&](std::uint32_t begin, std::uint32_t end) {
          for (std::uint32_t q = begin; q < end; ++q) {
            Stencil<T, D, K> st;
            st.compute(p_.x[q], grid_);
            const T* wx = st.w[0];
            Vec<T, D> up = Vec<T, D>::Zero();
            st.for_each_row([&](const typename Stencil<T, D, K>::Row& row) {
              Vec<T, D> s = Vec<T, D>::Zero();
              for (int i = 0; i < W; ++i) s += wx[i] * term[st.off[0][i] + row.off];
              up += row.w * s;
            });
            const Vec<T, D> mu = p_.mass[q] * up;
            Lanes lanes;
            if constexpr (D == 2)
              lanes = Lanes::of(T(0), mu[0], mu[1]);
            else
              lanes = Lanes::of(T(0), mu[0], mu[1], mu[2]);
            st.for_each_row([&](const typename Stencil<T, D, K>::Row& row) {
              for (int i = 0; i < W; ++i) acc[st.off[0][i] + row.off] += (row.w * wx[i]) * lanes;
            });
          }
        },
        parallel_worthwhile());
    // u ← (I − A) u, e += u. A node without mass has u = 0 from vⁿ = 0 on.
    for_each_box_node([&](std::size_t i) {
      const T mi = grid_.mass[i];
      if (mi > T(0)) {
        Vec<T, D> Au;
        for (int a = 0; a < D; ++a) Au[a] = acc[i][1 + a] / mi;
        xpic_term_[i] -= Au;
        xpic_shift_[i] += xpic_term_[i];
      }
    });
  }
}

}  // namespace apiclab
