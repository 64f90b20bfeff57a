// The Sec 6.8 round-trip transfer error (Fig 11): G2P then P2G with Δt = 0 on a periodic
// [0, 2π]² grid with velocity (1.1 sin x, 0.9 cos y), Poisson disk particles (separation Δx/3).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "sim/roundtrip.hpp"

namespace apiclab {
namespace {

// Least-squares slope of log(error) against log(Δx).
double fitted_slope(const std::vector<RoundTripResult>& rs) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = double(rs.size());
  for (const auto& r : rs) {
    double x = std::log(r.dx), y = std::log(r.l2_error);
    sx += x; sy += y; sxx += x * x; sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

std::vector<RoundTripResult> sweep(Scheme scheme) {
  std::vector<RoundTripResult> rs;
  for (int n : {16, 32, 64, 128}) rs.push_back(roundtrip_error(KernelType::quadratic, scheme, n));
  return rs;
}

TEST(RoundTrip, ConvergesAndApicBeatsPic) {
  const auto pic = sweep(Scheme::pic), apic = sweep(Scheme::apic);
  const double spic = fitted_slope(pic), sapic = fitted_slope(apic);
  double min_ratio = 1e300;
  for (std::size_t k = 0; k < pic.size(); ++k) {
    const double ratio = pic[k].l2_error / apic[k].l2_error;
    min_ratio = std::min(min_ratio, ratio);
    std::printf("[ round trip ] n = %3d  particles %6zu  PIC %.4e  APIC %.4e  PIC/APIC %.2f\n", pic[k].resolution,
                pic[k].particles, pic[k].l2_error, apic[k].l2_error, ratio);
    EXPECT_GT(apic[k].l2_error, 0.0);
    // The paper reports about one order of magnitude; require at least 3×.
    EXPECT_GT(ratio, 3.0) << "at resolution " << pic[k].resolution;
  }
  std::printf("[ round trip ] fitted slopes: PIC %.3f  APIC %.3f  (min PIC/APIC ratio %.2f)\n", spic, sapic, min_ratio);
  ::testing::Test::RecordProperty("slope_pic", std::to_string(spic));
  ::testing::Test::RecordProperty("slope_apic", std::to_string(sapic));
  ::testing::Test::RecordProperty("min_ratio", std::to_string(min_ratio));
  // Measured (seed 1, resolutions 16..512): PIC errors 2.47e-1, 6.67e-2, 2.09e-2, 8.15e-3,
  // 3.72e-3, 1.82e-3 (local slopes 1.89, 1.67, 1.36, 1.13, 1.04); APIC 6.82e-3, 1.49e-3,
  // 3.84e-4, 9.46e-5, 2.38e-5, 5.94e-6 (slopes 2.19, 1.96, 2.02, 1.99, 2.00).
  // PIC: v_p = Σ w v_i smooths by O(Δx²) (this dominates at coarse grids) and the return
  // P2G averages v(x_p) about the weighted particle centroid, which misses x_i by O(Δx) for
  // irregular (Poisson disk) particles: asymptotically first order, so the fitted slope over
  // 16..128 is ≈ 1.64 and the local slope falls towards 1. APIC reproduces affine fields
  // exactly (Sec 5.5), so its error is O(Δx²) — second order, not the first order Fig 11
  // states; the PIC/APIC ratio then grows with resolution (36× to 86× here).
  for (std::size_t k = 2; k < pic.size(); ++k) {
    const double prev = std::log(pic[k - 2].l2_error / pic[k - 1].l2_error) / std::log(2.0);
    const double last = std::log(pic[k - 1].l2_error / pic[k].l2_error) / std::log(2.0);
    EXPECT_LT(last, prev) << "PIC local slope should fall towards 1 (pre-asymptotic O(Δx²) part fading)";
  }
  const double pic_last = std::log(pic[2].l2_error / pic[3].l2_error) / std::log(2.0);
  EXPECT_GE(pic_last, 0.8);  // first order once the O(Δx) term dominates (1.36 at 64→128)
  EXPECT_LE(pic_last, 1.5);
  EXPECT_GE(spic, 0.8);      // fitted over 16..128 (measured 1.64): between first and second
  EXPECT_LE(spic, 2.0);
  EXPECT_GE(sapic, 1.8);     // second order (measured 2.05)
  EXPECT_LE(sapic, 2.2);
}

TEST(RoundTrip, RpicEqualsPicForCurlFreeField) {
  for (KernelType k : {KernelType::quadratic, KernelType::cubic}) {
    const auto pic = roundtrip_error(k, Scheme::pic, 32);
    const auto rpic = roundtrip_error(k, Scheme::rpic, 32);
    const auto apic = roundtrip_error(k, Scheme::apic, 32);
    // skew(B) is round-off (~1e-17 per particle): 1e-10 relative.
    EXPECT_NEAR(rpic.l2_error, pic.l2_error, 1e-10 * pic.l2_error);
    EXPECT_LT(apic.l2_error, pic.l2_error / 3);
  }
}

TEST(RoundTrip, SameSeedSameAnswer) {
  const auto a = roundtrip_error(KernelType::cubic, Scheme::apic, 16, 3);
  const auto b = roundtrip_error(KernelType::cubic, Scheme::apic, 16, 3);
  EXPECT_EQ(a.l2_error, b.l2_error);
  EXPECT_EQ(a.particles, b.particles);
}

TEST(RoundTrip, RejectsFlipAndTinyGrids) {
  EXPECT_THROW(roundtrip_error(KernelType::quadratic, Scheme::flip, 16), std::invalid_argument);
  EXPECT_THROW(roundtrip_error(KernelType::quadratic, Scheme::apic, 2), std::invalid_argument);
}

}  // namespace
}  // namespace apiclab
