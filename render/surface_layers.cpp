// The snapshot's object surfaces (sim/snapshot.hpp SurfaceLayer, the EoL solver's Algorithm 2
// placement): 2D as a dark outline over the node dots; 3D as translucent triangles lit from
// the eye (flat, |n · view|), so the node dots inside stay visible.
#include <algorithm>
#include <cmath>

#include "render/renderer.hpp"

namespace apiclab::render {
namespace {

constexpr Rgba8 kOutline{25, 25, 30, 255};
constexpr float kSurfaceRgb[3] = {235, 150, 70};  // warm, apart from viridis' blues and greens

}  // namespace

void Renderer::add_surface_layers(const Snapshot& s, const Camera& camera, float line_px) {
  const Vec3 toward_eye{camera.view(2, 0), camera.view(2, 1), camera.view(2, 2)};
  for (const SurfaceLayer& layer : s.surfaces) {
    const std::size_t vertices = layer.positions.size() / std::size_t(s.dim);
    auto vertex = [&](std::uint32_t v) {
      Vec3 x;
      for (int k = 0; k < s.dim; ++k) x[k] = layer.positions[std::size_t(v) * s.dim + k];
      return x;
    };
    for (std::size_t e = 0; e + std::size_t(s.dim) <= layer.elements.size(); e += s.dim) {
      const std::uint32_t* idx = &layer.elements[e];
      if (std::any_of(idx, idx + s.dim, [&](std::uint32_t v) { return v >= vertices; })) continue;
      if (s.dim == 2) {
        scene_lines_.push_back({vertex(idx[0]), vertex(idx[1]), kOutline, 1.8f * line_px, 0, 0});
        continue;
      }
      const Vec3 a = vertex(idx[0]), b = vertex(idx[1]), c = vertex(idx[2]);
      const Vec3 n = cross(b - a, c - a);
      const float len = length(n);
      const float light = len > 0 ? 0.35f + 0.65f * std::abs(dot(n, toward_eye)) / len : 0.35f;
      const Rgba8 colour{std::uint8_t(kSurfaceRgb[0] * light), std::uint8_t(kSurfaceRgb[1] * light),
                         std::uint8_t(kSurfaceRgb[2] * light), 120};
      scene_fills_.insert(scene_fills_.end(), {{a, colour}, {b, colour}, {c, colour}});
    }
  }
}

}  // namespace apiclab::render
