// Checks a GUI screenshot: not blank, and each pane rect (lines "pane K: x y w h" on stdin)
// holds particles, i.e. enough saturated colormap pixels (background, boxes and text are grey).
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <set>
#include <string>

#include "render/image.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: gui_screenshot_check FILE.png PANES < pane-lines\n");
    return 2;
  }
  const auto img = apiclab::render::read_png(argv[1]);
  const int expected = std::stoi(argv[2]);
  std::set<unsigned> colors;
  for (std::size_t i = 0; i < img.rgba.size(); i += 4 * 7)
    colors.insert(unsigned(img.rgba[i]) << 16 | unsigned(img.rgba[i + 1]) << 8 | img.rgba[i + 2]);
  std::printf("%dx%d, %zu distinct colors (sampled)\n", img.width, img.height, colors.size());
  int failures = colors.size() < 50 ? 1 : 0;
  int panes = 0;
  for (std::string line; std::getline(std::cin, line);) {
    int k, x, y, w, h;
    if (std::sscanf(line.c_str(), "pane %d: %d %d %d %d", &k, &x, &y, &w, &h) != 5) continue;
    ++panes;
    long saturated = 0;
    for (int py = y; py < y + h && py < img.height; ++py)
      for (int px = x; px < x + w && px < img.width; ++px) {
        const auto* p = img.pixel(px, py);
        const int hi = std::max({p[0], p[1], p[2]}), lo = std::min({p[0], p[1], p[2]});
        saturated += hi - lo > 50;
      }
    const bool ok = saturated > 2000;
    std::printf("pane %d (%d,%d %dx%d): %ld particle pixels%s\n", k, x, y, w, h, saturated,
                ok ? "" : "  <- EMPTY");
    failures += !ok;
  }
  if (panes != expected) {
    std::printf("expected %d panes, found %d\n", expected, panes);
    ++failures;
  }
  std::printf(failures ? "FAIL\n" : "OK\n");
  return failures ? 1 : 0;
}
