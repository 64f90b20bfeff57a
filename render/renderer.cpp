#include "render/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <unordered_set>

#include "render/gl.hpp"
#include "render/gl_upload.hpp"
#include "render/program.hpp"
#include "render/scene_geometry.hpp"

namespace apiclab::render {
namespace {

constexpr Rgba8 kArrow{20, 20, 20, 235};
constexpr Rgba8 kArrowHalo{255, 255, 255, 140};
constexpr Rgba8 kBox{120, 120, 120, 255};
constexpr Rgba8 kGrid{222, 222, 222, 255};
constexpr Rgba8 kCollider{70, 70, 70, 255};

Vec3 to_vec3(const Vec3d& v) { return {float(v[0]), float(v[1]), float(v[2])}; }

// Vertex attribute of `count` floats (or normalized bytes) at `offset` in a `stride` record.
void attribute(GLuint index, int count, GLenum type, std::size_t stride, std::size_t offset,
               bool per_instance) {
  gl::EnableVertexAttribArray(index);
  gl::VertexAttribPointer(index, count, type, type == GL_UNSIGNED_BYTE ? GL_TRUE : GL_FALSE,
                          GLsizei(stride), reinterpret_cast<const void*>(offset));
  gl::VertexAttribDivisor(index, per_instance ? 1 : 0);
}

}  // namespace

Rgba8 particle_color(const Snapshot& s, std::size_t i, const SceneStyle& style) {
  switch (style.color) {
    case ColorMode::material:
      return category_color(i < s.material.size() ? s.material[i] : 0);
    case ColorMode::object:
      return category_color(i < s.object.size() ? s.object[i] : 0);
    case ColorMode::noise:
      return to_rgba8(viridis(i < s.noise.size() ? s.noise[i] / style.color_max : 0));
    case ColorMode::speed:
      break;
  }
  return to_rgba8(viridis(particle_speed(s, i) / style.color_max));
}

bool carries_arrow(std::size_t id, int every) {
  if (every <= 1) return true;
  // A 32-bit integer hash: a lattice's rows do not alias with `every`.
  std::uint32_t x = std::uint32_t(id) + 0x9e3779b9u;
  x ^= x >> 16, x *= 0x7feb352du, x ^= x >> 15, x *= 0x846ca68bu, x ^= x >> 16;
  return x % std::uint32_t(every) == 0;
}

Renderer::Renderer() {
  discs_ = std::make_unique<Program>("shaders/particles.vert", "shaders/disc.frag");
  spheres_ = std::make_unique<Program>("shaders/particles.vert", "shaders/sphere.frag");
  shadow_map_ = std::make_unique<Program>("shaders/particles.vert", "shaders/shadow_map.frag");
  floor_ = std::make_unique<Program>("shaders/floor.vert", "shaders/floor.frag");
  segments_ = std::make_unique<Program>("shaders/segments.vert", "shaders/flat.frag");
  fills_ = std::make_unique<Program>("shaders/fill.vert", "shaders/fill.frag");
  text_ = std::make_unique<Program>("shaders/text.vert", "shaders/text.frag");

  const float quad[] = {-1, -1, 1, -1, -1, 1, 1, 1};  // triangle strip
  gl::GenBuffers(1, &quad_vbo_);
  gl::BindBuffer(GL_ARRAY_BUFFER, quad_vbo_);
  gl::BufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
  // Arrow template: shaft quad (two triangles) then head triangle; see segments.vert.
  const float arrow[] = {0, -1, 0, 1, -1, 0,  1, 1, 0, 0, -1, 0, 1, 1,
                         0, 0,  1, 0, 0,  -1, 1, 0, 1, 1, 1,  0, 1};
  gl::GenBuffers(1, &template_vbo_);
  gl::BindBuffer(GL_ARRAY_BUFFER, template_vbo_);
  gl::BufferData(GL_ARRAY_BUFFER, sizeof arrow, arrow, GL_STATIC_DRAW);

  // Particles as instanced quads, and the same buffer as one point per particle.
  gl::GenBuffers(1, &particle_vbo_);
  gl::GenVertexArrays(2, particle_vao_);
  using P = ParticleInstance;
  for (int points = 0; points < 2; ++points) {
    gl::BindVertexArray(particle_vao_[points]);
    if (!points) {
      gl::BindBuffer(GL_ARRAY_BUFFER, quad_vbo_);
      attribute(0, 2, GL_FLOAT, 2 * sizeof(float), 0, false);
    }
    gl::BindBuffer(GL_ARRAY_BUFFER, particle_vbo_);
    attribute(1, 3, GL_FLOAT, sizeof(P), offsetof(P, center), !points);
    attribute(2, 1, GL_FLOAT, sizeof(P), offsetof(P, radius), !points);
    attribute(3, 4, GL_UNSIGNED_BYTE, sizeof(P), offsetof(P, color), !points);
  }
  GLfloat point_sizes[2] = {1, 1};
  gl::GetFloatv(GL_POINT_SIZE_RANGE, point_sizes);
  max_point_size_ = point_sizes[1];

  gl::GenVertexArrays(1, &segment_vao_);
  gl::GenBuffers(1, &segment_vbo_);
  gl::BindVertexArray(segment_vao_);
  gl::BindBuffer(GL_ARRAY_BUFFER, template_vbo_);
  attribute(0, 3, GL_FLOAT, 3 * sizeof(float), 0, false);
  gl::BindBuffer(GL_ARRAY_BUFFER, segment_vbo_);
  using S = SegmentInstance;
  attribute(1, 3, GL_FLOAT, sizeof(S), offsetof(S, from), true);
  attribute(2, 3, GL_FLOAT, sizeof(S), offsetof(S, to), true);
  attribute(3, 4, GL_UNSIGNED_BYTE, sizeof(S), offsetof(S, color), true);
  attribute(4, 3, GL_FLOAT, sizeof(S), offsetof(S, width), true);

  gl::GenVertexArrays(1, &fill_vao_);
  gl::GenBuffers(1, &fill_vbo_);
  gl::BindVertexArray(fill_vao_);
  gl::BindBuffer(GL_ARRAY_BUFFER, fill_vbo_);
  using F = FillVertex;
  attribute(0, 3, GL_FLOAT, sizeof(F), offsetof(F, position), false);
  attribute(1, 4, GL_UNSIGNED_BYTE, sizeof(F), offsetof(F, color), false);

  gl::GenVertexArrays(1, &text_vao_);
  gl::GenBuffers(1, &text_vbo_);
  gl::BindVertexArray(text_vao_);
  gl::BindBuffer(GL_ARRAY_BUFFER, text_vbo_);
  using T = TextVertex;
  attribute(0, 2, GL_FLOAT, sizeof(T), offsetof(T, x), false);
  attribute(1, 2, GL_FLOAT, sizeof(T), offsetof(T, u), false);
  attribute(2, 4, GL_UNSIGNED_BYTE, sizeof(T), offsetof(T, color), false);
  gl::BindVertexArray(0);
}

Renderer::~Renderer() {
  if (shadow_texture_) gl::DeleteTextures(1, &shadow_texture_);
  if (shadow_fbo_) gl::DeleteFramebuffers(1, &shadow_fbo_);
  for (auto& [size, entry] : fonts_) gl::DeleteTextures(1, &entry.texture);
  unsigned vaos[] = {particle_vao_[0], particle_vao_[1], segment_vao_, fill_vao_, text_vao_};
  unsigned vbos[] = {quad_vbo_, template_vbo_, particle_vbo_, segment_vbo_, fill_vbo_, text_vbo_};
  gl::DeleteVertexArrays(5, vaos);
  gl::DeleteBuffers(6, vbos);
}

void Renderer::begin_frame(int width, int height, Rgba8 background) {
  width_ = width;
  height_ = height;
  gl::Viewport(0, 0, width, height);
  gl::Disable(GL_SCISSOR_TEST);
  gl::DepthMask(GL_TRUE);
  gl::ClearColor(background.r / 255.0f, background.g / 255.0f, background.b / 255.0f,
                 background.a / 255.0f);
  gl::Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  overlay_lines_.clear();
  overlay_fills_.clear();
  for (auto& [size, entry] : fonts_) entry.vertices.clear();
}

void Renderer::set_viewport(Rect r) {
  const int x = int(std::lround(r.x)), w = int(std::lround(r.w)), h = int(std::lround(r.h));
  const int y = height_ - int(std::lround(r.y)) - h;  // OpenGL counts rows from the bottom
  gl::Viewport(x, y, w, h);
  gl::Scissor(x, y, w, h);
  gl::Enable(GL_SCISSOR_TEST);
}

void Renderer::draw_scene(const Snapshot& s, const Camera& camera, Rect rect,
                          const SceneStyle& style) {
  set_viewport(rect);
  gl::Enable(GL_BLEND);
  gl::BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  gl::Clear(GL_DEPTH_BUFFER_BIT);
  const Box3 box = domain_box(s);
  const Vec2 viewport{rect.w, rect.h};
  const bool three_d = s.dim == 3;
  // Pixels per world unit at the scene's centre: sizes grid cells and hatches.
  const float ppu = camera.projection(1, 1) * 0.5f * rect.h /
                    (camera.perspective ? length(box.center() - camera.eye) : 1.0f);
  const Mat4 view_projection = camera.projection * camera.view;
  const bool points = upload_particles(s, camera, rect, style);

  // 1. Underlay: the 3D floor with its shadows, then the grid lines.
  int up = 1;
  if (three_d) {
    // The floor is the face at the minimum of the axis closest to the camera's up.
    const Vec3 camera_up{camera.view(1, 0), camera.view(1, 1), camera.view(1, 2)};
    for (int a = 0; a < 3; ++a)
      if (std::abs(camera_up[a]) > std::abs(camera_up[up])) up = a;
    gl::Enable(GL_DEPTH_TEST);
    gl::DepthFunc(GL_LEQUAL);
    gl::DepthMask(GL_FALSE);  // the floor never hides a particle sitting on it
    draw_floor(box, up, view_projection, rect);
  } else {
    gl::Disable(GL_DEPTH_TEST);
  }
  scene_lines_.clear();
  scene_fills_.clear();
  if (style.grid && s.dx > 0 && s.dx * ppu >= 3)
    add_grid(box, float(s.dx), three_d ? (up + 1) % 3 : 0, three_d ? (up + 2) % 3 : 1,
             style.line_px);
  // A solver's own grids (EoL's) with the grid lines: one click away, not over the body.
  if (style.grid && !s.grids.empty())
    add_grid_layers(s, camera, style.line_px, ppu, style.grid_field);
  draw_fills(scene_fills_, view_projection);
  draw_segments(scene_lines_, camera.view, camera.projection, viewport);

  // 2. Particles. Alpha to coverage antialiases sphere silhouettes without sorting; 2D
  //    discs blend.
  const Program& particles = three_d ? *spheres_ : *discs_;
  particles.use();
  particles.set("u_flatten_axis", -1);
  particles.set("u_radius_scale", 1.0f);
  if (three_d) {
    gl::DepthMask(GL_TRUE);
    gl::Disable(GL_BLEND);
    gl::Enable(GL_SAMPLE_ALPHA_TO_COVERAGE);
  }
  draw_particles(particles, camera, rect, points);
  if (three_d) {
    gl::Disable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    gl::Enable(GL_BLEND);
    gl::DepthMask(GL_FALSE);
  }

  // 3. Domain box and colliders over the particles (depth-tested in 3D), then the arrows.
  scene_lines_.clear();
  scene_fills_.clear();
  if (style.surface && !s.surfaces.empty()) add_surface_layers(s, camera, style.line_px);
  if (style.box) add_box(box, s.dim, style.line_px);
  if (style.colliders)
    for (const ColliderDesc& c : s.colliders)
      add_collider(c, s.time, box, s.dim, style.line_px, ppu);
  draw_fills(scene_fills_, view_projection);
  draw_segments(scene_lines_, camera.view, camera.projection, viewport);
  if ((style.vectors || style.surface_vectors) && style.vector_scale > 0)
    draw_arrows(s, camera, viewport, style);

  gl::DepthMask(GL_TRUE);
  gl::Disable(GL_DEPTH_TEST);
  gl::Disable(GL_SCISSOR_TEST);
  gl::Viewport(0, 0, width_, height_);
}

void Renderer::add_grid(const Box3& box, float dx, int axis_a, int axis_b, float line_px) {
  for (int k = 0; k < 2; ++k) {
    const int a = k ? axis_b : axis_a, b = k ? axis_a : axis_b;
    const int cells = int(std::lround((box.max[a] - box.min[a]) / dx));
    for (int i = 1; i < cells; ++i) {
      Vec3 from = box.min, to = box.min;
      from[a] = to[a] = box.min[a] + float(i) * dx;
      to[b] = box.max[b];
      scene_lines_.push_back({from, to, kGrid, 0.8f * line_px, 0, 0});
    }
  }
}

void Renderer::add_box(const Box3& box, int dim, float line_px) {
  auto corner = [&](int c) {
    return Vec3{c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y,
                c & 4 ? box.max.z : box.min.z};
  };
  for (int i = 0; i < (dim == 3 ? 8 : 4); ++i)
    for (int axis = 0; axis < dim; ++axis)
      if (!(i & (1 << axis)))
        scene_lines_.push_back({corner(i), corner(i | (1 << axis)), kBox, line_px, 0, 0});
}

void Renderer::add_collider(const ColliderDesc& c, double time, const Box3& box, int dim,
                            float line_px, float pixels_per_unit) {
  const ColliderPose pose = collider_pose(c, dim, time);
  if (pose.type != ColliderType::plane) return add_body(pose, dim, line_px);
  Vec3 p = to_vec3(pose.center), n = normalize(to_vec3(pose.normal));
  if (dim == 2) p.z = 0, n.z = 0;
  const std::vector<Vec3> poly = plane_in_box(p, n, box, dim);
  if (poly.size() < 2) return;
  if (dim == 2) {
    // The wall, and hatches on its solid side like an engineering drawing.
    const Vec3 a = poly[0], b = poly[1], t = normalize(b - a);
    scene_lines_.push_back({a, b, kCollider, 1.6f * line_px, 0, 0});
    const float px = 1 / std::max(pixels_per_unit, 1e-12f), wall = length(b - a);
    // 7 pixels apart, but at most kMaxHatches along the wall: zoomed in far, a wall is millions
    // of pixels long and a float sum of 7-pixel steps stops moving before its end.
    constexpr int kMaxHatches = 4096;
    const float spacing = std::max(7 * px * std::max(line_px, 1.0f), wall / kMaxHatches);
    const float depth = 5 * px * line_px;
    const Vec3 slant = normalize(t - n) * (depth * 1.4142f);
    const int hatches =
        spacing > 0 ? int(std::ceil(std::clamp(wall / spacing - 0.5f, 0.0f, float(kMaxHatches))))
                    : 0;  // every u = (k + 1/2) spacing below the wall's length
    for (int k = 0; k < hatches; ++k) {
      const float u = (float(k) + 0.5f) * spacing;
      scene_lines_.push_back({a + t * u, a + t * u + slant, kCollider, 0.8f * line_px, 0, 0});
    }
    return;
  }
  // 3D: the plane's polygon inside the domain, translucent, with its outline.
  Vec3 centre;
  for (const Vec3& q : poly) centre = centre + q * (1.0f / float(poly.size()));
  const Rgba8 fill{90, 90, 90, 40};
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Vec3& a = poly[k];
    const Vec3& b = poly[(k + 1) % poly.size()];
    scene_fills_.insert(scene_fills_.end(), {{centre, fill}, {a, fill}, {b, fill}});
    scene_lines_.push_back({a, b, kCollider, 1.2f * line_px, 0, 0});
  }
}

// A box or rod: its outline (2D, filled translucent) or its edges and rings (3D).
void Renderer::add_body(const ColliderPose& body, int dim, float line_px) {
  const Vec3 c = to_vec3(body.center);
  const Vec3 e[3] = {to_vec3(body.axes[0]), to_vec3(body.axes[1]), to_vec3(body.axes[2])};
  const float h[3] = {float(body.half[0]), float(body.half[1]), float(body.half[2])};
  const Rgba8 fill{90, 90, 90, 90};
  auto outline = [&](const std::vector<Vec3>& poly, bool filled) {
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const Vec3 &a = poly[k], &b = poly[(k + 1) % poly.size()];
      if (filled) scene_fills_.insert(scene_fills_.end(), {{c, fill}, {a, fill}, {b, fill}});
      scene_lines_.push_back({a, b, kCollider, 1.6f * line_px, 0, 0});
    }
  };
  constexpr int kArc = 16;  // segments per half circle
  constexpr float kPi = 3.14159265f;
  if (body.type == ColliderType::box) {
    if (dim == 2) {
      outline({c - e[0] * h[0] - e[1] * h[1], c + e[0] * h[0] - e[1] * h[1],
               c + e[0] * h[0] + e[1] * h[1], c - e[0] * h[0] + e[1] * h[1]},
              true);
      return;
    }
    for (int i = 0; i < 8; ++i)
      for (int a = 0; a < 3; ++a) {
        if (i & (1 << a)) continue;
        Vec3 p = c;
        for (int b = 0; b < 3; ++b) p = p + e[b] * (h[b] * ((i & (1 << b)) ? 1.0f : -1.0f));
        scene_lines_.push_back({p, p + e[a] * (2 * h[a]), kCollider, 1.2f * line_px, 0, 0});
      }
    return;
  }
  // A rod: half circles of radius r about the segment's ends, joined by its sides.
  const float half = h[0], r = h[1];
  auto ring = [&](Vec3 at, Vec3 u, Vec3 v, float from, float turn) {
    std::vector<Vec3> pts;
    for (int k = 0; k <= kArc; ++k) {
      const float t = from + turn * float(k) / kArc;
      pts.push_back(at + u * (r * std::cos(t)) + v * (r * std::sin(t)));
    }
    return pts;
  };
  if (dim == 2) {
    std::vector<Vec3> poly = ring(c + e[0] * half, e[0], e[1], -kPi / 2, kPi);
    for (const Vec3& q : ring(c - e[0] * half, e[0], e[1], kPi / 2, kPi)) poly.push_back(q);
    outline(poly, true);
    return;
  }
  for (float end : {-1.0f, 1.0f}) {
    const Vec3 at = c + e[0] * (end * half);
    const std::vector<Vec3> circle = ring(at, e[1], e[2], 0, 2 * kPi);
    for (std::size_t k = 0; k + 1 < circle.size(); ++k)
      scene_lines_.push_back({circle[k], circle[k + 1], kCollider, 1.2f * line_px, 0, 0});
    for (const Vec3& side : {e[1], e[2]}) {
      const std::vector<Vec3> cap = ring(at, side, e[0] * end, 0, kPi);
      for (std::size_t k = 0; k + 1 < cap.size(); ++k)
        scene_lines_.push_back({cap[k], cap[k + 1], kCollider, 1.2f * line_px, 0, 0});
    }
  }
  for (const Vec3& side : {e[1], e[2], e[1] * -1.0f, e[2] * -1.0f})
    scene_lines_.push_back(
        {c - e[0] * half + side * r, c + e[0] * half + side * r, kCollider, 1.2f * line_px, 0, 0});
}

void Renderer::draw_arrows(const Snapshot& s, const Camera& camera, Vec2 viewport,
                           const SceneStyle& style) {
  std::vector<SegmentInstance>& arrows = scene_lines_;
  arrows.clear();
  const float lw = style.line_px, head = std::max(4.0f, 3.5f * lw);
  const float fallback_radius = float(s.dx) * 0.25f;
  for (std::size_t i = 0; i < (style.vectors ? s.count() : 0); ++i) {
    if (!carries_arrow(i, style.vector_every)) continue;
    Vec3 x, v;
    for (int k = 0; k < s.dim; ++k) {
      x[k] = s.positions[i * s.dim + k];
      v[k] = s.velocities[i * s.dim + k];
    }
    // 3D arrows start on the sphere's surface facing the eye, not hidden inside it.
    const float r = (i < s.radius.size() ? s.radius[i] : fallback_radius) * style.particle_scale;
    arrows.push_back(
        {x, x + v * style.vector_scale, kArrow, 0.9f * lw, head, s.dim == 3 ? r : 0.0f});
  }
  // Arrows on the surface vertices (sim/snapshot.hpp SurfaceLayer), at most one per square of
  // the image as wide as the arrows are long on average (18 pixels at least): one per vertex,
  // a pixel or two apart, made a solid ring.
  if (style.surface_vectors) {
    const Mat4 view_projection = camera.projection * camera.view;
    auto pixel = [&](const Vec3& p, Vec2& out) {
      const Vec4 c = view_projection * Vec4{p.x, p.y, p.z, 1};
      if (!(c.w > 0)) return false;
      out = {(c.x / c.w + 1) * 0.5f * viewport.x, (c.y / c.w + 1) * 0.5f * viewport.y};
      return true;
    };
    std::vector<std::pair<Vec3, Vec3>> candidates;  // base and tip
    double length_px = 0;
    for (const SurfaceLayer& layer : s.surfaces)
      for (std::size_t i = 0; i * s.dim < layer.positions.size(); ++i) {
        Vec3 x, v;
        for (int k = 0; k < s.dim; ++k) {
          x[k] = layer.positions[i * s.dim + k];
          v[k] = layer.velocities[i * s.dim + k];
        }
        Vec2 a, b;
        if (!pixel(x, a) || !pixel(x + v * style.vector_scale, b)) continue;
        candidates.push_back({x, x + v * style.vector_scale});
        length_px += std::hypot(double(b.x - a.x), double(b.y - a.y));
      }
    const float cell =
        std::max(18.0f, candidates.empty() ? 0.0f : float(length_px / double(candidates.size())));
    std::unordered_set<long long> taken;
    for (const auto& [base, tip] : candidates) {
      Vec2 p;
      pixel(base, p);
      const long long key = std::llround(p.x / cell) * 1000003LL + std::llround(p.y / cell);
      if (taken.insert(key).second) arrows.push_back({base, tip, kArrow, 0.9f * lw, head, 0.0f});
    }
  }
  // A pale halo under every arrow first, so dark arrows read on dark particles too.
  std::vector<SegmentInstance> halos = arrows;
  const float halo = std::max(0.75f, 0.6f * lw);
  for (SegmentInstance& h : halos) {
    h.color = kArrowHalo;
    h.width += 2 * halo;
    h.head += 2 * halo;
  }
  draw_segments(halos, camera.view, camera.projection, viewport);
  draw_segments(arrows, camera.view, camera.projection, viewport);
}

bool Renderer::upload_particles(const Snapshot& s, const Camera& camera, Rect rect,
                                const SceneStyle& style) {
  const std::size_t n = s.count();
  particles_.resize(n);
  const float fallback_radius = float(s.dx) * 0.25f;
  float largest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ParticleInstance& p = particles_[i];
    p.center = {s.positions[i * s.dim], s.positions[i * s.dim + 1],
                s.dim == 3 ? s.positions[i * s.dim + 2] : 0.0f};
    p.radius = (i < s.radius.size() ? s.radius[i] : fallback_radius) * style.particle_scale;
    p.color = particle_color(s, i, style);
    largest = std::max(largest, p.radius);
  }
  upload(particle_vbo_, particles_);
  largest_radius_ = largest;
  // Points need one vertex instead of four; quads take over when a particle is larger than
  // the largest point the driver draws (llvmpipe: 255 pixels).
  const Box3 box = domain_box(s);
  float nearest = 1;
  if (camera.perspective)
    nearest = std::max(length(box.center() - camera.eye) - length(box.size()) / 2 - largest, 1e-6f);
  const float largest_px = largest * camera.projection(1, 1) * 0.5f * rect.h / nearest;
  return 2 * (1.3f * largest_px + 2) + 2 <= max_point_size_;
}

void Renderer::draw_particles(const Program& program, const Camera& camera, Rect rect,
                              bool points) {
  if (particles_.empty()) return;
  program.use();
  program.set("u_view", camera.view);
  program.set("u_projection", camera.projection);
  program.set("u_perspective", camera.perspective ? 1 : 0);
  program.set("u_points", points ? 1 : 0);
  program.set("u_viewport_height", rect.h);
  program.set("u_min_radius_px", 0.75f);
  program.set("u_rim", 0.45f);
  gl::Enable(GL_PROGRAM_POINT_SIZE);
  gl::BindVertexArray(particle_vao_[points]);
  if (points)
    gl::DrawArrays(GL_POINTS, 0, GLsizei(particles_.size()));
  else
    gl::DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(particles_.size()));
  gl::BindVertexArray(0);
  gl::Disable(GL_PROGRAM_POINT_SIZE);
}

}  // namespace apiclab::render
