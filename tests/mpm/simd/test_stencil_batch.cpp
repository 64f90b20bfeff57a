// StencilBatch (sim/mpm/simd/stencil_batch.hpp) gives each particle the stencil Stencil::compute
// gives it, for every kernel, in 2D and 3D, float and double, on slip and periodic grids, for
// partial batches, and at positions on nodes and half-nodes, where a floor taken another way would
// move the stencil by a node. Node offsets must be equal. Weights, gradients and x_i − x_p may
// differ by what one rounding of x / Δx moves them: GCC fuses (x − origin) · (1/Δx) into the next
// add (FMA) in one path and not always in the other: G2P's batch in mpm_3d.cpp and a per-particle
// compute differed by one ulp of x/Δx on torus-drop's Δx = 0.4/70 (compiled in this test, the
// two agree exactly). On a grid with Δx = 1/32 that product is exact. The batch's rows (3D: row
// products formed across lanes) equal its own stencil's rows exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sim/mpm/grid.hpp"
#include "sim/mpm/simd/stencil_batch.hpp"
#include "tests/mpm/test_helpers.hpp"

namespace apiclab {
namespace {

constexpr double kMin[3] = {-0.5, 0.25, 0};

template <class T, int D>
Grid<T, D> batch_grid(bool periodic, double dx) {
  return test::unit_box_grid<T, D>(periodic, dx, {kMin[0], kMin[1], kMin[2]});
}

// Random positions in the domain, then positions exactly on nodes and on half-nodes (the
// quadratic kernel's base changes there) up to the domain's far edge.
template <class T, int D>
std::vector<Vec<T, D>> batch_positions(double dx) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec<T, D>> x;
  for (int p = 0; p < 200; ++p) {
    Vec<T, D> v;
    for (int a = 0; a < D; ++a) v[a] = T(kMin[a] + u(rng));
    x.push_back(v);
  }
  const int cells = int(std::lround(1 / dx));
  for (int k = 0; k < 2 * cells; ++k) {
    Vec<T, D> v;
    for (int a = 0; a < D; ++a) v[a] = T(kMin[a] + (k / 2 + (a == 1 ? 0.0 : 0.5 * (k % 2))) * dx);
    x.push_back(v);
  }
  return x;
}

template <class T, int D, class K>
void check_batch(bool periodic, double dx) {
  SCOPED_TRACE(::testing::Message()
               << "D = " << D << " sizeof(T) = " << sizeof(T) << " width " << K::width
               << (periodic ? " periodic" : " slip") << " dx = " << dx);
  const Grid<T, D> g = batch_grid<T, D>(periodic, dx);
  const std::vector<Vec<T, D>> x = batch_positions<T, D>(dx);
  using Batch = StencilBatch<T, D, K>;
  const T eps = std::numeric_limits<T>::epsilon();
  Batch batch;
  int checked = 0;
  // Batches of every count from 1 to L, one after another through the positions.
  for (std::size_t begin = 0, count = 1; begin < x.size();
       begin += count, count = count % Batch::L + 1) {
    const int n = int(std::min<std::size_t>(count, x.size() - begin));
    batch.compute(&x[begin], n, g);
    for (int l = 0; l < n; ++l) {
      const Vec<T, D>& xp = x[begin + std::size_t(l)];
      Stencil<T, D, K> one, got;
      one.compute(xp, g);
      batch.get(l, got);
      for (int a = 0; a < D; ++a) {
        // One rounding of x / Δx (|x / Δx| < 40 here), carried into f, then into w = O(f²) with
        // |dw/df| ≤ 2, dw = O(f) with slope ≤ 3 (cubic), r = Δx (base + k − x/Δx).
        const T df = 2 * eps * T(40);
        for (int k = 0; k < K::width; ++k) {
          ASSERT_EQ(got.off[a][k], one.off[a][k]) << "particle at " << xp.transpose();
          EXPECT_NEAR(got.w[a][k], one.w[a][k], 2 * df + 2 * eps) << xp.transpose();
          EXPECT_NEAR(got.dw[a][k] * g.dx, one.dw[a][k] * g.dx, 3 * df + 4 * eps) << xp.transpose();
          EXPECT_NEAR(got.r[a][k] / g.dx, one.r[a][k] / g.dx, df + 4 * eps) << xp.transpose();
        }
      }
      // The rows P2G and G2P read from the batch are those of the batch's own stencil (`got`),
      // bit for bit: the same products in the same order (what keeps their results unchanged).
      std::vector<typename Stencil<T, D, K>::Row> expected;
      got.for_each_row([&](const auto& row) { expected.push_back(row); });
      std::size_t r = 0;
      batch.for_each_row(l, [&](const auto& row) {
        ASSERT_LT(r, expected.size());
        const auto& e = expected[r++];
        EXPECT_EQ(row.off, e.off);
        EXPECT_EQ(row.w, e.w);
        for (int a = 0; a < D; ++a) {
          EXPECT_EQ(row.dw[a], e.dw[a]) << "row " << r - 1 << " axis " << a;
          EXPECT_EQ(row.wr(a), e.wr(a)) << "row " << r - 1 << " axis " << a;
        }
      });
      EXPECT_EQ(r, expected.size());
      ++checked;
    }
  }
  EXPECT_EQ(checked, int(x.size()));
}

template <class T, int D>
void check_all_kernels() {
  for (double dx : {1.0 / 32, 0.4 / 70})
    for (bool periodic : {false, true}) {
      check_batch<T, D, LinearKernel>(periodic, dx);
      check_batch<T, D, QuadraticKernel>(periodic, dx);
      check_batch<T, D, CubicKernel>(periodic, dx);
    }
}

// Node offsets on a grid whose plane stride does not fit 32 bits (a region of more than 2³¹
// nodes a plane: no allocation here, the geometry alone), and on one whose stride is the largest
// that does: the batch multiplies in 32 × 32 → 64 bits only for the second.
template <class T, int D>
void offsets_beyond_32_bit_strides() {
  const Grid<T, D> g = batch_grid<T, D>(false, 1.0 / 32);
  const std::vector<Vec<T, D>> x = batch_positions<T, D>(1.0 / 32);
  for (std::size_t stride :
       {std::size_t(std::numeric_limits<std::int32_t>::max()), std::size_t(3) << 31}) {
    SCOPED_TRACE(::testing::Message() << D << "D, stride " << stride);
    GridGeometry<T, D> wide = g;
    wide.stride[D - 1] = stride;
    StencilBatch<T, D, QuadraticKernel> batch;
    for (std::size_t begin = 0; begin + batch.L <= x.size(); begin += batch.L) {
      batch.compute(&x[begin], batch.L, wide);
      for (int l = 0; l < batch.L; ++l) {
        Stencil<T, D, QuadraticKernel> one, got;
        one.compute(x[begin + std::size_t(l)], wide);
        batch.get(l, got);
        for (int a = 0; a < D; ++a)
          for (int k = 0; k < QuadraticKernel::width; ++k)
            ASSERT_EQ(got.off[a][k], one.off[a][k]) << "axis " << a << " node " << k;
      }
    }
  }
}

TEST(StencilBatch, OffsetsBeyond32BitStrides) {
  offsets_beyond_32_bit_strides<float, 2>();
  offsets_beyond_32_bit_strides<double, 2>();
  offsets_beyond_32_bit_strides<float, 3>();
  offsets_beyond_32_bit_strides<double, 3>();
}

TEST(StencilBatch, MatchesStencilCompute2DFloat) { check_all_kernels<float, 2>(); }
TEST(StencilBatch, MatchesStencilCompute2DDouble) { check_all_kernels<double, 2>(); }
TEST(StencilBatch, MatchesStencilCompute3DFloat) { check_all_kernels<float, 3>(); }
TEST(StencilBatch, MatchesStencilCompute3DDouble) { check_all_kernels<double, 3>(); }

}  // namespace
}  // namespace apiclab
