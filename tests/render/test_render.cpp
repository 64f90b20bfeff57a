// Renderer tests, headless: golden images (2D and 3D), what the options change, compare
// panes, text, the offscreen backends. Run with `--backend egl|osmesa|auto` (default auto).
// Regenerate the golden images: APICLAB_REGENERATE_GOLDEN=1 ctest --test-dir BUILD -R render
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>

#include "render/auto_scale.hpp"
#include "render/context.hpp"
#include "render/figure.hpp"
#include "render/legend.hpp"
#include "render/palette.hpp"
#include "render/scene_geometry.hpp"
#include "render/target.hpp"
#include "render/text.hpp"
#include "sim/mpm/schemes/scheme_facts.hpp"
#include "sim/simulation.hpp"
#include "tests/render/render_scenes.hpp"

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
  Snapshot s = synthetic::scene_2d();
  // The synthetic scene numbers objects like materials; swap them so the two modes differ.
  for (std::int32_t& o : s.object) o = 1 - o;
  std::vector<Image> images;
  for (ColorMode m : {ColorMode::speed, ColorMode::material, ColorMode::noise, ColorMode::object}) {
    FigureStyle style;
    style.color = m;
    images.push_back(draw({&s}, style, 320, 240));
  }
  for (std::size_t a = 0; a < images.size(); ++a)
    for (std::size_t b = a + 1; b < images.size(); ++b)
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

// Framed on the particles (--fit particles), four panes in a wide canvas (a 2 x 2 grid) each
// have a frame on all four sides: the domain box, outside the frame, drew none on three.
TEST(Render, FittedPanesHaveFramesOnEverySide) {
  const Snapshot s = synthetic::scene_2d();
  FigureStyle style;
  // A frame near the domain's top right corner, where there are no particles: only the frame
  // can mark the panes' edges.
  const Box3 box = domain_box(s);
  style.frame = Box3{box.max - box.size() * 0.12f, box.max - box.size() * 0.02f};
  const int w = 1280, h = 720;
  const Image img = draw({&s, &s, &s, &s}, style, w, h);
  context().make_current();
  Renderer r;
  const std::vector<Rect> rects = figure_scene_rects(r, w, h, 4, s, style);
  ASSERT_EQ(rects.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    const Rect& q = rects[i];
    // The middle of each side, one pixel inside the rect: not paper.
    const int sides[4][2] = {{int(q.x + q.w / 2), int(q.y)},
                             {int(q.x + q.w / 2), int(q.y + q.h) - 1},
                             {int(q.x), int(q.y + q.h / 2)},
                             {int(q.x + q.w) - 1, int(q.y + q.h / 2)}};
    for (const auto& p : sides) {
      const std::uint8_t* c = img.pixel(p[0], p[1]);
      EXPECT_LT(std::min({c[0], c[1], c[2]}), 245)
          << "pane " << i << " at " << p[0] << ", " << p[1];
    }
  }
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

// The scene area of a figure: what both paths draw.
Image crop(const Image& img, const Rect& r) {
  Image c(int(r.w), int(r.h));
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      std::copy_n(img.pixel(int(r.x) + x, int(r.y) + y), 4, c.pixel(x, y));
  return c;
}

// The GUI pane path (app/gui/scene_view.cpp): scales updated from the panes, the style
// resolved for the pane's rect, the scene drawn by draw_pane_scene through the linked
// camera framed on the domain; no header or legend around it.
Image draw_like_gui(const Snapshot& s, const FigureStyle& style, Rect rect, int w, int h,
                    SceneStyle* resolved = nullptr) {
  context().make_current();
  static std::unique_ptr<Renderer> renderer;
  if (!renderer) renderer = std::make_unique<Renderer>();
  RenderTarget target(w, h);
  ScaleState scales;
  update_scales(scales, {&s});
  const SceneStyle scene = resolve_scene_style(style, {&s}, rect, scales);
  if (resolved) *resolved = scene;
  const View view = frame_view(s.dim, domain_box(s), rect.w / rect.h, style.up_axis);
  renderer->begin_frame(w, h);
  draw_pane_scene(*renderer, s, view, rect, scene);
  renderer->end_frame();
  return target.read();
}

Rect scene_rect_of(const Snapshot& s, const FigureStyle& style, int w, int h) {
  context().make_current();
  Renderer r;
  return figure_scene_rects(r, w, h, 1, s, style).front();
}

TEST(RenderPaths, GuiPaneDrawsWhatThePngDraws) {
  for (const Snapshot& s : {synthetic::scene_2d(), synthetic::scene_3d()}) {
    for (ColorMode mode : {ColorMode::speed, ColorMode::noise, ColorMode::material}) {
      FigureStyle style;
      style.color = mode;
      style.vectors = true;
      const int w = 480, h = 300;
      const Rect rect = scene_rect_of(s, style, w, h);
      const Image png = crop(draw({&s}, style, w, h), rect);
      const Image gui = crop(draw_like_gui(s, style, rect, w, h), rect);
      EXPECT_LE(differing_pixels(png, gui), long(rect.w * rect.h) / 500)
          << s.scene_name << ", colour by " << key_of(mode);
    }
  }
}

// Pixels dark enough to be arrow ink (20, 20, 20), not particles (viridis and the palette
// stay above it in some channel).
std::vector<bool> arrow_ink(const Image& img) {
  std::vector<bool> ink(std::size_t(img.width) * img.height);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      ink[std::size_t(y) * img.width + x] = std::max({p[0], p[1], p[2]}) < 60;
    }
  return ink;
}

TEST(RenderPaths, ArrowLengthDoesNotDependOnTheColourMode) {
  Snapshot s = synthetic::scene_2d();
  for (float& n : s.noise) n *= 1e-3f;  // noise far below the speeds: the old GUI rule's bug
  FigureStyle base;
  base.vectors = true;
  base.particle_scale = 0.2f;  // small particles: the arrows are what shows
  base.legend = false;         // the legend's width depends on the mode; the scene rect must not
  const int w = 480, h = 300;
  const Rect rect = scene_rect_of(s, base, w, h);
  std::vector<bool> png_ink, gui_ink;
  float vector_scale = 0;
  for (ColorMode mode :
       {ColorMode::speed, ColorMode::material, ColorMode::noise, ColorMode::object}) {
    FigureStyle style = base;
    style.color = mode;
    SceneStyle resolved;
    const std::vector<bool> gui =
        arrow_ink(crop(draw_like_gui(s, style, rect, w, h, &resolved), rect));
    const std::vector<bool> png = arrow_ink(crop(draw({&s}, style, w, h), rect));
    if (png_ink.empty()) {
      png_ink = png, gui_ink = gui, vector_scale = resolved.vector_scale;
      ASSERT_GT(std::count(png.begin(), png.end(), true), 300) << "no arrows drawn";
      continue;
    }
    EXPECT_EQ(resolved.vector_scale, vector_scale) << key_of(mode);
    long png_changed = 0, gui_changed = 0;
    for (std::size_t i = 0; i < png.size(); ++i) png_changed += png[i] != png_ink[i];
    for (std::size_t i = 0; i < gui.size(); ++i) gui_changed += gui[i] != gui_ink[i];
    EXPECT_LT(png_changed, 40) << "PNG arrows change with colour by " << key_of(mode);
    EXPECT_LT(gui_changed, 40) << "GUI arrows change with colour by " << key_of(mode);
  }
}

TEST(RenderPaths, RoundOffNoiseIsNotPaintedAsFullRange) {
  Snapshot s = synthetic::scene_2d();
  for (float& n : s.noise) n = 1e-16f;
  FigureStyle style;
  style.color = ColorMode::noise;
  const int w = 480, h = 300;
  const Rect rect = scene_rect_of(s, style, w, h);
  const Image img = crop(draw({&s}, style, w, h), rect);
  const Rgba8 low = to_rgba8(viridis(0)), high = to_rgba8(viridis(1));
  long near_low = 0, near_high = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      auto near = [&](Rgba8 c) {
        return std::abs(p[0] - c.r) < 30 && std::abs(p[1] - c.g) < 30 && std::abs(p[2] - c.b) < 30;
      };
      near_low += near(low), near_high += near(high);
    }
  EXPECT_GT(near_low, 2000) << "round-off should sit at the bottom of the scale";
  EXPECT_LT(near_high, 50) << "round-off painted as full-range signal";
  ScaleState scales;
  update_scales(scales, {&s});
  EXPECT_GE(scales.noise, kNoiseFloor * scales.speed);
}

// A scene at rest (two-cubes' first frame): round-off noise sets no scale; the first motion
// sets it, on the floor relative to the speed.
TEST(AutoScale, RestSetsNoNoiseScale) {
  Snapshot rest = synthetic::scene_2d(), moving = rest;
  for (float& v : rest.velocities) v = 0;
  for (float& n : rest.noise) n = 1e-16f;
  for (float& n : moving.noise) n = 1e-16f;
  for (ScaleHold how : {ScaleHold::grow, ScaleHold::first_frame}) {
    ScaleState s;
    s.hold = how;
    update_scales(s, {&rest});
    EXPECT_EQ(s.speed, 0);
    EXPECT_EQ(s.noise, 0) << "round-off at rest set the noise scale";
    EXPECT_EQ(color_top(s, ColorMode::noise), 1.0f);
    update_scales(s, {&moving});
    EXPECT_GT(s.speed, 0);
    EXPECT_FLOAT_EQ(s.noise, kNoiseFloor * s.speed);
  }
}

TEST(AutoScale, GrowsOrHoldsTheFirstFrame) {
  Snapshot slow = synthetic::scene_2d(), fast = slow;
  for (float& v : fast.velocities) v *= 10;
  ScaleState grow, first;
  first.hold = ScaleHold::first_frame;
  update_scales(grow, {&slow});
  update_scales(first, {&slow});
  const float initial = grow.speed;
  EXPECT_GT(initial, 0);
  EXPECT_EQ(first.speed, initial);
  update_scales(grow, {&fast});
  update_scales(first, {&fast});
  EXPECT_GE(grow.speed, 9 * initial);
  EXPECT_EQ(first.speed, initial);
  update_scales(grow, {&slow});  // never shrinks
  EXPECT_GE(grow.speed, 9 * initial);
  // A pane that blew up does not set the scales of the healthy ones.
  Snapshot blown = fast;
  blown.failure = Failure{};
  ScaleState shared;
  update_scales(shared, {&slow, &blown});
  EXPECT_EQ(shared.speed, initial);
}

// The GUI soak hung the window (every pane blown up at once, so the scales came from them):
// speeds of inf made the speed scale inf, and the colour bar's float sum of tick steps never
// passed it. Non-finite speeds now set no scale, a scale never overflows to inf, and the colour
// bar's ticks are few and finite for any top.
TEST(AutoScale, NonFiniteSpeedsSetNoScaleAndTicksStayBounded) {
  const float inf = std::numeric_limits<float>::infinity(), big = std::numeric_limits<float>::max();
  Snapshot blown = synthetic::scene_2d();
  for (float& v : blown.velocities) v = inf;
  ScaleState s;
  update_scales(s, {&blown});
  EXPECT_EQ(s.speed, 0) << "inf speeds set a scale";
  EXPECT_EQ(color_top(s, ColorMode::speed), 1.0f);
  Snapshot half = synthetic::scene_2d();
  ScaleState finite_only, reference;
  update_scales(reference, {&half});
  for (std::size_t i = 0; i < half.velocities.size(); i += 4) half.velocities[i] = std::nan("");
  update_scales(finite_only, {&half});
  EXPECT_GT(finite_only.speed, 0);
  EXPECT_LE(finite_only.speed, reference.speed) << "NaN entered the quantile";
  Snapshot huge = synthetic::scene_2d();
  for (float& v : huge.velocities) v = 3e38f;  // |v| overflows float: inf, left out
  ScaleState h;
  update_scales(h, {&huge});
  EXPECT_EQ(h.speed, 0);
  EXPECT_EQ(nice_ceil(3.3e38f), big) << "a round number above FLT_MAX is inf";
  EXPECT_EQ(nice_ceil(inf), 0);
  for (float top : {1.0f, 0.3f, 2.5f, 7.0f, 1e9f, 3e38f, big, inf, -inf, std::nanf(""), 0.0f, -1.0f,
                    1e-45f, 1e-38f}) {
    const std::vector<float> t = color_bar_ticks(top);
    EXPECT_LE(t.size(), 9u) << top;
    for (std::size_t k = 0; k < t.size(); ++k) {
      EXPECT_TRUE(std::isfinite(t[k]) && t[k] <= top * 1.0001f) << top << ": " << t[k];
      if (k > 0) {
        EXPECT_FLOAT_EQ(t[k] - t[k - 1], t[1] - t[0]) << top;
      }
    }
    if (std::isfinite(top) && top >= 1e-38f) {
      EXPECT_GE(t.size(), 2u) << top;
    }
  }
  EXPECT_EQ(color_bar_ticks(1.0f), (std::vector<float>{0, 0.2f, 0.4f, 0.6f, 0.8f, 1.0f}));
  EXPECT_TRUE(color_bar_ticks(inf).empty());
}

// Seen once (`compare --color noise` went 1, 8e-16, 1.2e-15, 0.4 over a run): a real run's
// scales, as render and compare hold them across frames, never shrink, are shared by the panes,
// and APIC's velocity noise on a rigid rotation (round-off: APIC transfers rigid motion exactly)
// sits on the floor relative to the speed scale instead of being stretched to full range.
TEST(AutoScale, RealRunScalesNeverShrinkAndRoundOffNoiseStaysOnTheFloor) {
  const SceneDesc scene =
      load_scene(std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/rotating-disk.json",
                 {"time.end=0.25", "solver.integrator=\"midpoint\""});
  SceneDesc flip = scene;
  flip.solver.scheme = Scheme::flip;
  auto apic = make_simulation(scene), noisy = make_simulation(flip);
  ScaleState shared, apic_only;
  float speed = 0, noise = 0;
  for (int f = 0; f <= 6; ++f) {
    if (f > 0) {
      for (auto* sim : {apic.get(), noisy.get()}) ASSERT_FALSE(sim->advance_to(f / 24.0));
    }
    auto a = apic->snapshot(), b = noisy->snapshot();
    apic->transfers()->fill_velocity_noise(*a);
    noisy->transfers()->fill_velocity_noise(*b);
    update_scales(shared, {a.get(), b.get()});
    update_scales(apic_only, {a.get()});
    EXPECT_GE(shared.speed, speed) << "frame " << f;
    EXPECT_GE(shared.noise, noise) << "frame " << f;
    speed = shared.speed, noise = shared.noise;
    EXPECT_GE(shared.noise, kNoiseFloor * shared.speed);
    if (f == 0) {  // APIC's initial rigid rotation: noise is round-off, the scale the floor
      float apic_noise = 0;
      for (float n : a->noise) apic_noise = std::max(apic_noise, n);
      EXPECT_LT(apic_noise, 1e-6f * apic_only.speed) << "not round-off";
      EXPECT_FLOAT_EQ(apic_only.noise, kNoiseFloor * apic_only.speed);
    }
  }
  EXPECT_GT(speed, 0);
}

TEST(Palette, OneColourPerSchemeAndCategory) {
  EXPECT_EQ(packed_abgr(scheme_color("rpic")), packed_abgr(category_color(3)));
  EXPECT_EQ(packed_abgr(scheme_color("pic")), packed_abgr(palette_color(0)));
  EXPECT_EQ(scheme_label("apic"), "APIC");
  // One spelling per scheme and method, the registry's (the GUI titled PolyPIC "POLYPIC").
  EXPECT_EQ(scheme_label("polypic"), "PolyPIC");
  EXPECT_EQ(scheme_label("eol"), "EoL");
  EXPECT_EQ(scheme_label("eulerian"), "Eulerian");
  for (const auto& c : apiclab::scheme_choices())
    EXPECT_EQ(scheme_label(c.key), apiclab::scheme_facts(c.value).name) << c.key;
  // The hex values tests/render/figures_tests.sh looks for in the figures' lines.
  auto hex = [](Rgba8 c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "%02x%02x%02x", c.r, c.g, c.b);
    return std::string(buf);
  };
  EXPECT_EQ(hex(scheme_color("pic")), "0072b2");
  EXPECT_EQ(hex(scheme_color("flip")), "d55e00");
  EXPECT_EQ(hex(scheme_color("apic")), "009e73");
  EXPECT_EQ(hex(scheme_color("rpic")), "cc79a7");
  Snapshot s;
  s.scheme = "flip";
  s.flip_alpha = 0.95;
  EXPECT_EQ(scheme_label(s), "FLIP(\u03B1=0.95)");
  s.flip_alpha = 1;  // pure FLIP: nothing to say
  EXPECT_EQ(scheme_label(s), "FLIP");
  s.scheme = "pic";
  EXPECT_EQ(scheme_label(s), "PIC");
  // Compare's pane labels name the parameter of the schemes that have one.
  s.scheme_parameters = {3, 9, 0.5};
  s.scheme = "xpic";
  EXPECT_EQ(scheme_label(s), "XPIC(3)");
  s.scheme = "polypic";
  EXPECT_EQ(scheme_label(s), "PolyPIC(9 modes)");
  s.scheme = "asflip";
  s.flip_alpha = 0.95;
  EXPECT_EQ(scheme_label(s), "ASFLIP(\u03B1=0.95 \u03B2=0.5)");
}

// A rotated 2D grid layer with a ramp field over a few particles, and its 3D counterpart.
Snapshot with_grid_layer(Snapshot s) {
  GridLayer g;
  g.name = "eol";
  g.dx = s.dim == 2 ? 0.1 : 0.12;
  g.nodes = {8, 5, s.dim == 3 ? 4 : 1};
  const double c = std::cos(0.4), sn = std::sin(0.4);
  g.rotation = {c, -sn, 0, sn, c, 0, 0, 0, 1};
  g.translation = {s.dim == 2 ? 0.9 : 0.2, 0.2, s.dim == 3 ? 0.2 : 0.0};
  GridLayer::Field ramp{"ramp", {}};
  for (std::size_t n = 0; n < g.node_count(); ++n) ramp.values.push_back(float(n % 8));
  g.fields.push_back(ramp);
  s.grids.push_back(g);
  return s;
}

// Pixel of world point p in a single-pane figure's scene rect.
Vec2 to_pixel(const Snapshot& s, const FigureStyle& style, Rect rect, Vec3 p) {
  const View v = frame_view(s.dim, domain_box(s), rect.w / rect.h, style.up_axis);
  const Camera cam = make_camera(v, rect.w / rect.h, domain_box(s));
  const Vec4 q = cam.projection * (cam.view * Vec4{p.x, p.y, p.z, 1});
  return {rect.x + (q.x / q.w * 0.5f + 0.5f) * rect.w, rect.y + (0.5f - q.y / q.w * 0.5f) * rect.h};
}

TEST(RenderGridLayers, NodesAreColouredByTheirFieldInTheGridsFrame) {
  const Snapshot plain = synthetic::scene_2d(), s = with_grid_layer(plain);
  FigureStyle style;
  style.color = ColorMode::material;
  style.grid = true;  // grid layers come with the grid (--grid, the viewer's "grid")
  const int w = 640, h = 400;
  const Rect rect = scene_rect_of(s, style, w, h);
  const Image img = draw({&s}, style, w, h);
  const GridLayer& g = s.grids.front();
  // Node (i, j) at R (dx i, dx j) + t: low ramp values purple, high ones yellow-green.
  auto node_pixel = [&](int i, int j) {
    const double x = g.dx * i, y = g.dx * j;
    return to_pixel(s, style, rect,
                    {float(g.rotation[0] * x + g.rotation[1] * y + g.translation[0]),
                     float(g.rotation[3] * x + g.rotation[4] * y + g.translation[1]), 0});
  };
  const Vec2 low = node_pixel(1, 2), high = node_pixel(6, 2);  // inside the outline
  const std::uint8_t* a = img.pixel(int(low.x), int(low.y));
  const std::uint8_t* b = img.pixel(int(high.x), int(high.y));
  EXPECT_GT(a[2], a[1]) << "the field's minimum is not at the purple end";
  EXPECT_GT(b[1], b[2]) << "the field's maximum is not at the yellow end";
  EXPECT_GT(differing_pixels(crop(img, rect), crop(draw({&plain}, style, w, h), rect)), 1500);
  // Outside the rotated grid (near the domain's top right corner) nothing changes.
  const Vec2 outside = to_pixel(s, style, rect, {1.95f, 0.95f, 0});
  const std::uint8_t* o = img.pixel(int(outside.x), int(outside.y));
  EXPECT_GT(std::min({o[0], o[1], o[2]}), 200);
}

// By default a pane shows the body, not the solver's grids: the layers draw nothing without
// the grid (an EoL pane's mass tiles hid the body, and floated around it in 3D).
TEST(RenderGridLayers, HiddenUnlessTheGridIsOn) {
  for (const Snapshot& plain : {synthetic::scene_2d(), synthetic::scene_3d()}) {
    const Snapshot s = with_grid_layer(plain);
    FigureStyle style;
    style.color = ColorMode::material;
    const int w = 480, h = 360;
    const Rect rect = scene_rect_of(s, style, w, h);
    EXPECT_EQ(differing_pixels(crop(draw({&s}, style, w, h), rect),
                               crop(draw({&plain}, style, w, h), rect)),
              0)
        << plain.dim << "D";
  }
}

// Arrows on a surface are thinned on screen: a circle of 4000 vertices (a fine EoL surface)
// draws about as much arrow ink as one of 24, not the solid ring one arrow per vertex made.
TEST(RenderSurfaceArrows, AtMostOnePerFewPixels) {
  auto ink = [](int vertices) {
    Snapshot s = synthetic::scene_2d();
    SurfaceLayer ring;
    for (int k = 0; k < vertices; ++k) {
      const float a = 6.2831853f * float(k) / float(vertices);
      ring.positions.insert(ring.positions.end(),
                            {1.0f + 0.3f * std::cos(a), 0.5f + 0.3f * std::sin(a)});
      ring.velocities.insert(ring.velocities.end(), {-std::sin(a), std::cos(a)});
    }
    s.surfaces.push_back(ring);
    FigureStyle style;
    style.color = ColorMode::material;
    style.surface = false;
    style.surface_vectors = true;
    const Image img = draw({&s}, style, 640, 400);
    const Rect r = scene_rect_of(s, style, 640, 400);  // no header or legend text
    long dark = 0;
    for (int y = int(r.y) + 2; y < int(r.y + r.h) - 2; ++y)
      for (int x = int(r.x) + 2; x < int(r.x + r.w) - 2; ++x)
        dark += std::max({img.pixel(x, y)[0], img.pixel(x, y)[1], img.pixel(x, y)[2]}) < 60;
    return dark;
  };
  const long coarse = ink(24), fine = ink(4000);  // 24: an arrow every ~20 pixels
  EXPECT_GT(coarse, 100);
  EXPECT_LT(fine, 2 * coarse) << "coarse " << coarse;
}

TEST(RenderGridLayers, ThreeDGridsAreDrawn) {
  const Snapshot plain = synthetic::scene_3d(), s = with_grid_layer(plain);
  FigureStyle style;
  style.color = ColorMode::material;
  style.grid = true;
  const int w = 480, h = 360;
  const Rect rect = scene_rect_of(s, style, w, h);
  EXPECT_GT(differing_pixels(crop(draw({&s}, style, w, h), rect),
                             crop(draw({&plain}, style, w, h), rect)),
            300);
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

TEST(SceneGeometry, PlaneInBox) {
  const Box3 unit{{0, 0, 0}, {1, 1, 1}};
  // A horizontal plane through the middle of the cube: its square cross-section.
  const std::vector<Vec3> square = plane_in_box({0.5f, 0.5f, 0.5f}, {0, 1, 0}, unit, 3);
  ASSERT_EQ(square.size(), 4u);
  for (const Vec3& c : square) EXPECT_NEAR(c.y, 0.5f, 1e-6f);
  // A diagonal plane cutting three edges at one corner: a triangle.
  EXPECT_EQ(plane_in_box({0.2f, 0, 0}, normalize(Vec3{1, 1, 1}), unit, 3).size(), 3u);
  // 2D: a slanted line crosses the square in two points; a plane outside misses it.
  const Box3 square2d{{0, 0, 0}, {2, 1, 0}};
  EXPECT_EQ(plane_in_box({0, 0.25f, 0}, normalize(Vec3{0.1f, 1, 0}), square2d, 2).size(), 2u);
  EXPECT_TRUE(plane_in_box({0, 5, 0}, {0, 1, 0}, square2d, 2).empty());
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
  // One name per process: the EGL and OSMesa builds of this test run at the same time.
  const fs::path path =
      fs::temp_directory_path() / ("apiclab-roundtrip-" + std::to_string(::getpid()) + ".png");
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
