// Synthetic snapshots for the renderer's tests and benchmark: deterministic, solver-free,
// with every feature the renderer draws (two materials, velocities with FLIP-like noise,
// per-particle noise values, a slanted collider, a non-square 2D domain).
#pragma once
#include <cmath>
#include <cstdint>

#include "sim/snapshot.hpp"

namespace apiclab::synthetic {

// A repeatable value in [-1, 1] for integer i (no <random>: its distributions differ
// between standard libraries, and golden images must not).
inline float jitter(std::uint32_t i) {
  i ^= i >> 16, i *= 0x7feb352du, i ^= i >> 15, i *= 0x846ca68bu, i ^= i >> 16;
  return float(i) / 2147483647.5f - 1.0f;
}

inline void add_particle(Snapshot& s, const float* x, const float* v, int material, float radius) {
  const std::uint32_t id = std::uint32_t(s.count());
  for (int k = 0; k < s.dim; ++k) {
    s.positions.push_back(x[k]);
    s.velocities.push_back(v[k]);
  }
  s.material.push_back(material);
  s.object.push_back(material);
  s.radius.push_back(radius);
  s.noise.push_back(std::abs(jitter(id * 7 + 3)) * 0.2f);
}

// About `count` particles: a spinning disk with noisy velocities and a sliding block.
inline Snapshot scene_2d(double count = 1500) {
  Snapshot s;
  s.dim = 2;
  s.scene_name = "synthetic-2d";
  s.scheme = "flip";
  s.kernel = "quadratic";
  s.integrator = "symplectic";
  s.time = 0.5;
  s.domain_min = {0, 0, 0};
  s.domain_max = {2, 1, 0};
  s.dx = 1.0 / 16;
  s.material_names = {"jelly", "steel"};
  const double disk_r = 0.3, area = M_PI * disk_r * disk_r + 0.6 * 0.25;
  const float h = float(std::sqrt(area / count));
  for (float x = 0.2f + h / 2; x < 0.8f; x += h)
    for (float y = 0.35f + h / 2; y < 0.95f; y += h) {
      const float cx = x - 0.5f, cy = y - 0.65f;
      if (cx * cx + cy * cy > disk_r * disk_r) continue;
      const std::uint32_t id = std::uint32_t(s.count());
      const float p[2] = {x, y};
      const float v[2] = {-2 * cy + 0.15f * jitter(2 * id), 2 * cx + 0.15f * jitter(2 * id + 1)};
      add_particle(s, p, v, 0, h / 2);
    }
  for (float x = 1.2f + h / 2; x < 1.8f; x += h)
    for (float y = 0.15f + h / 2; y < 0.4f; y += h) {
      const float p[2] = {x, y}, v[2] = {-0.4f, 0.1f};
      add_particle(s, p, v, 1, h / 2);
    }
  ColliderDesc ramp;
  ramp.point = {0, 0.25, 0};
  ramp.normal = {0.1, 1, 0};
  s.colliders.push_back(ramp);
  return s;
}

// About `count` particles: a falling, spinning ball above a resting slab, and a slanted wall.
inline Snapshot scene_3d(double count = 4000) {
  Snapshot s;
  s.dim = 3;
  s.scene_name = "synthetic-3d";
  s.scheme = "apic";
  s.kernel = "cubic";
  s.integrator = "midpoint";
  s.time = 1.25;
  s.domain_min = {0, 0, 0};
  s.domain_max = {1, 1, 1};
  s.dx = 1.0 / 16;
  s.material_names = {"rubber", "stone"};
  const double ball_r = 0.2, volume = 4.0 / 3 * M_PI * ball_r * ball_r * ball_r + 0.6 * 0.15 * 0.6;
  const float h = float(std::cbrt(volume / count));
  for (float x = 0.3f + h / 2; x < 0.7f; x += h)
    for (float y = 0.45f + h / 2; y < 0.85f; y += h)
      for (float z = 0.3f + h / 2; z < 0.7f; z += h) {
        const float cx = x - 0.5f, cy = y - 0.65f, cz = z - 0.5f;
        if (cx * cx + cy * cy + cz * cz > ball_r * ball_r) continue;
        const float p[3] = {x, y, z}, v[3] = {-3 * cz, -1.0f, 3 * cx};
        add_particle(s, p, v, 0, h / 2);
      }
  for (float x = 0.2f + h / 2; x < 0.8f; x += h)
    for (float y = h / 2; y < 0.15f; y += h)
      for (float z = 0.2f + h / 2; z < 0.8f; z += h) {
        const float p[3] = {x, y, z}, v[3] = {0, 0, 0};
        add_particle(s, p, v, 1, h / 2);
      }
  ColliderDesc wall;
  wall.point = {0.9, 0, 0};
  wall.normal = {-1, 0.3, 0};
  s.colliders.push_back(wall);
  return s;
}

}  // namespace apiclab::synthetic
