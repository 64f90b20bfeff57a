#include "app/gui/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace apiclab::gui {
namespace {

constexpr ImU32 kFrame = IM_COL32(150, 150, 150, 255);
constexpr ImU32 kGrid = IM_COL32(225, 225, 225, 255);
constexpr ImU32 kText = IM_COL32(40, 40, 40, 255);
constexpr ImU32 kMuted = IM_COL32(100, 100, 100, 255);

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  bool valid() const { return lo <= hi; }
  void add(double v) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
};

// `text`, or as much of it as fits in `width` pixels followed by "...".
std::string fit_text(const std::string& text, float width) {
  if (ImGui::CalcTextSize(text.c_str()).x <= width) return text;
  std::string cut = text;
  while (!cut.empty() && ImGui::CalcTextSize((cut + "...").c_str()).x > width) cut.pop_back();
  return cut + "...";
}

// The legend band's entries, flowing left to right in rows between `left` and `right` from
// `top`, in at most `max_h` pixels; entries that do not fit are counted in "+N more".
struct LegendEntry {
  std::size_t series;
  std::string text;
  ImVec2 at;
};
struct LegendLayout {
  float bottom;  // of the band (top when empty)
  std::vector<LegendEntry> entries;
  std::string more;
  ImVec2 more_at;
};

LegendLayout layout_legend(const std::vector<PlotSeries>& series, float left, float right,
                           float top, float max_h) {
  const float fh = ImGui::GetFontSize(), row_h = fh + 3, gap = 14, sample = 24;
  const int rows = std::max(1, int(max_h / row_h));
  LegendLayout lay{top, {}, {}, {}};
  float x = left;
  int row = 0;
  std::size_t listed = 0, wanted = 0;
  for (std::size_t k = 0; k < series.size(); ++k) {
    if (series[k].label.empty()) continue;
    ++wanted;
    const std::string text = fit_text(series[k].label, std::max(right - left - sample, 20.0f));
    const float w = sample + ImGui::CalcTextSize(text.c_str()).x;
    if (x > left && x + w > right) x = left, ++row;
    if (row >= rows) break;
    lay.entries.push_back({k, text, ImVec2(x, top + row * row_h)});
    x += w + gap, ++listed;
  }
  if (listed < wanted) {  // "+N more" at the end of the last row, in place of entries if need be
    auto more = [&] { return "+" + std::to_string(wanted - lay.entries.size()) + " more"; };
    while (!lay.entries.empty() && lay.entries.back().at.y == top + (rows - 1) * row_h &&
           lay.entries.back().at.x + sample +
                   ImGui::CalcTextSize(lay.entries.back().text.c_str()).x + gap +
                   ImGui::CalcTextSize(more().c_str()).x >
               right)
      lay.entries.pop_back();
    const LegendEntry* last = lay.entries.empty() ? nullptr : &lay.entries.back();
    lay.more = more();
    lay.more_at =
        last ? ImVec2(last->at.x + sample + ImGui::CalcTextSize(last->text.c_str()).x + gap,
                      last->at.y)
             : ImVec2(left, top);
  }
  if (!lay.entries.empty() || !lay.more.empty())
    lay.bottom =
        top +
        (lay.entries.empty() ? 1 : int(lay.entries.back().at.y - top) / int(row_h) + 1) * row_h;
  return lay;
}

// Axis ends stay within ±1e300 (log axes: decades −300 … 300), so that padding, spans and the
// legend's room never overflow to inf or underflow to 0.
constexpr double kMaxDecade = 300, kMaxMagnitude = 1e300;

// A readable range around the data: padded, never empty (a constant series sits mid-plot).
Range pad(Range r, bool log) {
  if (!r.valid()) return log ? Range{1e-16, 1} : Range{0, 1};
  if (log) {  // decades inside double's normal range: a denormal's padding would reach 0
    double lo = std::log10(r.lo), hi = std::log10(r.hi);
    if (hi - lo < 1) lo = (lo + hi) / 2 - 0.5, hi = lo + 1;
    const double margin = 0.05 * (hi - lo);
    return {std::pow(10.0, std::max(lo - margin, -kMaxDecade)),
            std::pow(10.0, std::min(hi + margin, kMaxDecade))};
  }
  if (r.lo == 0 && r.hi == 0) return {-1, 1};  // all zero (round-off momenta): a plain 0 line
  r.lo = std::clamp(r.lo, -kMaxMagnitude, kMaxMagnitude);
  r.hi = std::clamp(r.hi, -kMaxMagnitude, kMaxMagnitude);
  double span = r.hi - r.lo;
  if (span <= 1e-12 * std::max(std::abs(r.lo), std::abs(r.hi)) || span == 0) {
    const double half = std::max(std::abs(r.lo) * 1e-3, 1e-12);
    return {r.lo - half, r.hi + half};
  }
  return {r.lo - 0.06 * span, r.hi + 0.06 * span};
}

}  // namespace

void draw_marker(ImDrawList* dl, ImVec2 c, float r, Marker m, ImU32 color) {
  const float t = std::max(1.5f, 0.45f * r);
  switch (m) {
    case Marker::circle:
      dl->AddCircleFilled(c, r, color, 12);
      break;
    case Marker::square:
      dl->AddRectFilled(ImVec2(c.x - 0.85f * r, c.y - 0.85f * r),
                        ImVec2(c.x + 0.85f * r, c.y + 0.85f * r), color);
      break;
    case Marker::triangle:
      dl->AddTriangleFilled(ImVec2(c.x, c.y - 1.15f * r), ImVec2(c.x + r, c.y + 0.7f * r),
                            ImVec2(c.x - r, c.y + 0.7f * r), color);
      break;
    case Marker::triangle_down:
      dl->AddTriangleFilled(ImVec2(c.x, c.y + 1.15f * r), ImVec2(c.x - r, c.y - 0.7f * r),
                            ImVec2(c.x + r, c.y - 0.7f * r), color);
      break;
    case Marker::diamond:
      dl->AddQuadFilled(ImVec2(c.x, c.y - 1.2f * r), ImVec2(c.x + 1.2f * r, c.y),
                        ImVec2(c.x, c.y + 1.2f * r), ImVec2(c.x - 1.2f * r, c.y), color);
      break;
    case Marker::plus:
      dl->AddLine(ImVec2(c.x - 1.2f * r, c.y), ImVec2(c.x + 1.2f * r, c.y), color, t);
      dl->AddLine(ImVec2(c.x, c.y - 1.2f * r), ImVec2(c.x, c.y + 1.2f * r), color, t);
      break;
    case Marker::cross:
      dl->AddLine(ImVec2(c.x - r, c.y - r), ImVec2(c.x + r, c.y + r), color, t);
      dl->AddLine(ImVec2(c.x - r, c.y + r), ImVec2(c.x + r, c.y - r), color, t);
      break;
    case Marker::ring:
      dl->AddCircle(c, r, color, 12, t);
      break;
  }
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> out;
  if (!(hi > lo) || !std::isfinite(hi - lo) || target < 1 || target > 64) return out;
  const double raw = (hi - lo) / target, mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  // Counted from the first multiple of the step, not summed: where the step is below the
  // values' spacing (hi and lo a few ulp apart) a sum never moves (found by the GUI soak's
  // sibling hang in the colour bar). At most target + 1 ticks.
  const double first = std::ceil(lo / step);
  const int count = int(std::min(std::floor((hi + step * 1e-9) / step) - first + 1, 64.0));
  for (int k = 0; k < count; ++k) {
    const double v = (first + k) * step;
    out.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  }
  // A lone tick (0.04 … 1.25 with step 1) neither shows the scale nor the step its label needs.
  if (out.size() < 2) return nice_ticks(lo, hi, 2 * target + 1);
  return out;
}

std::vector<double> log_ticks(double lo, double hi) {
  std::vector<double> out;
  if (!(lo > 0) || !(hi >= lo) || !std::isfinite(hi)) return out;
  const int a = int(std::ceil(std::log10(lo) - 1e-9)), b = int(std::floor(std::log10(hi) + 1e-9));
  const int every = std::max(1, (b - a + 1) / 6);  // at most ~6 labelled decades
  for (int e = a; e <= b; ++e)
    if ((e - a) % every == 0) out.push_back(std::pow(10.0, e));
  if (out.size() < 3) {  // a decade or two: label 2× and 5× as well
    for (int e = a - 1; e <= b; ++e)
      for (double m : {2.0, 5.0})
        if (const double v = m * std::pow(10.0, e); v >= lo && v <= hi) out.push_back(v);
    std::sort(out.begin(), out.end());
  }
  return out;
}

std::string tick_label(double v, double step) {
  char buf[32];
  const double a = std::abs(v);
  if (v == 0) return "0";
  if (v != 0 && (a >= 1e5 || a < 1e-3)) {
    // Enough significant digits that neighbouring ticks differ.
    const int sig =
        step > 0 ? int(std::floor(std::log10(a)) - std::floor(std::log10(step) + 1e-9)) + 1 : 3;
    std::snprintf(buf, sizeof buf, "%.*g", std::clamp(sig, 3, 10), v);
  } else {
    int digits = step > 0 ? std::clamp(int(-std::floor(std::log10(step) + 1e-9)), 0, 6) : 2;
    // A step like 0.25 needs one digit more than its magnitude says.
    while (step > 0 && digits < 8) {
      const double scaled = step * std::pow(10.0, digits);
      if (std::abs(scaled - std::round(scaled)) < 1e-6 * scaled) break;
      ++digits;
    }
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  }
  return buf;
}

std::vector<std::string> linear_tick_labels(const std::vector<double>& ticks, double step,
                                            std::string* offset) {
  std::vector<std::string> out;
  double big = 0;
  for (double v : ticks) big = std::max(big, std::abs(v));
  if (offset) offset->clear();
  if (!offset || ticks.size() < 2 || !(step > 0) || step >= 1e-4 * big) {
    for (double v : ticks) out.push_back(tick_label(v, step));
    return out;
  }
  // The middle tick as the base, with every digit down to the step's.
  const double base = ticks[ticks.size() / 2];
  const int sig = int(std::floor(std::log10(std::abs(base))) - std::floor(std::log10(step) + 1e-9));
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", std::clamp(sig + 1, 3, 17), base);
  *offset = buf;
  for (double v : ticks) {
    const double d = v - base;
    if (std::abs(d) < 1e-6 * step)
      out.push_back("0");
    else
      out.push_back((d > 0 ? "+" : "") + tick_label(d, step));
  }
  return out;
}

namespace {

// Text turned a quarter left (reading upwards), centred on `center`. Laid out level inside
// the window first (ImGui culls glyphs outside the clip rect), then turned into place.
void add_text_vertical(ImDrawList* dl, ImVec2 center, ImU32 color, const char* text) {
  const ImVec2 ts = ImGui::CalcTextSize(text);
  const ImVec2 at = ImGui::GetWindowPos();
  const ImVec2 mid(at.x + ts.x / 2, at.y + ts.y / 2);
  dl->PushClipRectFullScreen();
  const int first = dl->VtxBuffer.Size;
  dl->AddText(at, color, text);
  for (int i = first; i < dl->VtxBuffer.Size; ++i) {
    ImVec2& p = dl->VtxBuffer[i].pos;
    const float dx = p.x - mid.x, dy = p.y - mid.y;
    p = ImVec2(center.x + dy, center.y - dx);
  }
  dl->PopClipRect();
}

// A polyline as dashes of `on` pixels separated by `off` pixels.
void add_dashed(ImDrawList* dl, const std::vector<ImVec2>& pts, ImU32 color, float thickness,
                float on, float off) {
  float phase = 0;  // distance into the current on+off period
  std::vector<ImVec2> dash;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    ImVec2 a = pts[i - 1];
    const ImVec2 b = pts[i];
    float len = std::hypot(b.x - a.x, b.y - a.y);
    const float ux = len > 0 ? (b.x - a.x) / len : 0, uy = len > 0 ? (b.y - a.y) / len : 0;
    while (len > 0) {
      const bool drawing = phase < on;
      const float step = std::min(len, drawing ? on - phase : on + off - phase);
      const ImVec2 c(a.x + ux * step, a.y + uy * step);
      if (drawing) {
        if (dash.empty()) dash.push_back(a);
        dash.push_back(c);
      }
      phase += step, len -= step, a = c;
      if (phase >= on && !dash.empty()) {
        if (dash.size() > 1) dl->AddPolyline(dash.data(), int(dash.size()), color, 0, thickness);
        dash.clear();
      }
      if (phase >= on + off) phase = 0;
    }
  }
  if (dash.size() > 1) dl->AddPolyline(dash.data(), int(dash.size()), color, 0, thickness);
}

}  // namespace

PlotPick plot(const char* id, ImVec2 size, const PlotOptions& o,
              const std::vector<PlotSeries>& series) {
  PlotPick pick;
  ImGui::PushID(id);
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  if (size.x <= 0) size.x = avail.x;
  if (size.y <= 0) size.y = avail.y;
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("plot", size);
  const bool hovered = o.interactive && ImGui::IsItemHovered();
  const bool clicked = hovered && ImGui::IsItemClicked(ImGuiMouseButton_Left);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const float fh = ImGui::GetFontSize();

  // Data ranges.
  Range xr, yr;
  for (auto& s : series)
    for (std::size_t i = 0; i < s.count; ++i) {
      const double x = s.x(i), y = s.y(i);
      if ((o.log_y && !(y > 0)) || (o.log_x && !(x > 0))) continue;
      xr.add(x);
      yr.add(y);
    }
  if (o.log_x) {
    xr = pad(xr, true);
  } else {
    if (!xr.valid()) xr = {0, 1};
    if (xr.hi <= xr.lo) xr.hi = xr.lo + 1;
  }
  yr = pad(yr, o.log_y);
  auto fx = [&](double x) { return o.log_x ? std::log10(x) : x; };
  auto fy = [&](double y) { return o.log_y ? std::log10(y) : y; };
  const double xlo = fx(xr.lo), xhi = fx(xr.hi), ylo = fy(yr.lo), yhi = fy(yr.hi);

  // Tick labels decide the left margin.
  std::vector<double> yt = o.log_y ? log_ticks(yr.lo, yr.hi) : nice_ticks(yr.lo, yr.hi, 4);
  const double ystep = yt.size() > 1 ? yt[1] - yt[0] : yr.hi - yr.lo;
  std::string y_offset;
  std::vector<std::string> ylabels;
  if (o.log_y)
    for (double v : yt) ylabels.push_back(tick_label(v, v));
  else
    ylabels = linear_tick_labels(yt, ystep, &y_offset);
  float label_w = 0;
  for (const std::string& l : ylabels)
    label_w = std::max(label_w, ImGui::CalcTextSize(l.c_str()).x);
  const float ylabel_w = o.y_label.empty() ? 0.0f : fh + 6;
  const float box_left = p0.x + ylabel_w + label_w + 10, box_right = p0.x + size.x - 8;
  const float legend_top = p0.y + fh + 6;
  const LegendLayout lay =
      o.legend ? layout_legend(series, box_left, box_right, legend_top, 0.35f * size.y)
               : LegendLayout{legend_top, {}, {}, {}};
  const ImVec2 a(box_left, lay.bottom + (lay.entries.empty() ? 0.0f : 4.0f));  // box, top left
  const ImVec2 b(box_right, p0.y + size.y - 2 * fh - 6);                       // bottom right
  pick.box_min = a, pick.box_max = b;
  pick.y_lo = yr.lo, pick.y_hi = yr.hi;
  pick.y_tick_labels = ylabels;
  pick.y_offset = y_offset;
  if (!lay.entries.empty())
    pick.legend_min = ImVec2(box_left, legend_top), pick.legend_max = ImVec2(box_right, lay.bottom);
  if (b.x - a.x < 20 || b.y - a.y < 20) {
    ImGui::PopID();
    return pick;
  }
  // Pixels, held within a screen's reach of the box: a value far outside the range (1e308 on
  // an axis the range clamps to 1e300) would overflow to inf, and ImGui's lines to NaN.
  auto sx = [&](double x) {
    return float(std::clamp(a.x + (fx(x) - xlo) / (xhi - xlo) * (b.x - a.x), a.x - 1e6, b.x + 1e6));
  };
  auto sy = [&](double y) {
    return float(std::clamp(b.y - (fy(y) - ylo) / (yhi - ylo) * (b.y - a.y), a.y - 1e6, b.y + 1e6));
  };

  dl->AddRectFilled(a, b, IM_COL32(255, 255, 255, 255));
  // Text never runs into the next plot: cut to the room it has, with "...".
  // A tiny range's ticks are offsets: the base they are added to ends the title line.
  const std::string offset_text = y_offset.empty() ? "" : "y ticks + " + y_offset;
  const float offset_w =
      offset_text.empty() ? 0.0f : ImGui::CalcTextSize(offset_text.c_str()).x + 12;
  const std::string title = fit_text(o.title, size.x - 8 - offset_w);
  const float title_w = ImGui::CalcTextSize(title.c_str()).x;
  dl->AddText(ImVec2(o.interactive ? p0.x + 4 : (a.x + b.x - title_w) / 2, p0.y + 2), kText,
              title.c_str());
  if (!offset_text.empty())
    dl->AddText(ImVec2(b.x - offset_w + 12, p0.y + 2), kMuted, offset_text.c_str());
  // Minor grid lines of log axes: 2..9 times each decade.
  auto minor = [&](double lo, double hi, auto&& draw) {  // lo > 0 (pad's log range)
    for (int e = int(std::floor(std::log10(lo))); e <= int(std::ceil(std::log10(hi))); ++e)
      for (int m = 2; m <= 9; ++m)
        if (const double v = m * std::pow(10.0, e); v >= lo && v <= hi) draw(v);
  };
  constexpr ImU32 kMinor = IM_COL32(240, 240, 240, 255);
  if (o.log_y && o.minor_log_grid)
    minor(yr.lo, yr.hi,
          [&](double v) { dl->AddLine(ImVec2(a.x, sy(v)), ImVec2(b.x, sy(v)), kMinor); });
  if (o.log_x && o.minor_log_grid)
    minor(xr.lo, xr.hi,
          [&](double v) { dl->AddLine(ImVec2(sx(v), a.y), ImVec2(sx(v), b.y), kMinor); });
  for (std::size_t k = 0; k < yt.size(); ++k) {
    const float y = sy(yt[k]);
    dl->AddLine(ImVec2(a.x, y), ImVec2(b.x, y), kGrid);
    const ImVec2 ts = ImGui::CalcTextSize(ylabels[k].c_str());
    dl->AddText(ImVec2(a.x - 5 - ts.x, y - ts.y / 2), kMuted, ylabels[k].c_str());
  }
  if (!o.y_label.empty())
    add_text_vertical(dl, ImVec2(p0.x + 2 + fh / 2, (a.y + b.y) / 2), kMuted, o.y_label.c_str());
  const auto xt = o.log_x ? log_ticks(xr.lo, xr.hi)
                          : nice_ticks(xr.lo, xr.hi, std::max(2, int((b.x - a.x) / 90)));
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : xr.hi - xr.lo;
  float last_right = -1e30f;  // a label that would run into the one before is left out
  for (double v : xt) {
    const float x = sx(v);
    dl->AddLine(ImVec2(x, a.y), ImVec2(x, b.y), kGrid);
    const std::string l = o.log_x ? tick_label(v, v) : tick_label(v, xstep);
    const float w = ImGui::CalcTextSize(l.c_str()).x;
    const float left = std::clamp(x - w / 2, a.x - 4, b.x - w);
    if (left < last_right + 6) continue;
    dl->AddText(ImVec2(left, b.y + 3), kMuted, l.c_str());
    last_right = left + w;
  }
  const float xlw = ImGui::CalcTextSize(o.x_label.c_str()).x;
  dl->AddText(ImVec2((a.x + b.x - xlw) / 2, b.y + fh + 3), kMuted, o.x_label.c_str());

  // Lines: one vertex per point, or min/max per pixel column when points outnumber pixels.
  dl->PushClipRect(a, b, true);
  std::vector<ImVec2> pts;
  for (auto& s : series) {
    auto stroke = [&] {
      if (pts.size() > 1) {
        if (s.dashed)
          add_dashed(dl, pts, s.color, s.thickness, 3 * s.thickness + 3, 2 * s.thickness + 2);
        else
          dl->AddPolyline(pts.data(), int(pts.size()), s.color, 0, s.thickness);
      }
    };
    pts.clear();
    const double per_px = double(s.count) / std::max(1.0f, b.x - a.x);
    float col = -1e9f, lo = 0, hi = 0;
    auto flush = [&] {
      if (col > -1e8f) {
        pts.push_back(ImVec2(col, lo));
        if (hi != lo) pts.push_back(ImVec2(col, hi));
      }
    };
    for (std::size_t i = 0; i < s.count; ++i) {
      const double xv = s.x(i), yv = s.y(i);
      if (!std::isfinite(yv) || (o.log_y && !(yv > 0)) || (o.log_x && !(xv > 0))) {
        flush(), col = -1e9f;
        stroke();
        pts.clear();
        continue;
      }
      const float x = sx(xv), y = sy(yv);
      if (s.markers) {
        draw_marker(dl, ImVec2(x, y), s.thickness + 2.0f, s.marker_of ? s.marker_of(i) : s.marker,
                    s.color);
        if (s.point_label)
          if (const std::string t = s.point_label(i); !t.empty())
            dl->AddText(ImVec2(x + s.thickness + 5, y - fh + 2), kMuted, t.c_str());
      }
      if (per_px < 2) {
        pts.push_back(ImVec2(x, y));
      } else if (std::floor(x) != col) {
        flush();
        col = std::floor(x), lo = hi = y;
      } else {
        lo = std::min(lo, y), hi = std::max(hi, y);
      }
    }
    flush();
    stroke();
    if (pts.size() == 1 && !s.markers) dl->AddCircleFilled(pts[0], 2.5f, s.color);
  }
  dl->PopClipRect();
  dl->AddRect(a, b, kFrame);

  // Legend: the band above the box; each entry its sample (line, dashes, marker) and label.
  for (const LegendEntry& e : lay.entries) {
    const PlotSeries& s = series[e.series];
    const ImVec2 l0(e.at.x, e.at.y + fh / 2), l1(e.at.x + 18, e.at.y + fh / 2);
    if (s.dashed)
      add_dashed(dl, {l0, l1}, s.color, 2.0f, 6, 3);
    else if (s.thickness > 0)
      dl->AddLine(l0, l1, s.color, 2.5f);
    if (s.markers)
      draw_marker(dl, ImVec2((l0.x + l1.x) / 2, l0.y), std::max(s.thickness, 1.6f) + 2.0f, s.marker,
                  s.color);
    dl->AddText(ImVec2(e.at.x + 24, e.at.y), kText, e.text.c_str());
  }
  if (!lay.more.empty()) dl->AddText(lay.more_at, kMuted, lay.more.c_str());

  const ImVec2 m = ImGui::GetIO().MousePos;
  if (hovered && o.pick_points) {  // the nearest marker within 10 pixels, ringed
    float best = 10 * 10;
    for (std::size_t k = 0; k < series.size(); ++k) {
      const PlotSeries& s = series[k];
      if (!s.markers) continue;
      for (std::size_t i = 0; i < s.count; ++i) {
        const double xv = s.x(i), yv = s.y(i);
        if (!std::isfinite(yv) || (o.log_y && !(yv > 0)) || (o.log_x && !(xv > 0))) continue;
        const float dx = sx(xv) - m.x, dy = sy(yv) - m.y;
        if (dx * dx + dy * dy < best) {
          best = dx * dx + dy * dy;
          pick.hit = true, pick.clicked = false, pick.series = k, pick.point = i;
        }
      }
    }
    if (pick.hit) {
      const PlotSeries& s = series[pick.series];
      dl->AddCircle(ImVec2(sx(s.x(pick.point)), sy(s.y(pick.point))), s.thickness + 6, kText, 16,
                    1.5f);
      pick.clicked = clicked;
      ImGui::BeginTooltip();
      if (o.point_tooltip)
        o.point_tooltip(pick.series, pick.point);
      else
        ImGui::Text("%s: %.6g, %.6g", s.label.c_str(), s.x(pick.point), s.y(pick.point));
      ImGui::EndTooltip();
    }
  } else if (hovered && m.x >= a.x && m.x <= b.x) {
    // Hover: a vertical rule and each series' value at the nearest sample.
    dl->AddLine(ImVec2(m.x, a.y), ImVec2(m.x, b.y), IM_COL32(120, 120, 120, 160));
    const double xf = xlo + (m.x - a.x) / (b.x - a.x) * (xhi - xlo);
    const double xv = o.log_x ? std::pow(10.0, xf) : xf;
    ImGui::BeginTooltip();
    ImGui::Text("%s = %.6g", o.x_label.c_str(), xv);
    for (auto& s : series) {
      if (s.count == 0) continue;
      std::size_t lo = 0, hi = s.count - 1;  // first sample with x >= xv
      while (lo < hi) {
        const std::size_t mid = (lo + hi) / 2;
        (s.x(mid) < xv ? lo = mid + 1 : hi = mid);
      }
      ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(s.color), "%s: %.6g", s.label.c_str(),
                         s.y(lo));
    }
    ImGui::EndTooltip();
  }
  ImGui::PopID();
  return pick;
}

}  // namespace apiclab::gui
