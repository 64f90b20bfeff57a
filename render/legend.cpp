#include "render/legend.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "render/auto_scale.hpp"

namespace apiclab::render {
namespace {

constexpr Rgba8 kText{30, 30, 30, 255};
constexpr Rgba8 kMuted{110, 110, 110, 255};
constexpr Rgba8 kFrame{90, 90, 90, 255};

std::string format_g(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

int object_count(const Snapshot& s) {
  int n = 0;
  for (auto o : s.object) n = std::max(n, int(o) + 1);
  return std::max(n, 1);
}

// The colour bar, top of the bar the top of the scale, with round ticks; returns its bottom.
float draw_color_bar(Renderer& r, float x, float y, float f, float height, float top) {
  const float bar_w = 0.9f * f, bar_h = std::min(0.5f * height, 14.0f * f);
  constexpr int steps = 48;
  for (int k = 0; k < steps; ++k) {
    const float y0 = y + bar_h * (1 - float(k + 1) / steps),
                y1 = y + bar_h * (1 - float(k) / steps);
    const Rgba8 c0 = to_rgba8(viridis(float(k) / steps)),
                c1 = to_rgba8(viridis(float(k + 1) / steps));
    const Vec2 q[4] = {{x, y1}, {x + bar_w, y1}, {x + bar_w, y0}, {x, y0}};
    const Rgba8 cs[4] = {c0, c0, c1, c1};
    r.fill_quad(q, cs);
  }
  r.line({x, y}, {x + bar_w, y}, 1, kFrame);
  r.line({x, y + bar_h}, {x + bar_w, y + bar_h}, 1, kFrame);
  r.line({x, y}, {x, y + bar_h}, 1, kFrame);
  r.line({x + bar_w, y}, {x + bar_w, y + bar_h}, 1, kFrame);
  for (const float v : color_bar_ticks(top)) {
    const float ty = std::round(y + bar_h * (1 - v / top)) + 0.5f;
    r.line({x + bar_w, ty}, {x + bar_w + 0.3f * f, ty}, 1, kFrame);
    r.text(format_g(v), x + bar_w + 0.45f * f, ty + 0.35f * f, f, kText);
  }
  return y + bar_h;
}

}  // namespace

std::vector<float> color_bar_ticks(float top) {
  std::vector<float> ticks;
  const float step = std::isfinite(top) ? nice_floor(top / 3.5f) : 0;
  if (!(step > 0)) return ticks;
  // Counted, not summed: a float sum of steps stalls or overflows near FLT_MAX (the GUI soak
  // hung here on a top of inf). top / step is below 8 for every step nice_floor gives.
  const int last = int(std::min(top / step * 1.0001f, 8.0f));
  for (int k = 0; k <= last; ++k) ticks.push_back(float(k) * step);
  return ticks;
}

std::string legend_title(ColorMode m) {
  switch (m) {
    case ColorMode::speed:
      return "speed |v| [m/s]";
    case ColorMode::noise:
      return "noise |v \u2212 v_PIC| [m/s]";
    case ColorMode::material:
      return "material";
    case ColorMode::object:
      return "object";
  }
  return "";
}

float legend_width(Renderer& r, float font, float pad, ColorMode color, bool vectors,
                   const Snapshot& first) {
  float content = r.text_width(legend_title(color), font);
  if (is_scalar(color)) {
    content = std::max(content, 1.4f * font + r.text_width("0.0000", font));
  } else if (color == ColorMode::material) {
    for (const std::string& name : first.material_names)
      content = std::max(content, 1.4f * font + r.text_width(name, font));
  } else {
    content = std::max(content, 1.4f * font + r.text_width("object 00", font));
    for (const std::string& name : first.object_names)
      content = std::max(content, 1.4f * font + r.text_width(name, font));
  }
  if (vectors) content = std::max(content, r.text_width("|v| = 0.000 m/s", font));
  return std::round(content + 2 * pad);
}

void draw_legend(Renderer& r, Rect area, float font, float pad, const SceneStyle& s,
                 const Snapshot& first, float pixels_per_unit) {
  const float f = font, x = area.x + pad;
  float y = area.y + f * 1.5f;
  r.text(legend_title(s.color), x, y, f, kText);
  y += 0.6f * f;
  const float bar_w = 0.9f * f;
  if (is_scalar(s.color)) {
    y = draw_color_bar(r, x, y, f, area.h, s.color_max) + 1.2f * f;
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
      // The scene's names; "material k" / "object k" only where the scene gives none.
      const std::vector<std::string>& names =
          s.color == ColorMode::material ? first.material_names : first.object_names;
      std::string name =
          k < int(names.size()) && !names[k].empty()
              ? names[k]
              : (s.color == ColorMode::material ? "material " : "object ") + std::to_string(k);
      r.text(name, x + 1.4f * f, y + 0.8f * f, f, kText);
      y += 1.2f * f;
    }
    y += 1.0f * f;
  }
  // The solver's grid layers (drawn with the grid): their field on viridis, low to high.
  if (s.grid && !first.grids.empty() && y + 4 * f <= area.y + area.h) {
    const GridLayer& g = first.grids.front();
    const GridLayer::Field* field = nullptr;
    for (const GridLayer::Field& c : g.fields)
      if (!field && (s.grid_field.empty() || c.name == s.grid_field)) field = &c;
    float low = INFINITY, high = -INFINITY;
    for (float v : field ? field->values : std::vector<float>{})
      if (std::isfinite(v)) low = std::min(low, v), high = std::max(high, v);
    if (field && low <= high) {
      r.text("grid nodes: " + field->name, x, y, f, kText);
      y += 0.5f * f;
      constexpr int steps = 24;
      const float strip_w = 5 * f, strip_h = 0.7f * f;
      for (int k = 0; k < steps; ++k)
        r.fill_rect({x + strip_w * float(k) / steps, std::round(y), std::ceil(strip_w / steps),
                     std::round(strip_h)},
                    to_rgba8(viridis((float(k) + 0.5f) / steps)));
      y += strip_h + 1.0f * f;
      char range[64];
      std::snprintf(range, sizeof range, "%.3g .. %.3g", low, high);
      r.text(range, x, y, f, kText);
      y += 1.4f * f;
    }
  }
  // The arrow key needs four lines; small images go without it.
  if ((s.vectors || s.surface_vectors) && s.vector_scale > 0 && pixels_per_unit > 0 &&
      y + 4 * f <= area.y + area.h) {
    // A reference arrow of a round speed, about four text heights long.
    const float px_per_speed = s.vector_scale * pixels_per_unit;
    const float speed = nice_floor(4 * f / px_per_speed);
    const float len = speed * px_per_speed;
    y += 0.8f * f;
    r.text("arrows", x, y, f, kText);
    y += 0.9f * f;
    // On a pixel centre and at least a pixel wide: without multisampling (the GUI under a
    // software rasterizer) a thinner line between pixel rows vanishes.
    const float lw = std::max(1.0f, f / 16), line_y = std::round(y) + 0.5f;
    r.line({x, line_y}, {x + len, line_y}, std::max(1.0f, 0.9f * lw), {20, 20, 20, 235},
           std::max(4.0f, 3.5f * lw));
    y += 1.3f * f;
    r.text("|v| = " + format_g(speed) + " m/s", x, y, f, kText);
  }
}

}  // namespace apiclab::render
