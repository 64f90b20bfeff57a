// RGBA8 images in memory, PNG files, and the per-pixel comparison behind golden tests.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace apiclab::render {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // rows top to bottom
  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(std::size_t(w) * h * 4, 0) {}
  std::uint8_t* pixel(int x, int y) { return &rgba[(std::size_t(y) * width + x) * 4]; }
  const std::uint8_t* pixel(int x, int y) const { return &rgba[(std::size_t(y) * width + x) * 4]; }
};

// Throws std::runtime_error naming the file.
void write_png(const Image& image, const std::string& path);
Image read_png(const std::string& path);

struct ImageDifference {
  long differing_pixels = 0;  // pixels whose largest channel difference exceeds the tolerance
  int largest = 0;            // largest channel difference anywhere
  Image visual;               // the reference greyed out, differing pixels in red: what to look at
};
// Sizes must match (otherwise every pixel differs).
ImageDifference compare_images(const Image& reference, const Image& actual, int tolerance);

}  // namespace apiclab::render
