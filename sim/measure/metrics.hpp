// What a sweep measures of a run: conservation from its diagnostics rows, and its
// distance to a reference run from the particle positions at frame times. Pure functions of
// rows and frames, so they are tested on constructed cases (tests/measure/test_metrics.cpp).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "sim/measure/diagnostics.hpp"

namespace apiclab {
class DriftRule;  // sim/measure/run_summary.hpp
}

namespace apiclab::metrics {

// Conservation over a run, by the drift rule of sim/measure/run_summary.hpp: |ΔE|/|E₀|, or the
// absolute |ΔE| where E₀ is round-off; |ΔL|/|L₀|, or the absolute |ΔL| where L₀ counts as zero;
// |Δp| absolute. Max over every row and at the last row.
struct Conservation {
  double max_energy = 0, final_energy = 0;
  double max_angular = 0, final_angular = 0;
  bool angular_relative = true;
  double max_momentum = 0, final_momentum = 0;
  bool energy_relative = true;
};
// `drift`: the run's rule, from its first row (DriftRule::of).
Conservation conservation(const std::vector<DiagnosticsRow>& rows, const DriftRule& drift);

// One run at its frame times: particle positions by particle id (dim values each) and the
// energies at that time. Frame 0 is the initial state, so positions[0] are the material points X.
struct Frame {
  double t = 0, kinetic = 0, elastic = 0;
  std::vector<double> positions;
};
struct RunFrames {
  int dim = 2;
  std::vector<std::int32_t> object;  // object index per particle
  std::vector<Frame> frames;
  std::size_t count() const { return object.size(); }
  int object_count() const;
};

// Centre of mass per object (particles of one object carry equal mass: uniform density and
// equal volume per sample), dim components, zero-padded to 3.
std::vector<std::array<double, 3>> centres_of_mass(const RunFrames& run, const Frame& frame);

// sqrt(Σ|a − b|²) / max(sqrt(Σ|b|²), floor): a relative L2 error over a series.
double relative_l2(const std::vector<double>& a, const std::vector<double>& b, double floor);

// Interpolation of another run's displacement u = x − X at the reference's material points: for
// each point, weights c_j over the k nearest material points of the same object in the other run
// (k-d tree, nanoflann) from a weighted linear least-squares fit, so u(X*) = Σ c_j u_j is exact
// for every affine displacement field (rigid motions included).
class DisplacementInterpolator {
 public:
  DisplacementInterpolator(const RunFrames& from, const RunFrames& at);
  // The interpolated displacement of `from` at `at`'s material points at frame f (dim values per
  // point, by `at`'s particle order).
  std::vector<double> displacement(const RunFrames& from, std::size_t f) const;

 private:
  struct Term {
    std::uint32_t particle;
    double weight;
  };
  std::vector<std::uint32_t> begin_;  // terms of point q: [begin_[q], begin_[q + 1])
  std::vector<Term> terms_;
  int dim_ = 2;
};

// Distances of a run to the reference, each a relative L2 error over the frames: centre-of-mass
// trajectory (relative to the reference body's RMS radius), kinetic energy (relative to the
// reference's), elastic energy (relative to the reference's kinetic + elastic energy), and the
// displacement field x − X at the reference's material points (relative to the reference's).
// displacement_rms is the absolute RMS displacement error. NaN when the runs do not share their
// frame times (a run that blew up) or the particle objects differ.
struct ReferenceDistance {
  double com = 0, kinetic = 0, elastic = 0, displacement = 0, displacement_rms = 0;
};
ReferenceDistance reference_distance(const RunFrames& run, const RunFrames& reference);

// A known answer: each object in free rigid motion about its initial centre c (a disk spinning
// with no forces, to the extent its elastic stretch is negligible),
// x(t) = c + v t + R(ω t)(X − c), with R the rotation by |ω| t about ω (2D: about z, ω = ω_z).
struct RigidMotion {
  std::array<double, 3> centre{0, 0, 0}, velocity{0, 0, 0}, omega{0, 0, 0};
};
// The relative L2 error over the frames of the run's displacement x − X against the rigid
// motion's, per particle of object o with motions[o]; NaN without frames.
double rigid_motion_distance(const RunFrames& run, const std::vector<RigidMotion>& motions);

// Least-squares slope of log(y) against log(x) over the positive, finite pairs; NaN with fewer
// than two.
double log_log_slope(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace apiclab::metrics
