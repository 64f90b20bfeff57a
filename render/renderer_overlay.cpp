// The Renderer's 2D overlay in pixels: fills, lines with arrow heads, text; end_frame draws
// them over the scene.
#include <algorithm>
#include <cmath>

#include "render/gl_upload.hpp"
#include "render/program.hpp"
#include "render/renderer.hpp"

namespace apiclab::render {

void Renderer::draw_segments(const std::vector<SegmentInstance>& segments, const Mat4& view,
                             const Mat4& projection, Vec2 viewport) {
  if (segments.empty()) return;
  upload(segment_vbo_, segments);
  segments_->use();
  segments_->set("u_view", view);
  segments_->set("u_projection", projection);
  segments_->set("u_viewport", viewport.x, viewport.y);
  gl::BindVertexArray(segment_vao_);
  gl::DrawArraysInstanced(GL_TRIANGLES, 0, 9, GLsizei(segments.size()));
  gl::BindVertexArray(0);
}

void Renderer::draw_fills(const std::vector<FillVertex>& vertices, const Mat4& matrix) {
  if (vertices.empty()) return;
  upload(fill_vbo_, vertices);
  fills_->use();
  fills_->set("u_matrix", matrix);
  gl::BindVertexArray(fill_vao_);
  gl::DrawArrays(GL_TRIANGLES, 0, GLsizei(vertices.size()));
  gl::BindVertexArray(0);
}

void Renderer::fill_rect(Rect r, Rgba8 color) {
  const Vec2 c[4] = {{r.x, r.y}, {r.x + r.w, r.y}, {r.x + r.w, r.y + r.h}, {r.x, r.y + r.h}};
  const Rgba8 colors[4] = {color, color, color, color};
  fill_quad(c, colors);
}

void Renderer::fill_quad(const Vec2 corners[4], const Rgba8 colors[4]) {
  for (int k : {0, 1, 2, 0, 2, 3})
    overlay_fills_.push_back({{corners[k].x, corners[k].y, 0}, colors[k]});
}

void Renderer::line(Vec2 a, Vec2 b, float width, Rgba8 color, float head) {
  overlay_lines_.push_back({{a.x, a.y, 0}, {b.x, b.y, 0}, color, width, head, 0});
}

Renderer::FontEntry& Renderer::font_entry(float size) {
  const int key = std::max(6, int(std::lround(size)));
  auto it = fonts_.find(key);
  if (it != fonts_.end()) return it->second;
  FontEntry& e = fonts_[key];
  e.font = std::make_unique<Font>(float(key));
  gl::GenTextures(1, &e.texture);
  gl::BindTexture(GL_TEXTURE_2D, e.texture);
  gl::PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl::TexImage2D(GL_TEXTURE_2D, 0, GL_R8, e.font->atlas_width(), e.font->atlas_height(), 0, GL_RED,
                 GL_UNSIGNED_BYTE, e.font->atlas().data());
  gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl::TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return e;
}

const Font& Renderer::font(float size) { return *font_entry(size).font; }

float Renderer::text_width(std::string_view utf8, float size) {
  return font_entry(size).font->width(utf8);
}

float Renderer::text(std::string_view utf8, float x, float y, float size, Rgba8 color,
                     float align) {
  FontEntry& e = font_entry(size);
  const float w = e.font->width(utf8);
  // Whole-pixel pen and baseline keep glyph stems sharp.
  const float x0 = std::round(x - align * w), y0 = std::round(y);
  std::vector<Font::Quad> quads;
  e.font->layout(utf8, x0, y0, quads);
  for (const Font::Quad& q : quads) {
    const TextVertex v[4] = {{q.x0, q.y0, q.s0, q.t0, color},
                             {q.x1, q.y0, q.s1, q.t0, color},
                             {q.x1, q.y1, q.s1, q.t1, color},
                             {q.x0, q.y1, q.s0, q.t1, color}};
    for (int k : {0, 1, 2, 0, 2, 3}) e.vertices.push_back(v[k]);
  }
  return w;
}

void Renderer::end_frame() {
  gl::Viewport(0, 0, width_, height_);
  gl::Disable(GL_DEPTH_TEST);
  gl::Disable(GL_SCISSOR_TEST);
  gl::Enable(GL_BLEND);
  gl::BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  // Pixel space with y down, origin at the top-left corner.
  const Mat4 pixels = ortho(0, float(width_), float(height_), 0, -1, 1);
  draw_fills(overlay_fills_, pixels);
  draw_segments(overlay_lines_, Mat4{}, pixels, {float(width_), float(height_)});
  text_->use();
  text_->set("u_viewport", float(width_), float(height_));
  text_->set("u_atlas", 0);
  gl::ActiveTexture(GL_TEXTURE0);
  for (auto& [size, e] : fonts_) {
    if (e.vertices.empty()) continue;
    upload(text_vbo_, e.vertices);
    gl::BindTexture(GL_TEXTURE_2D, e.texture);
    gl::BindVertexArray(text_vao_);
    gl::DrawArrays(GL_TRIANGLES, 0, GLsizei(e.vertices.size()));
    e.vertices.clear();
  }
  gl::BindVertexArray(0);
  overlay_lines_.clear();
  overlay_fills_.clear();
}

}  // namespace apiclab::render
