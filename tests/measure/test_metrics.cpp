// The sweep's metrics (sim/measure/metrics.hpp) on cases with known answers: a run against itself,
// a run shifted by a known displacement, different particles of the same motion, constructed
// diagnostics rows and a power law.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/measure/metrics.hpp"
#include "sim/measure/run_summary.hpp"

namespace apiclab::metrics {
namespace {

// Material points of a disk (centre c, radius R) on a lattice of spacing h offset by `shift`
// (in units of h), as object 0; a second, smaller disk as object 1.
RunFrames disk_points(double h, double shift) {
  RunFrames run;
  run.dim = 2;
  Frame f0;
  auto add = [&](double cx, double cy, double R, int object) {
    for (double x = cx - R + shift * h; x <= cx + R; x += h)
      for (double y = cy - R + shift * h; y <= cy + R; y += h)
        if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= R * R) {
          f0.positions.push_back(x);
          f0.positions.push_back(y);
          run.object.push_back(object);
        }
  };
  add(0.5, 0.5, 0.3, 0);
  add(1.5, 0.4, 0.1, 1);
  run.frames.push_back(f0);
  return run;
}

// Frames 1..F-1: each object turns rigidly about its own centre by ω t and moves by v t, plus
// `wave` · (sin(2πy), 0) (a non-affine deformation).
void move(RunFrames& run, int frames, double wave = 0) {
  const double centres[2][2] = {{0.5, 0.5}, {1.5, 0.4}};
  const std::vector<double> X = run.frames.front().positions;
  for (int f = 1; f < frames; ++f) {
    const double t = 0.1 * f, a = 0.4 * t;
    Frame fr;
    fr.t = t;
    fr.kinetic = 1.0 + 0.01 * f;
    fr.elastic = 0.1 * f;
    for (std::size_t q = 0; q < run.count(); ++q) {
      const double* c = centres[run.object[q]];
      const double rx = X[2 * q] - c[0], ry = X[2 * q + 1] - c[1];
      fr.positions.push_back(c[0] + std::cos(a) * rx - std::sin(a) * ry + 0.2 * t +
                             wave * t * std::sin(2 * M_PI * X[2 * q + 1]));
      fr.positions.push_back(c[1] + std::sin(a) * rx + std::cos(a) * ry - 0.1 * t);
    }
    run.frames.push_back(fr);
  }
  run.frames.front().kinetic = 1.0;
}

TEST(Metrics, RunAgainstItselfIsZero) {
  RunFrames ref = disk_points(0.02, 0.5);
  move(ref, 6, 0.05);
  const ReferenceDistance d = reference_distance(ref, ref);
  EXPECT_EQ(d.com, 0);
  EXPECT_EQ(d.kinetic, 0);
  EXPECT_EQ(d.elastic, 0);
  EXPECT_NEAR(d.displacement, 0, 1e-13);  // interpolation at its own points: exact to round-off
}

TEST(Metrics, KnownShiftGivesThatDistance) {
  RunFrames ref = disk_points(0.02, 0.5);
  move(ref, 6);
  RunFrames run = ref;
  const double dx = 3e-3, dy = -4e-3;  // |d| = 5e-3
  for (std::size_t f = 1; f < run.frames.size(); ++f)
    for (std::size_t q = 0; q < run.count(); ++q) {
      run.frames[f].positions[2 * q] += dx;
      run.frames[f].positions[2 * q + 1] += dy;
    }
  const ReferenceDistance d = reference_distance(run, ref);
  // Frame 0 is unshifted (the material points X): 5 of the 6 frames carry |d|.
  const double expected = 5e-3 * std::sqrt(5.0 / 6.0);
  EXPECT_NEAR(d.displacement_rms, expected, 1e-12);
  // Centre of mass: the same shift, relative to the bodies' RMS radius sqrt(R²/2) summed over
  // both bodies in quadrature (lattice sampling: within 5% of the continuum value).
  const double size = std::sqrt(0.3 * 0.3 / 2 + 0.1 * 0.1 / 2);
  EXPECT_NEAR(d.com, expected * std::sqrt(2.0) / size, 0.05 * expected * std::sqrt(2.0) / size);
  EXPECT_EQ(d.kinetic, 0);
}

TEST(Metrics, DifferentParticlesOfTheSameMotionGiveAboutZero) {
  // Rigid motion: u = (R − I)(X − c) + v t is affine in X, which the linear fit reproduces.
  RunFrames ref = disk_points(0.02, 0.5), run = disk_points(0.017, 0.2);
  ASSERT_NE(ref.count(), run.count());
  move(ref, 6);
  move(run, 6);
  const ReferenceDistance rigid = reference_distance(run, ref);
  EXPECT_LT(rigid.displacement, 1e-11);
  // The centre of mass of a different sampling differs by the sampling's own error, O(h/R)².
  EXPECT_LT(rigid.com, 5e-3);
  // A smooth non-affine motion: the fit's error is second order in the spacing, far below the
  // displacement itself.
  RunFrames ref_w = disk_points(0.02, 0.5), run_w = disk_points(0.017, 0.2);
  move(ref_w, 6, 0.05);
  move(run_w, 6, 0.05);
  const double wavy = reference_distance(run_w, ref_w).displacement;
  EXPECT_LT(wavy, 2e-3);
  // ...and it can fail: the same run against a reference with a different motion is far.
  RunFrames other = disk_points(0.02, 0.5);
  move(other, 6, 0.5);
  EXPECT_GT(reference_distance(run_w, other).displacement, 0.1);
}

TEST(Metrics, RigidMotionOfAKnownAnswer) {
  // move() turns each disk about its own centre at 0.4 rad/s and moves it by (0.2, −0.1) t.
  RunFrames run = disk_points(0.02, 0.5);
  move(run, 6);
  std::vector<RigidMotion> motions(2);
  motions[0] = {{0.5, 0.5, 0}, {0.2, -0.1, 0}, {0, 0, 0.4}};
  motions[1] = {{1.5, 0.4, 0}, {0.2, -0.1, 0}, {0, 0, 0.4}};
  EXPECT_LT(rigid_motion_distance(run, motions), 1e-14);
  // A wrong spin rate is far from it.
  motions[0].omega[2] = motions[1].omega[2] = 0.2;
  EXPECT_GT(rigid_motion_distance(run, motions), 0.1);
}

TEST(Metrics, FailedRunIsNotComparable) {
  RunFrames ref = disk_points(0.02, 0.5), run = ref;
  move(ref, 6);
  move(run, 4);  // stopped early
  EXPECT_TRUE(std::isnan(reference_distance(run, ref).displacement));
}

TEST(Metrics, ConservationOfConstructedRows) {
  std::vector<DiagnosticsRow> rows(3);
  rows[0].total = 2.0, rows[0].kinetic = 2.0, rows[0].L = {0, 0, 1}, rows[0].p = {1, 0, 0};
  rows[1].total = 1.9, rows[1].L = {0, 0, 1.05}, rows[1].p = {1, 0.3, 0};
  rows[2].total = 2.02, rows[2].L = {0, 0, 0.99}, rows[2].p = {1, 0, 0.4};
  const Conservation c = conservation(rows, DriftRule(rows[0], 1.0, 1.0));
  EXPECT_NEAR(c.max_energy, 0.05, 1e-15);
  EXPECT_NEAR(c.final_energy, 0.01, 1e-15);
  EXPECT_TRUE(c.angular_relative);
  EXPECT_NEAR(c.max_angular, 0.05, 1e-14);
  EXPECT_NEAR(c.final_angular, 0.01, 1e-14);
  EXPECT_NEAR(c.max_momentum, 0.4, 1e-15);
  // L₀ = 0 (a body at rest): the absolute |ΔL|.
  rows[0].L = {0, 0, 0};
  EXPECT_FALSE(conservation(rows, DriftRule(rows[0], 1.0, 1.0)).angular_relative);
  EXPECT_NEAR(conservation(rows, DriftRule(rows[0], 1.0, 1.0)).final_angular, 0.99, 1e-14);
}

TEST(Metrics, LogLogSlope) {
  std::vector<double> x = {0.1, 0.05, 0.025, 0.0125}, y;
  for (double v : x) y.push_back(3 * v * v);
  EXPECT_NEAR(log_log_slope(x, y), 2.0, 1e-12);
  EXPECT_TRUE(std::isnan(log_log_slope({0.1}, {1.0})));
}

}  // namespace
}  // namespace apiclab::metrics
