// What the drawing rules need to know about a Snapshot: its boxes, particle speeds, sampled
// quantiles, the typical particle radius, and which way is up. CPU only; no GL.
#pragma once
#include <cmath>
#include <cstddef>
#include <vector>

#include "render/camera.hpp"
#include "sim/snapshot.hpp"

namespace apiclab::render {

// Box of a snapshot's domain (2D: z from 0 to 0).
Box3 domain_box(const Snapshot& s);
// Bounding box of the particles' centres (the domain box when there are none).
Box3 particle_box(const Snapshot& s);

// |v_p| of particle i.
inline float particle_speed(const Snapshot& s, std::size_t i) {
  const float* v = &s.velocities[i * std::size_t(s.dim)];
  float v2 = 0;
  for (int k = 0; k < s.dim; ++k) v2 += v[k] * v[k];
  return std::sqrt(v2);
}

// The q-quantile (q in [0, 1]) of `values`, reordering them; 0 when empty.
float quantile_of(std::vector<float>& values, float q);

// The q-quantile of |v_p| and of the noise field over at most kQuantileSamples particles
// (every n/kQuantileSamples-th one: steady from frame to frame), of the finite values only.
// Noise: 0 when absent.
inline constexpr std::size_t kQuantileSamples = 50000;
float speed_quantile(const Snapshot& s, float q);
float noise_quantile(const Snapshot& s, float q);

// The median drawing radius (a quarter cell when the snapshot has none).
float typical_radius(const Snapshot& s);

// The axis that points up on screen: against the strongest gravity component, y when there
// is no gravity (2D scenes always y).
int up_axis_from_gravity(const Vec3d& gravity, int dim);

}  // namespace apiclab::render
