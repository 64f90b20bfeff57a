// The entries of consecutive vectors and matrices as one register per entry
// (sim/mpm/simd/soa_transpose.hpp), in every register shape the stress pass and the diagnostics
// row's sums use (4 or 8 floats, 2 or 4 doubles, whatever the target's registers), for 2- and
// 3-vectors and 2×2 and 3×3 matrices: each path (pairs split, transposes within 128-bit halves,
// lane by lane) must put item l's entry e in lane l of register e, and store_entries must put it
// back.
#include <gtest/gtest.h>

#include <string>

#include "sim/mpm/simd/soa_transpose.hpp"

namespace apiclab {
namespace {

template <class T, int lanes, int n>
void entries_round_trip() {
  using V = typename SimdVector<T, lanes>::type;
  SCOPED_TRACE(std::string(sizeof(T) == 8 ? "double" : "float") + ", " + std::to_string(lanes) +
               " lanes, " + std::to_string(n) + " entries");
  T items[lanes * n + 1];  // one more: a load must not take it
  for (int s = 0; s < lanes * n + 1; ++s) items[s] = T(100 + s);
  V regs[n];
  load_entries<n>(items, regs);
  for (int e = 0; e < n; ++e)
    for (int l = 0; l < lanes; ++l) EXPECT_EQ(regs[e][l], items[n * l + e]) << e << ", lane " << l;
  T back[lanes * n + 1] = {};
  store_entries<n>(regs, back);
  for (int s = 0; s < lanes * n; ++s) EXPECT_EQ(back[s], items[s]) << "scalar " << s;
  EXPECT_EQ(back[lanes * n], T(0));  // nothing stored past the items
}

template <class T, int lanes>
void every_shape() {
  entries_round_trip<T, lanes, 2>();
  entries_round_trip<T, lanes, 3>();
  entries_round_trip<T, lanes, 4>();
  entries_round_trip<T, lanes, 9>();
}

TEST(SoaTranspose, EveryEntryInItsLaneAndBack) {
  every_shape<float, 4>();
  every_shape<float, 8>();
  every_shape<double, 2>();
  every_shape<double, 4>();
}

}  // namespace
}  // namespace apiclab
