// A multisampled offscreen framebuffer of a fixed size and its read-back to an Image.
#pragma once
#include "render/image.hpp"

namespace apiclab::render {

// The window's back buffer (framebuffer 0) as an opaque image, top row first: GUI screenshots.
Image read_window_pixels(int width, int height);

class RenderTarget {
 public:
  // Needs a current context. samples is clamped to what the driver offers (llvmpipe: 4).
  RenderTarget(int width, int height, int samples = 8);
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }
  void bind();   // draw into it
  Image read();  // resolves the samples and copies the pixels out (top row first)

 private:
  int width_, height_, samples_ = 1;
  unsigned msaa_fbo_ = 0, color_rb_ = 0, depth_rb_ = 0;
  unsigned resolve_fbo_ = 0, resolve_rb_ = 0;
};

}  // namespace apiclab::render
