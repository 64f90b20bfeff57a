// Renderer cost per frame: 10k and 200k particles, 2D and 3D, with and without arrows,
// drawn and read back at 1280x720 (PNG encoding timed apart).
//   render_bench [--backend auto|egl|osmesa] [--size WxH] [--frames N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "render/context.hpp"
#include "render/figure.hpp"
#include "render/target.hpp"
#include "tests/render/render_scenes.hpp"

using namespace apiclab;
using namespace apiclab::render;

int main(int argc, char** argv) {
  std::string backend = "auto";
  int width = 1280, height = 720, frames = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--backend")) backend = argv[i + 1];
    if (!std::strcmp(argv[i], "--size")) std::sscanf(argv[i + 1], "%dx%d", &width, &height);
    if (!std::strcmp(argv[i], "--frames")) frames = std::max(1, std::atoi(argv[i + 1]));
  }
  try {
    auto context = create_offscreen_context(parse_backend(backend));
    std::printf("%s, %dx%d, %d samples, median of %d frames\n", context->description().c_str(),
                width, height, RenderTarget(width, height).samples(), frames);
    RenderTarget target(width, height);
    Renderer renderer;
    std::printf("%-4s %9s %8s %12s %10s\n", "dim", "particles", "arrows", "draw ms", "PNG ms");
    using clock = std::chrono::steady_clock;
    const auto ms = [](clock::duration d) {
      return std::chrono::duration<double, std::milli>(d).count();
    };
    for (int dim : {2, 3})
      for (double count : {1e4, 2e5}) {
        const Snapshot s = dim == 2 ? synthetic::scene_2d(count) : synthetic::scene_3d(count);
        for (bool arrows : {false, true}) {
          FigureStyle style;
          style.vectors = arrows;
          FigureState state;
          std::vector<double> draw, png;
          for (int f = 0; f <= frames; ++f) {  // frame 0 warms the shader caches
            const auto t0 = clock::now();
            target.bind();
            draw_figure(renderer, width, height, {&s}, style, state);
            const Image image = target.read();
            const auto t1 = clock::now();
            write_png(image, "/tmp/apiclab-render-bench.png");
            if (f) draw.push_back(ms(t1 - t0)), png.push_back(ms(clock::now() - t1));
          }
          std::sort(draw.begin(), draw.end());
          std::sort(png.begin(), png.end());
          std::printf("%-4d %9zu %8s %12.1f %10.1f\n", dim, s.count(), arrows ? "yes" : "no",
                      draw[draw.size() / 2], png[png.size() / 2]);
        }
      }
    std::remove("/tmp/apiclab-render-bench.png");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_bench: %s\n", e.what());
    return 1;
  }
}
