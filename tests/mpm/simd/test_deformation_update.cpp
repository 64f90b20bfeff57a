// G2P's lane-form deformation update (sim/mpm/simd/deformation_update.hpp, eq 40): every entry is
// the scalar loop's sum F_ab + Σ_k g_ak F_kb in its order, and the overlapping column stores stay
// inside the particle's nine scalars.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "sim/mpm/simd/deformation_update.hpp"

namespace apiclab {
namespace {

template <class T, int bytes>
void check_update() {
  SCOPED_TRACE(std::string(sizeof(T) == 8 ? "double" : "float") + " in " + std::to_string(bytes) +
               "-byte registers");
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-2, 2);
  const T eps = std::numeric_limits<T>::epsilon();
  for (int trial = 0; trial < 200; ++trial) {
    std::array<T, 27> F;  // three particles' F; the middle one is updated
    for (T& f : F) f = T(u(rng));
    const std::array<T, 27> before = F;
    T g[3][3];  // g[k][a] = (Δt ∇u)(a, k)
    Lanes<T, 3, bytes> columns[3];
    for (int k = 0; k < 3; ++k) {
      for (int a = 0; a < 3; ++a) g[k][a] = T(0.1 * u(rng));
      columns[k] = Lanes<T, 3, bytes>::of(g[k][0], g[k][1], g[k][2]);
    }
    update_deformation_3d(F.data() + 9, columns);
    for (int i = 0; i < 9; ++i) {
      EXPECT_EQ(F[std::size_t(i)], before[std::size_t(i)]) << "the particle before, entry " << i;
      EXPECT_EQ(F[std::size_t(18 + i)], before[std::size_t(18 + i)]) << "the particle after";
    }
    const T* F0 = before.data() + 9;
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        // The scalar loop's order, each product added with one rounding where the target fuses
        // multiply-add (G2P's loop was contracted to FMAs), else two.
        T fused = F0[3 * b + a], bound = std::abs(fused);
        for (int k = 0; k < 3; ++k) {
          fused = std::fma(g[k][a], F0[3 * b + k], fused);
          bound += std::abs(g[k][a] * F0[3 * b + k]);
        }
        const T got = F[std::size_t(9 + 3 * b + a)];
        // The lane form's sums, contracted to FMAs, give the fused chain's bits; the scalar loop
        // (four lanes not in one register) is contracted as the compiler chooses, so within
        // round-off.
#if defined(__FMA__)
        constexpr bool lane_form = Lanes<T, 3, bytes>::parts == 1;
        if (lane_form)
          EXPECT_EQ(got, fused) << "F(" << a << ", " << b << ")";
        else
          EXPECT_NEAR(got, fused, 6 * eps * bound) << "F(" << a << ", " << b << ")";
#else
        EXPECT_NEAR(got, fused, 6 * eps * bound) << "F(" << a << ", " << b << ")";
#endif
      }
  }
}

TEST(DeformationUpdate, LanesGiveTheScalarLoopsSumsAndStayInsideTheParticle) {
  // 32 bytes: the lane form in float and double; 16 (SSE): the lane form in float, the scalar
  // loop in double.
  check_update<float, 32>();
  check_update<double, 32>();
  check_update<float, 16>();
  check_update<double, 16>();
}

}  // namespace
}  // namespace apiclab
