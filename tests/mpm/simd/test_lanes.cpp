// Node lane groups (sim/mpm/simd/lanes.hpp) in every layout the targets use: one register of 8
// lanes (AVX-512 double, AVX2 float), two or more register-sized parts (AVX2 double, SSE). P2G and
// G2P address lanes by index, so each layout must keep lane i at index i through every operation.
#include <gtest/gtest.h>

#include "sim/mpm/simd/lanes.hpp"

namespace apiclab {
namespace {

template <class T, int used, int bytes>
void check_layout() {
  using L = Lanes<T, used, bytes>;
  SCOPED_TRACE(std::string(sizeof(T) == 8 ? "double" : "float") + ", " + std::to_string(used) +
               " lanes in " + std::to_string(bytes) + "-byte registers");
  static_assert(sizeof(typename L::Part) <= std::size_t(bytes));
  static_assert(L::count >= used && L::count - used < L::per_part);
  const L a = L::of(1, 2, 3, 4, 5);
  for (int i = 0; i < L::count; ++i) EXPECT_EQ(a[i], i < 5 ? T(i + 1) : T(0)) << "lane " << i;
  const L b = L::of(10, 20, 30, 40, 50, 60);
  const L sum = a + b, diff = b - a, prod = a * b, scaled = T(2) * a;
  L acc = a;
  acc += b;
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(sum[i], a[i] + b[i]) << "lane " << i;
    EXPECT_EQ(acc[i], a[i] + b[i]) << "lane " << i;
    EXPECT_EQ(diff[i], b[i] - a[i]) << "lane " << i;
    EXPECT_EQ(prod[i], a[i] * b[i]) << "lane " << i;
    EXPECT_EQ(scaled[i], 2 * a[i]) << "lane " << i;
  }
  // The shuffles of G2P's ṽ × vⁿ: lanes from anywhere in the group to the front.
  const L f = b.template front3<4, 1, 5>();
  EXPECT_EQ(f[0], T(50));
  EXPECT_EQ(f[1], T(20));
  EXPECT_EQ(f[2], T(60));
  // G2P reads the first 4 lanes (2D) or 6 (3D) of a node's group.
  using Front = Lanes<T, 4, bytes>;
  const Front p = Front::prefix_of(b);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(p[i], b[i]) << "lane " << i;
}

TEST(Lanes, EveryLayoutKeepsLaneOrder) {
  for (auto check :
       {check_layout<double, 7, 64>, check_layout<double, 7, 32>, check_layout<double, 7, 16>,
        check_layout<float, 7, 64>, check_layout<float, 7, 32>, check_layout<float, 7, 16>,
        check_layout<double, 6, 32>, check_layout<float, 6, 16>})
    check();
}

// shuffle_lanes: indices below P take a's lanes, from P on b's, in both compilers' builtins.
TEST(Lanes, ShufflePicksFromBothRegisters) {
  using F4 = SimdVector<float, 4>::type;
  using D4 = SimdVector<double, 4>::type;
  const F4 fa{1, 2, 3, 4}, fb{5, 6, 7, 8};
  const F4 f = shuffle_lanes<2, 4, 5, 6>(fa, fb);
  const D4 da{1, 2, 3, 4}, db{5, 6, 7, 8};
  const D4 d = shuffle_lanes<1, 2, 4, 7>(da, db);
  const D4 one = shuffle_lanes<3, 1, 2, 2>(da, da);  // from one register
  const float f_want[4] = {3, 5, 6, 7};
  const double d_want[4] = {2, 3, 5, 8}, one_want[4] = {4, 2, 3, 3};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(f[i], f_want[i]) << "lane " << i;
    EXPECT_EQ(d[i], d_want[i]) << "lane " << i;
    EXPECT_EQ(one[i], one_want[i]) << "lane " << i;
  }
  // front3 of a one-register, four-lane group (the layouts above have eight or several parts).
  const Lanes<float, 4, 16> g = Lanes<float, 4, 16>::of(10, 20, 30, 40);
  const Lanes<float, 4, 16> front = g.front3<3, 0, 2>();
  EXPECT_EQ(front[0], 40.f);
  EXPECT_EQ(front[1], 10.f);
  EXPECT_EQ(front[2], 30.f);
}

// The parts fit the build's registers: double on an AVX2 build is two 4-lane parts, not one
// 8-lane vector that the compiler would split through the stack.
TEST(Lanes, PartsFitTheTargetRegisters) {
  EXPECT_LE(sizeof(Lanes<double, 5>::Part), std::size_t(simd_register_bytes));
  EXPECT_LE(sizeof(Lanes<float, 7>::Part), std::size_t(simd_register_bytes));
}

}  // namespace
}  // namespace apiclab
