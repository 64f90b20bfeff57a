// Checks a figure PNG: at least the given size, not blank (enough non-white pixels and
// colors), and each listed color (a scheme's line, e.g. 0072b2) present on enough pixels.
// Usage: figures_png_check FILE.png MIN_W MIN_H [RRGGBB ...]
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>

#include "render/image.hpp"

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: figures_png_check FILE.png MIN_W MIN_H [RRGGBB ...]\n");
    return 2;
  }
  apiclab::render::Image img;
  try {
    img = apiclab::render::read_png(argv[1]);
  } catch (const std::exception& e) {
    std::printf("%s\nFAIL\n", e.what());
    return 1;
  }
  int failures = 0;
  if (img.width < std::atoi(argv[2]) || img.height < std::atoi(argv[3])) {
    std::printf("%s: %dx%d, smaller than %sx%s\n", argv[1], img.width, img.height, argv[2],
                argv[3]);
    ++failures;
  }
  long ink = 0;
  std::set<unsigned> colors;
  for (std::size_t i = 0; i + 3 < img.rgba.size(); i += 4) {
    const unsigned r = img.rgba[i], g = img.rgba[i + 1], b = img.rgba[i + 2];
    ink += r + g + b < 3 * 235;
    colors.insert(r << 16 | g << 8 | b);
  }
  const long pixels = long(img.width) * img.height;
  std::printf("%s: %dx%d, %.1f%% ink, %zu colors\n", argv[1], img.width, img.height,
              100.0 * ink / pixels, colors.size());
  if (ink < pixels / 200 || colors.size() < 50) {
    std::printf("  blank\n");
    ++failures;
  }
  for (int k = 4; k < argc; ++k) {
    const unsigned c = unsigned(std::strtoul(argv[k], nullptr, 16));
    const int cr = c >> 16 & 255, cg = c >> 8 & 255, cb = c & 255;
    long n = 0;
    for (std::size_t i = 0; i + 3 < img.rgba.size(); i += 4)
      n += std::abs(img.rgba[i] - cr) + std::abs(img.rgba[i + 1] - cg) +
               std::abs(img.rgba[i + 2] - cb) <
           40;
    std::printf("  #%s: %ld pixels%s\n", argv[k], n, n >= 30 ? "" : "  <- MISSING");
    failures += n < 30;
  }
  std::printf(failures ? "FAIL\n" : "OK\n");
  return failures ? 1 : 0;
}
