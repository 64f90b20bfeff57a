#include "render/target.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "render/gl.hpp"

namespace apiclab::render {

RenderTarget::RenderTarget(int width, int height, int samples) : width_(width), height_(height) {
  GLint max_samples = 1;
  gl::GetIntegerv(GL_MAX_SAMPLES, &max_samples);
  samples_ = std::clamp(samples, 1, int(max_samples));

  gl::GenFramebuffers(1, &msaa_fbo_);
  gl::BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_);
  gl::GenRenderbuffers(1, &color_rb_);
  gl::BindRenderbuffer(GL_RENDERBUFFER, color_rb_);
  gl::RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_RGBA8, width, height);
  gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_rb_);
  gl::GenRenderbuffers(1, &depth_rb_);
  gl::BindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
  gl::RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_DEPTH_COMPONENT24, width,
                                     height);
  gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
  if (gl::CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("multisampled framebuffer " + std::to_string(width) + "x" +
                             std::to_string(height) + " is incomplete");

  gl::GenFramebuffers(1, &resolve_fbo_);
  gl::BindFramebuffer(GL_FRAMEBUFFER, resolve_fbo_);
  gl::GenRenderbuffers(1, &resolve_rb_);
  gl::BindRenderbuffer(GL_RENDERBUFFER, resolve_rb_);
  gl::RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  gl::FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_rb_);
  if (gl::CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("resolve framebuffer is incomplete");
  bind();
}

RenderTarget::~RenderTarget() {
  gl::DeleteFramebuffers(1, &msaa_fbo_);
  gl::DeleteFramebuffers(1, &resolve_fbo_);
  unsigned rbs[] = {color_rb_, depth_rb_, resolve_rb_};
  gl::DeleteRenderbuffers(3, rbs);
}

void RenderTarget::bind() {
  gl::BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_);
  gl::Viewport(0, 0, width_, height_);
}

namespace {

// The pixels of the bound read buffer, flipped so that the top row comes first.
Image read_bound_pixels(int width, int height) {
  gl::PixelStorei(GL_PACK_ALIGNMENT, 1);
  Image image(width, height);
  std::vector<std::uint8_t> rows(image.rgba.size());
  gl::ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
  // OpenGL's first row is the bottom one.
  const std::size_t stride = std::size_t(width) * 4;
  for (int y = 0; y < height; ++y)
    std::memcpy(&image.rgba[y * stride], &rows[(height - 1 - y) * stride], stride);
  return image;
}

}  // namespace

Image read_window_pixels(int width, int height) {
  gl::BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  gl::ReadBuffer(GL_BACK);
  Image image = read_bound_pixels(width, height);
  for (std::size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 255;
  return image;
}

Image RenderTarget::read() {
  gl::BindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo_);
  gl::BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo_);
  gl::BlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
  gl::BindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo_);
  gl::ReadBuffer(GL_COLOR_ATTACHMENT0);
  Image image = read_bound_pixels(width_, height_);
  bind();
  return image;
}

}  // namespace apiclab::render
