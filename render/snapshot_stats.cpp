#include "render/snapshot_stats.hpp"

#include <algorithm>
#include <cmath>

namespace apiclab::render {
namespace {

Vec3 to_vec3(const Vec3d& v) { return {float(v[0]), float(v[1]), float(v[2])}; }

template <class Value>
float sampled_quantile(std::size_t n, Value value, float q) {
  const std::size_t stride = std::max<std::size_t>(1, n / kQuantileSamples);
  std::vector<float> samples;
  samples.reserve(n / stride + 1);
  for (std::size_t i = 0; i < n; i += stride)  // inf and NaN (a blow-up) would set no scale
    if (const float v = value(i); std::isfinite(v)) samples.push_back(v);
  return quantile_of(samples, q);
}

}  // namespace

Box3 domain_box(const Snapshot& s) {
  Box3 b{to_vec3(s.domain_min), to_vec3(s.domain_max)};
  if (s.dim == 2) b.min.z = b.max.z = 0;
  return b;
}

Box3 particle_box(const Snapshot& s) {
  if (s.count() == 0) return domain_box(s);
  Box3 b{{1e30f, 1e30f, 0}, {-1e30f, -1e30f, 0}};
  if (s.dim == 3) b.min.z = 1e30f, b.max.z = -1e30f;
  for (std::size_t i = 0; i < s.count(); ++i)
    for (int k = 0; k < s.dim; ++k) {
      b.min[k] = std::min(b.min[k], s.positions[i * s.dim + k]);
      b.max[k] = std::max(b.max[k], s.positions[i * s.dim + k]);
    }
  return b;
}

float quantile_of(std::vector<float>& values, float q) {
  if (values.empty()) return 0;
  const std::size_t k =
      std::min(values.size() - 1, std::size_t(std::clamp(q, 0.0f, 1.0f) * float(values.size())));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
  return values[k];
}

float speed_quantile(const Snapshot& s, float q) {
  return sampled_quantile(
      s.count(), [&](std::size_t i) { return particle_speed(s, i); }, q);
}

float noise_quantile(const Snapshot& s, float q) {
  const std::size_t n = std::min(s.count(), s.noise.size());
  return sampled_quantile(
      n, [&](std::size_t i) { return s.noise[i]; }, q);
}

float typical_radius(const Snapshot& s) {
  if (s.radius.empty()) return float(s.dx) * 0.25f;
  return sampled_quantile(
      s.radius.size(), [&](std::size_t i) { return s.radius[i]; }, 0.5f);
}

int up_axis_from_gravity(const Vec3d& gravity, int dim) {
  if (dim == 2) return 1;
  int up = 1;
  double strongest = 0;
  for (int a = 0; a < 3; ++a)
    if (std::abs(gravity[a]) > strongest) strongest = std::abs(gravity[a]), up = a;
  return up;
}

}  // namespace apiclab::render
