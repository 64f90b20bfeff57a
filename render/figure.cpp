#include "render/figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace apiclab::render {
namespace {

constexpr Rgba8 kText{30, 30, 30, 255};
constexpr Rgba8 kMuted{110, 110, 110, 255};
constexpr Rgba8 kFailure{200, 30, 30, 255};

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

// The largest of 1, 2, 5 (x 10^k) not above v.
float nice_floor(float v) {
  const float e = std::pow(10.0f, std::floor(std::log10(v)));
  for (float m : {5.0f, 2.0f, 1.0f})
    if (m * e <= v * 1.0001f) return m * e;
  return e;
}

float speed_of(const Snapshot& s, std::size_t i) {
  float v2 = 0;
  for (int k = 0; k < s.dim; ++k) v2 += s.velocities[i * s.dim + k] * s.velocities[i * s.dim + k];
  return std::sqrt(v2);
}

// The q-quantile of a per-particle value, on at most ~50k particles.
template <class F>
float quantile(const Snapshot& s, F value, float q) {
  const std::size_t n = s.count();
  if (n == 0) return 0;
  const std::size_t stride = std::max<std::size_t>(1, n / 50000);
  std::vector<float> v;
  for (std::size_t i = 0; i < n; i += stride) v.push_back(value(i));
  auto k = v.begin() + std::ptrdiff_t(std::min(v.size() - 1, std::size_t(q * float(v.size()))));
  std::nth_element(v.begin(), k, v.end());
  return *k;
}

float typical_radius(const Snapshot& s) {
  if (s.radius.empty()) return float(s.dx) * 0.25f;
  return quantile(
      s, [&](std::size_t i) { return s.radius[i]; }, 0.5f);
}

// Enough decimals to tell frames apart: 24 fps gives "0.042", 10 fps "0.1".
std::string time_label(double t, double step) {
  if (!(step > 0)) return format("%.4g", t);
  const double digits = -std::log10(step);
  int decimals = int(std::ceil(digits - 1e-9));
  if (std::abs(digits - std::round(digits)) > 1e-9) ++decimals;  // 1/24 needs one more
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", std::clamp(decimals, 0, 9), t);
  return buf;
}

std::string legend_title(ColorMode m) {
  switch (m) {
    case ColorMode::speed:
      return "speed |v|";
    case ColorMode::noise:
      return "noise |v \u2212 v_PIC|";
    case ColorMode::material:
      return "material";
    case ColorMode::object:
      return "object";
  }
  return "";
}

struct Layout {
  float font = 12, pad = 6;
  Rect legend;
  std::vector<Rect> panes, scenes;
};

// Width over height of the domain box as the default camera shows it.
float scene_aspect(const Snapshot& s, const Box3& box, int up_axis) {
  if (s.dim == 2) return std::max(box.size().x, 1e-6f) / std::max(box.size().y, 1e-6f);
  const View v = frame_view(3, box, 1.0f, up_axis);
  const Camera c = make_camera(v, 1.0f, box);
  float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
  for (int i = 0; i < 8; ++i) {
    Vec4 p =
        c.projection * (c.view * Vec4{i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                      i & 4 ? box.max.z : box.min.z, 1});
    for (int k = 0; k < 2; ++k) {
      float ndc = (k == 0 ? p.x : p.y) / p.w;
      lo[k] = std::min(lo[k], ndc), hi[k] = std::max(hi[k], ndc);
    }
  }
  return std::clamp((hi[0] - lo[0]) / std::max(hi[1] - lo[1], 1e-6f), 0.3f, 3.0f);
}

int object_count(const Snapshot& s) {
  int n = 0;
  for (auto o : s.object) n = std::max(n, int(o) + 1);
  return std::max(n, 1);
}

Layout layout(Renderer& r, int width, int height, int panes, const Snapshot& first,
              const FigureStyle& style) {
  Layout l;
  l.font =
      std::clamp(std::round(std::min(float(height), 0.75f * float(width)) / 36.0f), 9.0f, 40.0f);
  l.pad = std::round(0.6f * l.font);
  const float header = style.header ? std::round(1.7f * l.font) : 0;
  float legend_w = 0;
  if (style.legend) {
    float content = r.text_width(legend_title(style.color), l.font);
    if (is_scalar(style.color)) {
      content = std::max(content, 1.4f * l.font + r.text_width("0.0000", l.font));
    } else if (style.color == ColorMode::material) {
      for (const std::string& name : first.material_names)
        content = std::max(content, 1.4f * l.font + r.text_width(name, l.font));
    } else {
      content = std::max(content, 1.4f * l.font + r.text_width("object 00", l.font));
    }
    if (style.vectors) content = std::max(content, r.text_width("|v| = 0.000", l.font));
    legend_w = std::round(content + 2 * l.pad);
  }
  // Pane grid: the number of columns that shows the scene largest; scenes keep their aspect
  // and the group of panes and legend sits in the middle of the image.
  const Rect area{l.pad, header, float(width) - legend_w - 2 * l.pad,
                  float(height) - header - l.pad};
  const float aspect = scene_aspect(first, style.frame.value_or(domain_box(first)), style.up_axis);
  const float label = panes > 1 ? std::round(1.5f * l.font) : 0;
  const float gap = panes > 1 ? l.pad : 0;
  int cols = 1;
  float best = -1;
  for (int c = 1; c <= panes; ++c) {
    const int rows = (panes + c - 1) / c;
    const float w = (area.w - (c - 1) * gap) / c, h = (area.h - (rows - 1) * gap) / rows - label;
    const float scene_h = std::min(w / aspect, h);
    if (scene_h > best) best = scene_h, cols = c;
  }
  const int rows = (panes + cols - 1) / cols;
  const float sh = std::floor(std::max(best, 1.0f)),
              sw = std::floor(std::min(sh * aspect, (area.w - (cols - 1) * gap) / cols));
  const float group_w = cols * sw + (cols - 1) * gap + legend_w;
  const float group_h = rows * (sh + label) + (rows - 1) * gap;
  const float x0 = std::round(std::max(l.pad, (float(width) - group_w) / 2));
  const float y0 = std::round(header + std::max(0.0f, (area.h - group_h) / 2));
  for (int i = 0; i < panes; ++i) {
    const float x = x0 + (i % cols) * (sw + gap), y = y0 + (i / cols) * (sh + label + gap);
    l.panes.push_back({x, y, sw, sh + label});
    l.scenes.push_back({x, y + label, sw, sh});
  }
  l.legend = {x0 + cols * sw + (cols - 1) * gap, y0 + label, legend_w, float(height) - y0 - label};
  return l;
}

// Resolves the automatic parts of the style against the panes, updating the steady state.
SceneStyle resolve(const FigureStyle& style, const std::vector<const Snapshot*>& panes,
                   const Rect& scene_rect, FigureState& state) {
  SceneStyle s;
  s.color = style.color;
  s.vectors = style.vectors;
  s.grid = style.grid;
  s.box = style.box;
  s.colliders = style.colliders;
  s.particle_scale = style.particle_scale;
  s.line_px = std::max(1.0f, std::min(scene_rect.w, scene_rect.h) / 500.0f);

  // Panes that blew up would swamp the scales of the others.
  std::vector<const Snapshot*> healthy;
  for (const Snapshot* p : panes)
    if (!p->failure) healthy.push_back(p);
  if (healthy.empty()) healthy = panes;

  if (is_scalar(style.color)) {
    if (style.color_max > 0) {
      s.color_max = style.color_max;
    } else {
      float top = 0;
      for (const Snapshot* p : healthy) {
        if (style.color == ColorMode::speed)
          top = std::max(top, quantile(
                                  *p, [&](std::size_t i) { return speed_of(*p, i); }, 0.995f));
        else if (!p->noise.empty())
          top = std::max(top, quantile(
                                  *p, [&](std::size_t i) { return p->noise[i]; }, 0.995f));
      }
      state.color_max = std::max(state.color_max, nice_ceil(top));
      s.color_max = state.color_max > 0 ? state.color_max : 1;
    }
  }

  if (style.vectors) {
    const Snapshot& first = *healthy.front();
    std::size_t n = first.count();
    if (style.vector_every > 0) {
      s.vector_every = style.vector_every;
    } else {
      // About one arrow per 12 x 12 pixels of scene.
      const double budget = std::max(1.0, double(scene_rect.w) * scene_rect.h / 144.0);
      s.vector_every = int(std::max(1.0, std::ceil(double(n) / budget)));
    }
    if (style.vector_scale > 0) {
      s.vector_scale = style.vector_scale;
    } else {
      float reference = 0;
      for (const Snapshot* p : healthy)
        reference =
            std::max(reference, quantile(
                                    *p, [&](std::size_t i) { return speed_of(*p, i); }, 0.95f));
      if (reference > 0) {
        // An arrow at the reference speed spans 2.5 times the spacing between arrows.
        const float spacing = 2.5f * 2 * typical_radius(first) * style.particle_scale *
                              std::pow(float(s.vector_every), 1.0f / float(first.dim));
        const float automatic = spacing / reference;
        state.vector_scale =
            state.vector_scale > 0 ? std::min(state.vector_scale, automatic) : automatic;
      }
      s.vector_scale = state.vector_scale;
    }
  }
  return s;
}

void draw_legend(Renderer& r, const Layout& l, const SceneStyle& s, const Snapshot& first,
                 float pixels_per_unit) {
  const float f = l.font, x = l.legend.x + l.pad;
  float y = l.legend.y + f * 1.5f;
  r.text(legend_title(s.color), x, y, f, kText);
  y += 0.6f * f;
  const float bar_w = 0.9f * f;
  if (is_scalar(s.color)) {
    const float bar_h = std::min(0.5f * l.legend.h, 14.0f * f);
    constexpr int steps = 48;
    for (int k = 0; k < steps; ++k) {
      // Top of the bar is the top of the scale.
      const float y0 = y + bar_h * (1 - float(k + 1) / steps),
                  y1 = y + bar_h * (1 - float(k) / steps);
      const Rgba8 c0 = to_rgba8(viridis(float(k) / steps)),
                  c1 = to_rgba8(viridis(float(k + 1) / steps));
      const Vec2 q[4] = {{x, y1}, {x + bar_w, y1}, {x + bar_w, y0}, {x, y0}};
      const Rgba8 cs[4] = {c0, c0, c1, c1};
      r.fill_quad(q, cs);
    }
    const Rgba8 frame{90, 90, 90, 255};
    r.line({x, y}, {x + bar_w, y}, 1, frame);
    r.line({x, y + bar_h}, {x + bar_w, y + bar_h}, 1, frame);
    r.line({x, y}, {x, y + bar_h}, 1, frame);
    r.line({x + bar_w, y}, {x + bar_w, y + bar_h}, 1, frame);
    const float step = nice_floor(s.color_max / 3.5f);
    for (float v = 0; v <= s.color_max * 1.0001f; v += step) {
      const float ty = std::round(y + bar_h * (1 - v / s.color_max)) + 0.5f;
      r.line({x + bar_w, ty}, {x + bar_w + 0.3f * f, ty}, 1, frame);
      r.text(format("%g", std::round(v / step) * step), x + bar_w + 0.45f * f, ty + 0.35f * f, f,
             kText);
    }
    y += bar_h + 1.2f * f;
    if (s.color == ColorMode::noise && first.noise.empty()) {
      r.text("(not computed)", x, y, f, kMuted);
      y += 1.4f * f;
    }
  } else {
    const int n = s.color == ColorMode::material
                      ? std::max<int>(1, int(first.material_names.size()))
                      : object_count(first);
    for (int k = 0; k < n; ++k) {
      y += 0.3f * f;
      r.fill_rect({x, std::round(y), std::round(bar_w), std::round(bar_w)}, category_color(k));
      std::string name =
          s.color == ColorMode::material && k < int(first.material_names.size())
              ? first.material_names[k]
              : (s.color == ColorMode::material ? "material " : "object ") + std::to_string(k);
      r.text(name, x + 1.4f * f, y + 0.8f * f, f, kText);
      y += 1.2f * f;
    }
    y += 1.0f * f;
  }
  // The arrow key needs four lines; small images go without it.
  if (s.vectors && s.vector_scale > 0 && pixels_per_unit > 0 &&
      y + 4 * f <= l.legend.y + l.legend.h) {
    // A reference arrow of a round speed, about four text heights long.
    const float px_per_speed = s.vector_scale * pixels_per_unit;
    const float speed = nice_floor(4 * f / px_per_speed);
    const float len = speed * px_per_speed;
    y += 0.8f * f;
    r.text("arrows", x, y, f, kText);
    y += 0.9f * f;
    const float lw = std::max(1.0f, f / 16);
    r.line({x, y}, {x + len, y}, 0.9f * lw, {20, 20, 20, 235}, std::max(4.0f, 3.5f * lw));
    y += 1.3f * f;
    r.text("|v| = " + format("%g", speed), x, y, f, kText);
  }
}

}  // namespace

float nice_ceil(float v) {
  if (!(v > 0)) return 0;
  const float e = std::pow(10.0f, std::floor(std::log10(v)));
  for (float m : {1.0f, 1.2f, 1.5f, 2.0f, 2.5f, 3.0f, 4.0f, 5.0f, 6.0f, 8.0f, 10.0f})
    if (m * e >= v * 0.9999f) return m * e;
  return 10 * e;
}

std::string scheme_label(const Snapshot& s) {
  std::string label;
  for (char c : s.scheme) label += char(std::toupper(static_cast<unsigned char>(c)));
  if (s.scheme == "flip" && s.flip_alpha < 1) label += " \u03B1=" + format("%g", s.flip_alpha);
  return label;
}

std::vector<Rect> figure_scene_rects(Renderer& r, int width, int height, int panes,
                                     const Snapshot& first, const FigureStyle& style) {
  return layout(r, width, height, panes, first, style).scenes;
}

void draw_figure(Renderer& r, int width, int height, const std::vector<const Snapshot*>& panes,
                 const FigureStyle& style, FigureState& state, const View* view) {
  r.begin_frame(width, height);
  if (panes.empty()) {
    r.end_frame();
    return;
  }
  const Snapshot& first = *panes.front();
  const Layout l = layout(r, width, height, int(panes.size()), first, style);
  const SceneStyle scene = resolve(style, panes, l.scenes.front(), state);
  const float f = l.font;

  float pixels_per_unit = 0;
  for (std::size_t i = 0; i < panes.size(); ++i) {
    const Snapshot& s = *panes[i];
    const Rect& rect = l.scenes[i];
    const float aspect = rect.w / std::max(rect.h, 1.0f);
    const Box3 framed = style.frame.value_or(domain_box(s));
    View v = view ? *view : frame_view(s.dim, framed, aspect, style.up_axis);
    const Camera camera = make_camera(v, aspect, domain_box(s));
    pixels_per_unit = s.dim == 2 ? rect.h / (2 * v.half_height)
                                 : camera.projection(1, 1) * 0.5f * rect.h / v.distance;
    r.draw_scene(s, camera, rect, scene);
    // Labels line up with the domain box (2D) or the pane (3D).
    float left = rect.x, top = rect.y, bottom = rect.y + rect.h;
    if (s.dim == 2 && !view) {
      const Vec3 size = framed.size();
      left = std::round(rect.x + rect.w / 2 - size.x * pixels_per_unit / 2);
      top = std::round(rect.y + rect.h / 2 - size.y * pixels_per_unit / 2);
      bottom = std::round(rect.y + rect.h / 2 + size.y * pixels_per_unit / 2);
    }
    if (panes.size() > 1) r.text(scheme_label(s), left, top - 0.45f * f, f, kText);
    if (s.failure) {
      const std::string what =
          "stopped at t = " + format("%.4g", s.failure->t) + ": " + s.failure->quantity;
      const float w = r.text_width(what, f);
      r.fill_rect({left + 0.3f * f, bottom - 1.9f * f, w + 0.8f * f, 1.5f * f},
                  {255, 255, 255, 215});
      r.text(what, left + 0.7f * f, bottom - 0.85f * f, f, kFailure);
    }
  }

  if (style.header) {
    // Scene, scheme (one pane), kernel and integrator on the left, time on the right; the
    // details give way first when the image is narrow.
    const float baseline = std::round(0.5f * l.pad + r.font(f).ascent() + 0.2f * f);
    const std::string name = first.scene_name.empty() ? "scene" : first.scene_name;
    const std::string scheme = panes.size() == 1 ? "  " + scheme_label(first) : "";
    const std::string details = "  " + first.kernel + " \u00B7 " + first.integrator;
    const std::string time = "t = " + time_label(first.time, style.time_step);
    const float room = float(width) - 2 * l.pad - r.text_width(time, f) - f;
    float x = l.pad;
    x += r.text(name, x, baseline, f, kText);
    if (r.text_width(name + scheme, f) <= room) x += r.text(scheme, x, baseline, f, kText);
    if (r.text_width(name + scheme + details, f) <= room) r.text(details, x, baseline, f, kMuted);
    r.text(time, float(width) - l.pad, baseline, f, kText, 1);
  }
  if (style.legend) draw_legend(r, l, scene, first, pixels_per_unit);
  r.end_frame();
}

}  // namespace apiclab::render
