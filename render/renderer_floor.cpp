// The Renderer's 3D floor: a plane under the bodies, shaded by the particles' soft shadow.
#include <algorithm>
#include <cmath>

#include "render/gl_upload.hpp"
#include "render/program.hpp"
#include "render/renderer.hpp"
#include "render/scene_geometry.hpp"

namespace apiclab::render {
namespace {
constexpr Rgba8 kFloor{238, 238, 236, 255};
}  // namespace

void Renderer::draw_floor(const Box3& box, int up, const Mat4& view_projection, Rect rect) {
  const int a1 = (up + 1) % 3, a2 = (up + 2) % 3;
  constexpr int kMap = 128;  // shadow map side: soft shadows come from its coarseness
  GLint previous = 0;        // the caller's framebuffer (ours, or the GUI's window)
  gl::GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous);
  if (!shadow_texture_) {
    gl::GenTextures(1, &shadow_texture_);
    gl::BindTexture(GL_TEXTURE_2D, shadow_texture_);
    gl::TexImage2D(GL_TEXTURE_2D, 0, GL_R8, kMap, kMap, 0, GL_RED, GL_UNSIGNED_BYTE, nullptr);
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl::GenFramebuffers(1, &shadow_fbo_);
    gl::BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
    gl::FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, shadow_texture_,
                             0);
  }
  // 1. The shadow map: the particles seen from straight above, u along a1 and v along a2.
  gl::BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
  gl::Viewport(0, 0, kMap, kMap);
  gl::Disable(GL_SCISSOR_TEST);
  gl::Disable(GL_DEPTH_TEST);
  gl::ClearColor(0, 0, 0, 0);
  gl::Clear(GL_COLOR_BUFFER_BIT);
  const Vec3 c = box.center(), size = box.size();
  Camera top;  // rows pick the world axes a1, a2, up; the map's far side is the floor
  top.view(0, 0) = top.view(1, 1) = top.view(2, 2) = 0;
  top.view(0, a1) = 1, top.view(0, 3) = -c[a1];
  top.view(1, a2) = 1, top.view(1, 3) = -c[a2];
  top.view(2, up) = 1, top.view(2, 3) = -(box.max[up] + 1);
  top.projection =
      ortho(-size[a1] / 2, size[a1] / 2, -size[a2] / 2, size[a2] / 2, 0.5f, size[up] + 2);
  const float map_px = largest_radius_ * kMap / std::max(std::min(size[a1], size[a2]), 1e-6f);
  gl::BlendEquation(GL_MAX);
  shadow_map_->use();
  shadow_map_->set("u_flatten_axis", up);
  shadow_map_->set("u_flatten_to", box.min[up]);
  shadow_map_->set("u_radius_scale", 1.2f);
  shadow_map_->set("u_shadow_reach", std::max(size[up], 1e-6f));
  draw_particles(*shadow_map_, top, {0, 0, float(kMap), float(kMap)},
                 2 * (1.6f * map_px + 2) + 2 <= max_point_size_);
  gl::BlendEquation(GL_FUNC_ADD);
  gl::BindFramebuffer(GL_FRAMEBUFFER, GLuint(previous));
  set_viewport(rect);
  gl::Enable(GL_DEPTH_TEST);

  // 2. The floor face, darkened where the map says.
  Vec3 q[4];
  for (int k = 0; k < 4; ++k) {
    q[k][up] = box.min[up];
    q[k][a1] = (k == 1 || k == 2) ? box.max[a1] : box.min[a1];
    q[k][a2] = (k >= 2) ? box.max[a2] : box.min[a2];
  }
  std::vector<FillVertex> floor;
  for (int k : {0, 1, 2, 0, 2, 3}) floor.push_back({q[k], kFloor});
  upload(fill_vbo_, floor);
  Vec3 axis_u, axis_v;
  axis_u[a1] = 1 / std::max(size[a1], 1e-12f);
  axis_v[a2] = 1 / std::max(size[a2], 1e-12f);
  floor_->use();
  floor_->set("u_matrix", view_projection);
  floor_->set("u_shadow", 0);
  floor_->set("u_origin", box.min);
  floor_->set("u_axis_u", axis_u);
  floor_->set("u_axis_v", axis_v);
  floor_->set("u_texel", 1.0f / kMap);
  gl::ActiveTexture(GL_TEXTURE0);
  gl::BindTexture(GL_TEXTURE_2D, shadow_texture_);
  gl::BindVertexArray(fill_vao_);
  gl::DrawArrays(GL_TRIANGLES, 0, 6);
  gl::BindVertexArray(0);
}

}  // namespace apiclab::render
