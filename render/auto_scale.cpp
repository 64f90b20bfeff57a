#include "render/auto_scale.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/snapshot_stats.hpp"

namespace apiclab::render {
namespace {

std::vector<const Snapshot*> healthy_panes(const std::vector<const Snapshot*>& panes) {
  std::vector<const Snapshot*> healthy;
  for (const Snapshot* p : panes)
    if (!p->failure) healthy.push_back(p);
  return healthy.empty() ? panes : healthy;
}

// Grow: the larger; first frame: the first non-zero value.
float hold(ScaleHold how, float held, float now) {
  if (how == ScaleHold::first_frame && held > 0) return held;
  return std::max(held, now);
}

}  // namespace

void update_scales(ScaleState& state, const std::vector<const Snapshot*>& panes) {
  if (state.hold == ScaleHold::fixed) return;
  float speed = 0, noise = 0;
  const std::vector<const Snapshot*> healthy = healthy_panes(panes);
  if (healthy.empty()) return;
  state.radius = typical_radius(*healthy.front());
  for (const Snapshot* p : healthy) {
    speed = std::max(speed, speed_quantile(*p, kScaleQuantile));
    noise = std::max(noise, noise_quantile(*p, kScaleQuantile));
  }
  state.speed = hold(state.hold, state.speed, nice_ceil(speed));
  // Noise is measured against motion: while nothing moves (a scene starting at rest) there is
  // no scale for it, and round-off noise must not set one (it would be painted full range).
  if (state.speed > 0)
    state.noise =
        hold(state.hold, state.noise, std::max(nice_ceil(noise), kNoiseFloor * state.speed));
}

float color_top(const ScaleState& state, ColorMode mode) {
  const float top = mode == ColorMode::noise ? state.noise : state.speed;
  return top > 0 ? top : 1.0f;
}

SceneStyle resolve_scene_style(const FigureStyle& style, const std::vector<const Snapshot*>& panes,
                               Rect scene_rect, const ScaleState& state) {
  SceneStyle s;
  s.color = style.color;
  s.vectors = style.vectors;
  s.surface = style.surface;
  s.surface_vectors = style.surface_vectors;
  s.grid = style.grid;
  s.box = style.box;
  s.colliders = style.colliders;
  s.particle_scale = style.particle_scale;
  s.line_px = std::max(1.0f, std::min(scene_rect.w, scene_rect.h) / 500.0f);
  if (panes.empty()) return s;
  s.color_max = style.color_max > 0 ? style.color_max : color_top(state, style.color);

  const auto healthy = std::find_if(panes.begin(), panes.end(), [](auto p) { return !p->failure; });
  const Snapshot& first = healthy != panes.end() ? **healthy : *panes.front();
  if (style.vector_every > 0) {
    s.vector_every = style.vector_every;
  } else {
    const double budget = std::max(1.0, double(scene_rect.w) * scene_rect.h / kPixelsPerArrow);
    s.vector_every = int(std::max(1.0, std::ceil(double(first.count()) / budget)));
  }
  if (style.vector_scale > 0) {
    s.vector_scale = style.vector_scale;
  } else if (state.speed > 0) {
    // Spacing between arrows: one per `every` particles sampled 2r apart, in `dim`
    // dimensions (the particles' drawing size does not move them apart).
    const float spacing =
        2 * state.radius * std::pow(float(s.vector_every), 1.0f / float(first.dim));
    s.vector_scale = kArrowSpacings * spacing / state.speed * style.vector_gain;
  } else {
    s.vector_scale = 0;  // nothing moves: no arrows to draw
  }
  return s;
}

float nice_ceil(float v) {
  if (!(v > 0) || !std::isfinite(v)) return 0;
  const float e = std::pow(10.0f, std::floor(std::log10(v)));
  for (float m : {1.0f, 1.2f, 1.5f, 2.0f, 2.5f, 3.0f, 4.0f, 5.0f, 6.0f, 8.0f, 10.0f})
    if (m * e >= v * 0.9999f) return std::min(m * e, std::numeric_limits<float>::max());
  return std::numeric_limits<float>::max();
}

float nice_floor(float v) {
  if (!(v > 0)) return 0;
  const float e = std::pow(10.0f, std::floor(std::log10(v)));
  for (float m : {5.0f, 2.0f, 1.0f})
    if (m * e <= v * 1.0001f) return m * e;
  return e;
}

}  // namespace apiclab::render
