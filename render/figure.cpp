#include "render/figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "render/legend.hpp"
#include "render/palette.hpp"
#include "render/snapshot_stats.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"
#include "sim/scene/registry.hpp"

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

Layout layout(Renderer& r, int width, int height, int panes, const Snapshot& first,
              const FigureStyle& style) {
  Layout l;
  l.font =
      std::clamp(std::round(std::min(float(height), 0.75f * float(width)) / 36.0f), 9.0f, 40.0f);
  l.pad = std::round(0.6f * l.font);
  const float header = style.header ? std::round(1.7f * l.font) : 0;
  const float legend_w = style.legend ? legend_width(r, l.font, l.pad, style.color,
                                                     style.vectors || style.surface_vectors, first)
                                      : 0;
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

}  // namespace

std::string scheme_label(std::string_view key, double flip_alpha,
                         const SchemeParameters& parameters) {
  const auto& schemes = scheme_choices();
  const auto it =
      std::find_if(schemes.begin(), schemes.end(), [&](const auto& c) { return c.key == key; });
  if (it == schemes.end()) return render::scheme_label(key);
  // FLIP's blend α (eq 3), XPIC's m, PolyPIC's modes, ASFLIP's α and β
  // (sim/mpm/schemes/scheme_label.hpp).
  return with_scheme_parameter(render::scheme_label(key), it->value, flip_alpha, parameters);
}

std::string scheme_label(const Snapshot& s) {
  return scheme_label(s.scheme, s.flip_alpha, s.scheme_parameters);
}

std::vector<Rect> figure_scene_rects(Renderer& r, int width, int height, int panes,
                                     const Snapshot& first, const FigureStyle& style) {
  return layout(r, width, height, panes, first, style).scenes;
}

float draw_pane_scene(Renderer& r, const Snapshot& s, const View& view, Rect rect,
                      const SceneStyle& style) {
  const float aspect = rect.w / std::max(rect.h, 1.0f);
  const Camera camera = make_camera(view, aspect, domain_box(s));
  r.draw_scene(s, camera, rect, style);
  return s.dim == 2 ? rect.h / (2 * view.half_height)
                    : camera.projection(1, 1) * 0.5f * rect.h / view.distance;
}

void draw_figure(Renderer& r, int width, int height, const std::vector<const Snapshot*>& panes,
                 const FigureStyle& style, ScaleState& state) {
  r.begin_frame(width, height);
  if (panes.empty()) {
    r.end_frame();
    return;
  }
  const Snapshot& first = *panes.front();
  const Layout l = layout(r, width, height, int(panes.size()), first, style);
  update_scales(state, panes);
  const SceneStyle scene = resolve_scene_style(style, panes, l.scenes.front(), state);
  const float f = l.font;

  // Panes that differ in kernel or integrator (or method) each say theirs beside their label;
  // the header names them only when every pane shares them.
  const bool shared_details = std::all_of(panes.begin(), panes.end(), [&](const Snapshot* p) {
    return p->kernel == first.kernel && p->integrator == first.integrator;
  });
  float pixels_per_unit = 0;
  for (std::size_t i = 0; i < panes.size(); ++i) {
    const Snapshot& s = *panes[i];
    const Rect& rect = l.scenes[i];
    const float aspect = rect.w / std::max(rect.h, 1.0f);
    const Box3 framed = style.frame.value_or(domain_box(s));
    pixels_per_unit =
        draw_pane_scene(r, s, frame_view(s.dim, framed, aspect, style.up_axis), rect, scene);
    // Labels line up with the domain box (2D) or the pane (3D, or framed on the particles:
    // the pane's own frame).
    float left = rect.x, top = rect.y;
    if (s.dim == 2 && !style.frame) {
      const Vec3 size = framed.size();
      left = std::round(rect.x + rect.w / 2 - size.x * pixels_per_unit / 2);
      top = std::round(rect.y + rect.h / 2 - size.y * pixels_per_unit / 2);
    }
    float label_end = left;
    if (panes.size() > 1) label_end += r.text(scheme_label(s), left, top - 0.45f * f, f, kText);
    if (panes.size() > 1 && !shared_details && !s.failure) {
      const std::string details = "  " + s.kernel + " \u00B7 " + s.integrator;
      if (r.text_width(details, f) <= rect.x + rect.w - label_end - 0.6f * f)
        label_end += r.text(details, label_end, top - 0.45f * f, f, kMuted);
    }
    // Framed on the particles (--fit), the domain box may lie outside the pane: a frame of
    // its own marks where each pane ends.
    if (style.frame && panes.size() > 1) {
      const Rgba8 edge{190, 190, 190, 255};
      const float x0 = rect.x + 0.5f, y0 = rect.y + 0.5f;  // on pixel centres, inside the rect
      const float x1 = rect.x + rect.w - 0.5f, y1 = rect.y + rect.h - 0.5f;
      r.line({x0, y0}, {x1, y0}, 1, edge);
      r.line({x0, y1}, {x1, y1}, 1, edge);
      r.line({x0, y0}, {x0, y1}, 1, edge);
      r.line({x1, y0}, {x1, y1}, 1, edge);
    }
    if (s.failure) {  // once, on the label line above the domain, cut to the pane's width
      const float room = rect.x + rect.w - label_end - 0.6f * f;
      std::string what = (panes.size() > 1 ? "  " : "") + std::string("blew up at t = ") +
                         format("%.4g", s.failure->t) + ": " + s.failure->quantity;
      if (r.text_width(what, f) > room) what = what.substr(0, what.find(':'));
      if (r.text_width(what, f) <= room || panes.size() == 1)
        r.text(what, label_end, top - 0.45f * f, f, kFailure);
    }
  }

  if (style.header) {
    // Scene, scheme (one pane), kernel and integrator on the left, time on the right; the
    // details give way first when the image is narrow.
    const float baseline = std::round(0.5f * l.pad + r.font(f).ascent() + 0.2f * f);
    const std::string name = first.scene_name.empty() ? "scene" : first.scene_name;
    const std::string scheme = panes.size() == 1 ? "  " + scheme_label(first) : "";
    const std::string details = panes.size() == 1 || shared_details
                                    ? "  " + first.kernel + " \u00B7 " + first.integrator
                                    : "";
    const std::string time = "t = " + time_label(first.time, style.time_step);
    const float room = float(width) - 2 * l.pad - r.text_width(time, f) - f;
    float x = l.pad;
    x += r.text(name, x, baseline, f, kText);
    if (r.text_width(name + scheme, f) <= room) x += r.text(scheme, x, baseline, f, kText);
    if (r.text_width(name + scheme + details, f) <= room) r.text(details, x, baseline, f, kMuted);
    r.text(time, float(width) - l.pad, baseline, f, kText, 1);
  }
  if (style.legend) draw_legend(r, l.legend, l.font, l.pad, scene, first, pixels_per_unit);
  r.end_frame();
}

}  // namespace apiclab::render
