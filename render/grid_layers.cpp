// The snapshot's optional grid layers (sim/snapshot.hpp GridLayer): each grid's outline in
// its own frame, and its nodes coloured by one field on viridis over the field's range;
// 2D as translucent cells centred on the nodes, 3D as small squares facing the camera.
#include <algorithm>
#include <cmath>

#include "render/renderer.hpp"

namespace apiclab::render {
namespace {

constexpr Rgba8 kGridOutline{40, 70, 140, 255};

// World position of local point (dx-scaled node coordinates) q: R q + t.
Vec3 to_world(const GridLayer& g, const Vec3& q, int dim) {
  const auto& R = g.rotation;
  Vec3 w;
  for (int r = 0; r < 3; ++r)
    w[r] = float(R[3 * r] * q.x + R[3 * r + 1] * q.y + R[3 * r + 2] * q.z + g.translation[r]);
  if (dim == 2) w.z = 0;
  return w;
}

const GridLayer::Field* field_of(const GridLayer& g, const std::string& name) {
  for (const GridLayer::Field& f : g.fields)
    if (name.empty() || f.name == name) return f.values.size() == g.node_count() ? &f : nullptr;
  return nullptr;
}

}  // namespace

void Renderer::add_grid_layers(const Snapshot& s, const Camera& camera, float line_px,
                               float pixels_per_unit, const std::string& field) {
  const Vec3 right{camera.view(0, 0), camera.view(0, 1), camera.view(0, 2)};
  for (const GridLayer& g : s.grids) {
    const float dx = float(g.dx);
    const int n[3] = {g.nodes[0], g.nodes[1], s.dim == 3 ? g.nodes[2] : 1};
    if (!(dx > 0) || n[0] < 1 || n[1] < 1 || n[2] < 1) continue;
    // Outline: the box from node 0 to the last node.
    const Vec3 extent{dx * float(n[0] - 1), dx * float(n[1] - 1), dx * float(n[2] - 1)};
    auto corner = [&](int c) {
      return to_world(g, {c & 1 ? extent.x : 0, c & 2 ? extent.y : 0, c & 4 ? extent.z : 0}, s.dim);
    };
    for (int c = 0; c < (s.dim == 3 ? 8 : 4); ++c)
      for (int axis = 0; axis < s.dim; ++axis)
        if (!(c & (1 << axis)))
          scene_lines_.push_back(
              {corner(c), corner(c | (1 << axis)), kGridOutline, 1.4f * line_px, 0, 0});
    const GridLayer::Field* f = field_of(g, field);
    if (!f) continue;
    // Non-finite values mark nodes without a value (an EoL grid's empty nodes): not drawn.
    float low = INFINITY, high = -INFINITY;
    for (float v : f->values)
      if (std::isfinite(v)) {
        low = std::min(low, v);
        high = std::max(high, v);
      }
    const float range = high > low ? high - low : 0.f;
    std::size_t node = 0;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i, ++node) {
          if (!std::isfinite(f->values[node])) continue;
          const float t = range > 0 ? (f->values[node] - low) / range : 0.5f;
          const Vec3 q{dx * float(i), dx * float(j), dx * float(k)};
          if (s.dim == 2) {
            const Rgba8 c = to_rgba8(viridis(t), 0.6f);
            const float h = 0.5f * dx;
            const Vec3 quad[4] = {
                to_world(g, q + Vec3{-h, -h, 0}, 2), to_world(g, q + Vec3{h, -h, 0}, 2),
                to_world(g, q + Vec3{h, h, 0}, 2), to_world(g, q + Vec3{-h, h, 0}, 2)};
            for (int v : {0, 1, 2, 0, 2, 3}) scene_fills_.push_back({quad[v], c});
          } else {
            const Vec3 p = to_world(g, q, 3), half = right * (0.18f * dx);
            scene_lines_.push_back({p - half, p + half, to_rgba8(viridis(t)),
                                    std::max(2.0f, 0.36f * dx * pixels_per_unit), 0, 0});
          }
        }
  }
}

}  // namespace apiclab::render
