// 2D float G2P's paired gather (sim/gather_paired.hpp), used where the target has 16 vector
// registers (x86-64-v3) and compiled here on any: from nodes holding their 4 lanes twice, its
// sums must be those of the plain gather — Σ w ṽ|vⁿ, the ∇w columns and the w (x_i − x_p)
// columns — to float round-off over 9 terms, for every particle of a batch.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "sim/gather_paired.hpp"
#include "sim/grid.hpp"
#include "sim/stencil_batch.hpp"
#include "test_helpers.hpp"

namespace apiclab {
namespace {

TEST(GatherPaired, SumsOfThePlainGather) {
  using K = QuadraticKernel;
  using Batch = StencilBatch<float, 2, K>;
  using Sums = Lanes<float, 4>;
  const Grid<float, 2> g = test::unit_box_grid<float, 2>(false, 1.0 / 32);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1), pos(0.1, 0.9);
  std::vector<Lanes<float, 5>> nodes(g.region_size());
  std::vector<std::array<float, 4>> lanes(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    for (float& l : lanes[i]) l = float(u(rng));
    const auto& l = lanes[i];
    nodes[i] = Lanes<float, 5>::of(l[0], l[1], l[2], l[3], l[0], l[1], l[2], l[3]);
  }
  std::vector<Vec<float, 2>> x(Batch::L);
  for (auto& p : x) p = Vec<float, 2>(float(pos(rng)), float(pos(rng)));
  Batch batch;
  batch.compute(x.data(), Batch::L, g);
  for (int l = 0; l < Batch::L; ++l) {
    Stencil<float, 2, K> st;
    batch.get(l, st);
    float wr[K::width];
    for (int i = 0; i < K::width; ++i) wr[i] = st.w[0][i] * st.r[0][i];
    Sums vsum{}, grad[2] = {}, b[2] = {};
    gather_2d_paired(batch, l, wr, nodes.data(), vsum, grad, b);
    // The plain gather in double: node (i, j) has w = wx_i wy_j, ∇w = (dwx_i wy_j, wx_i dwy_j),
    // x_i − x_p = (rx_i, ry_j).
    double e_sum[4] = {}, e_grad[2][4] = {}, e_b[2][4] = {};
    for (int j = 0; j < K::width; ++j)
      for (int i = 0; i < K::width; ++i) {
        const auto& n = lanes[st.off[0][i] + st.off[1][j]];
        const double w = double(st.w[0][i]) * st.w[1][j];
        for (int c = 0; c < 4; ++c) {
          e_sum[c] += w * n[c];
          e_grad[0][c] += double(st.dw[0][i]) * st.w[1][j] * n[c];
          e_grad[1][c] += double(st.w[0][i]) * st.dw[1][j] * n[c];
          e_b[0][c] += w * st.r[0][i] * n[c];
          e_b[1][c] += w * st.r[1][j] * n[c];
        }
      }
    // Bound: 9 terms of |w n| ≤ 1 (|∇w| ≤ 2/Δx = 64), each product and add rounded in float.
    const double tol = 32 * 6e-8, tol_grad = 64 * tol;
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(vsum.part[0][c], e_sum[c], tol) << "particle " << l << " lane " << c;
      for (int a = 0; a < 2; ++a) {
        EXPECT_NEAR(grad[a].part[0][c], e_grad[a][c], tol_grad) << l << " grad " << a << c;
        EXPECT_NEAR(b[a].part[0][c], e_b[a][c], tol / 32) << l << " B " << a << c;
      }
    }
  }
}

}  // namespace
}  // namespace apiclab
