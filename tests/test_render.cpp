// Renderer tests, headless: golden images (2D and 3D), what the options change, compare
// panes, text, the offscreen backends. Run with `--backend egl|osmesa|auto` (default auto).
// Regenerate the golden images: APICLAB_REGENERATE_GOLDEN=1 ctest --test-dir BUILD -R render
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "render/context.hpp"
#include "render/figure.hpp"
#include "render/target.hpp"
#include "render/text.hpp"
#include "render_scenes.hpp"

namespace {

using namespace apiclab;
using namespace apiclab::render;
namespace fs = std::filesystem;

std::string g_backend = "auto";

// One context for the whole test program, made on first use.
OffscreenContext& context() {
  static std::unique_ptr<OffscreenContext> c = create_offscreen_context(parse_backend(g_backend));
  return *c;
}

Image draw(const std::vector<const Snapshot*>& panes, const FigureStyle& style, int w = 160,
           int h = 120) {
  context().make_current();
  static std::unique_ptr<Renderer> renderer;
  if (!renderer) renderer = std::make_unique<Renderer>();
  RenderTarget target(w, h);
  FigureState state;
  draw_figure(*renderer, w, h, panes, style, state);
  return target.read();
}

long differing_pixels(const Image& a, const Image& b) {
  return compare_images(a, b, 24).differing_pixels;
}

// Differs from the golden image by at most `tolerance` per channel in all but 0.5% of the
// pixels: llvmpipe builds may round an edge differently, a real change moves far more.
void expect_matches_golden(const Image& actual, const std::string& name) {
  long inked = 0;  // a blank frame must never become a golden image
  for (std::size_t i = 0; i < actual.rgba.size(); i += 4) inked += actual.rgba[i] < 200;
  ASSERT_GT(inked, long(actual.width) * actual.height / 20) << name << " is nearly blank";
  const fs::path golden = fs::path(APICLAB_SOURCE_DIR) / "tests" / "golden" / (name + ".png");
  if (std::getenv("APICLAB_REGENERATE_GOLDEN")) {
    write_png(actual, golden.string());
    std::printf("regenerated %s\n", golden.c_str());
    return;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing; regenerate with "
                                  << "APICLAB_REGENERATE_GOLDEN=1 ctest -R render";
  const Image reference = read_png(golden.string());
  const ImageDifference d = compare_images(reference, actual, 24);
  const long allowed = long(reference.width) * reference.height / 200;
  if (d.differing_pixels > allowed) {
    const fs::path dir = fs::path(APICLAB_BINARY_DIR) / "render-diff";
    fs::create_directories(dir);
    write_png(actual, (dir / (name + "-" + g_backend + "-actual.png")).string());
    write_png(d.visual, (dir / (name + "-" + g_backend + "-diff.png")).string());
    ADD_FAILURE() << name << ": " << d.differing_pixels << " pixels differ (allowed " << allowed
                  << ", largest channel difference " << d.largest << "); see "
                  << (dir / (name + "-" + g_backend + "-diff.png")) << "; if the change is "
                  << "intended: APICLAB_REGENERATE_GOLDEN=1 ctest -R render";
  }
}

TEST(RenderGolden, Scene2D) {
  const Snapshot s = synthetic::scene_2d();
  FigureStyle style;
  style.vectors = true;
  style.grid = true;
  expect_matches_golden(draw({&s}, style), "render_2d");
}

TEST(RenderGolden, Scene3D) {
  const Snapshot s = synthetic::scene_3d();
  FigureStyle style;
  style.color = ColorMode::material;
  expect_matches_golden(draw({&s}, style), "render_3d");
}

TEST(Render, BackendIsTheOneAskedFor) {
  const std::string d = context().description();
  if (g_backend == "egl") {
    EXPECT_EQ(d.rfind("EGL", 0), 0u) << d;
  } else if (g_backend == "osmesa") {
    EXPECT_EQ(d.rfind("OSMesa", 0), 0u) << d;
  }
  EXPECT_NE(d.find("OpenGL"), std::string::npos) << d;
}

TEST(Render, VectorsChangeTheImage) {
  for (const Snapshot& s : {synthetic::scene_2d(), synthetic::scene_3d()}) {
    FigureStyle plain, arrows;
    arrows.vectors = true;
    EXPECT_GT(differing_pixels(draw({&s}, plain, 320, 240), draw({&s}, arrows, 320, 240)), 500)
        << s.scene_name;
  }
}

TEST(Render, ColorModesDiffer) {
  const Snapshot s = synthetic::scene_2d();
  std::vector<Image> images;
  for (ColorMode m : {ColorMode::speed, ColorMode::material, ColorMode::noise, ColorMode::object}) {
    FigureStyle style;
    style.color = m;
    images.push_back(draw({&s}, style, 320, 240));
  }
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t b = a + 1; b < 3; ++b)
      EXPECT_GT(differing_pixels(images[a], images[b]), 1000) << "modes " << a << " and " << b;
}

// Counts pixels inside r that are neither white nor grey: particle colours.
long coloured_pixels(const Image& img, const Rect& r) {
  long n = 0;
  for (int y = int(r.y); y < int(r.y + r.h); ++y)
    for (int x = int(r.x); x < int(r.x + r.w); ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      const int spread = std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]});
      n += spread > 40;
    }
  return n;
}

TEST(Render, CompareDrawsOnePanePerScheme) {
  Snapshot pic = synthetic::scene_2d(), flip = pic, apic = pic;
  pic.scheme = "pic";
  apic.scheme = "apic";
  // PIC's pane: every particle at rest, so its colours differ from the others'.
  for (float& v : pic.velocities) v = 0;
  const int w = 480, h = 160;
  FigureStyle style;
  const Image img = draw({&pic, &flip, &apic}, style, w, h);
  context().make_current();
  Renderer r;
  const std::vector<Rect> rects = figure_scene_rects(r, w, h, 3, pic, style);
  ASSERT_EQ(rects.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_GT(rects[i].w, 80) << i;
    if (i > 0) {
      EXPECT_GE(rects[i].x, rects[i - 1].x + rects[i - 1].w) << "panes overlap";
    }
    EXPECT_GT(coloured_pixels(img, rects[i]), 300) << "pane " << i << " has no particles";
  }
  // Each pane is labelled: dark text pixels in the band above it.
  for (const Rect& rect : rects) {
    long dark = 0;
    for (int y = std::max(0, int(rect.y) - 14); y < int(rect.y); ++y)
      for (int x = int(rect.x); x < int(rect.x + 40); ++x) dark += img.pixel(x, y)[0] < 128;
    EXPECT_GT(dark, 10) << "no label above the pane at x = " << rect.x;
  }
  // PIC at rest against FLIP in motion: the panes differ.
  const auto crop = [&](const Rect& r) {
    Image c(int(r.w), int(r.h));
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x)
        std::copy_n(img.pixel(int(r.x) + x, int(r.y) + y), 4, c.pixel(x, y));
    return c;
  };
  const Rect a{rects[0].x, rects[0].y, std::min(rects[0].w, rects[1].w), rects[0].h};
  const Rect b{rects[1].x, rects[1].y, a.w, a.h};
  EXPECT_GT(differing_pixels(crop(a), crop(b)), 300);
}

TEST(Render, LargeParticlesBecomeQuads) {
  // One particle larger than any point sprite: drawn through the instanced-quad path.
  Snapshot s = synthetic::scene_2d(10);
  s.positions = {1.0f, 0.5f};
  s.velocities = {0.0f, 0.0f};
  s.material = {0};
  s.object = {0};
  s.noise = {0};
  s.radius = {0.45f};
  FigureStyle style;
  style.color = ColorMode::material;
  const Image img = draw({&s}, style, 1600, 900);
  context().make_current();
  Renderer r;
  const Rect scene = figure_scene_rects(r, 1600, 900, 1, s, style).front();
  const std::uint8_t* center = img.pixel(int(scene.x + scene.w / 2), int(scene.y + scene.h / 2));
  const Rgba8 blue = category_color(0);
  EXPECT_NEAR(center[0], blue.r, 4);
  EXPECT_NEAR(center[2], blue.b, 4);
  // A disc of radius ~300 pixels: far more than the largest point sprite (255 wide) covers.
  EXPECT_GT(coloured_pixels(img, scene), 200000);
}

TEST(Render, TextComesFromTheFont) {
  Font font(20);
  EXPECT_GT(font.width("W"), 1.5f * font.width("i"));              // proportional, not a fixed grid
  EXPECT_LT(font.width("AV"), font.width("A") + font.width("V"));  // kerning
  EXPECT_GT(font.width("α=0.95"), 0);
  // Antialiased glyphs: many grey levels between paper and ink.
  FigureStyle style;
  const Snapshot s = synthetic::scene_2d();
  const Image img = draw({&s}, style, 640, 360);
  std::vector<bool> levels(256);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 200; ++x) levels[img.pixel(x, y)[0]] = true;
  EXPECT_GT(std::count(levels.begin(), levels.end(), true), 30);
}

TEST(Render, UnknownKeysAreRejected) {
  EXPECT_THROW(parse_backend("vulkan"), std::invalid_argument);
  EXPECT_THROW(parse_color_mode("rainbow"), std::invalid_argument);
  EXPECT_EQ(parse_color_mode("noise"), ColorMode::noise);
}

TEST(Image, ComparisonToleratesSmallDifferences) {
  Image a(10, 10), b(10, 10);
  b.pixel(3, 3)[0] = 20;   // within tolerance
  b.pixel(5, 5)[1] = 200;  // a real difference
  const ImageDifference d = compare_images(a, b, 24);
  EXPECT_EQ(d.differing_pixels, 1);
  EXPECT_EQ(d.largest, 200);
  EXPECT_EQ(d.visual.pixel(5, 5)[0], 255);
  EXPECT_EQ(compare_images(a, Image(5, 5), 24).differing_pixels, 100);
}

TEST(Image, PngRoundTrip) {
  Image a(7, 5);
  for (std::size_t i = 0; i < a.rgba.size(); ++i) a.rgba[i] = std::uint8_t(i * 37);
  const fs::path path = fs::temp_directory_path() / "apiclab-roundtrip.png";
  write_png(a, path.string());
  const Image b = read_png(path.string());
  EXPECT_EQ(b.rgba, a.rgba);
  fs::remove(path);
  EXPECT_THROW(write_png(a, "/nonexistent-dir/x.png"), std::runtime_error);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--backend") g_backend = argv[i + 1];
  return RUN_ALL_TESTS();
}
