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

// A readable range around the data: padded, never empty (a constant series sits mid-plot).
Range pad(Range r, bool log) {
  if (!r.valid()) return log ? Range{1e-16, 1} : Range{0, 1};
  if (log) {
    double lo = std::log10(r.lo), hi = std::log10(r.hi);
    if (hi - lo < 1) lo = (lo + hi) / 2 - 0.5, hi = lo + 1;
    return {std::pow(10.0, lo - 0.05 * (hi - lo)), std::pow(10.0, hi + 0.05 * (hi - lo))};
  }
  double span = r.hi - r.lo;
  if (span <= 1e-12 * std::max(std::abs(r.lo), std::abs(r.hi)) || span == 0) {
    const double half = std::max(std::abs(r.lo) * 1e-3, 1e-12);
    return {r.lo - half, r.hi + half};
  }
  return {r.lo - 0.06 * span, r.hi + 0.06 * span};
}

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> out;
  if (!(hi > lo) || target < 1) return out;
  const double raw = (hi - lo) / target, mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  for (double v = std::ceil(lo / step) * step; v <= hi + step * 1e-9; v += step)
    out.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  return out;
}

std::vector<double> log_ticks(double lo, double hi) {
  std::vector<double> out;
  const int a = int(std::ceil(std::log10(lo) - 1e-9)), b = int(std::floor(std::log10(hi) + 1e-9));
  const int every = std::max(1, (b - a + 1) / 6);  // at most ~6 labelled decades
  for (int e = a; e <= b; ++e)
    if ((e - a) % every == 0) out.push_back(std::pow(10.0, e));
  return out;
}

std::string tick_label(double v, double step) {
  char buf[32];
  const double a = std::abs(v);
  if (v == 0) return "0";
  if (v != 0 && (a >= 1e5 || a < 1e-3)) {
    std::snprintf(buf, sizeof buf, "%.3g", v);
  } else {
    const int digits = step > 0 ? std::clamp(int(-std::floor(std::log10(step) + 1e-9)), 0, 6) : 2;
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  }
  return buf;
}

void plot(const char* id, ImVec2 size, const PlotOptions& o, const std::vector<PlotSeries>& series) {
  ImGui::PushID(id);
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  if (size.x <= 0) size.x = avail.x;
  if (size.y <= 0) size.y = avail.y;
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("plot", size);
  const bool hovered = ImGui::IsItemHovered();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const float fh = ImGui::GetFontSize();

  // Data ranges.
  Range xr, yr;
  for (auto& s : series)
    for (std::size_t i = 0; i < s.count; ++i) {
      const double y = s.y(i);
      if (o.log_y && !(y > 0)) continue;
      xr.add(s.x(i));
      yr.add(y);
    }
  if (!xr.valid()) xr = {0, 1};
  if (xr.hi <= xr.lo) xr.hi = xr.lo + 1;
  yr = pad(yr, o.log_y);
  auto fy = [&](double y) { return o.log_y ? std::log10(y) : y; };
  const double ylo = fy(yr.lo), yhi = fy(yr.hi);

  // Tick labels decide the left margin.
  std::vector<double> yt = o.log_y ? log_ticks(yr.lo, yr.hi) : nice_ticks(yr.lo, yr.hi, 4);
  const double ystep = yt.size() > 1 ? yt[1] - yt[0] : yr.hi - yr.lo;
  std::vector<std::string> ylabels;
  float label_w = 0;
  for (double v : yt) {
    ylabels.push_back(o.log_y ? tick_label(v, v) : tick_label(v, ystep));
    label_w = std::max(label_w, ImGui::CalcTextSize(ylabels.back().c_str()).x);
  }
  const ImVec2 a(p0.x + label_w + 10, p0.y + fh + 6);                // plot box, top left
  const ImVec2 b(p0.x + size.x - 8, p0.y + size.y - 2 * fh - 6);     // bottom right
  if (b.x - a.x < 20 || b.y - a.y < 20) {
    ImGui::PopID();
    return;
  }
  auto sx = [&](double x) { return float(a.x + (x - xr.lo) / (xr.hi - xr.lo) * (b.x - a.x)); };
  auto sy = [&](double y) { return float(b.y - (fy(y) - ylo) / (yhi - ylo) * (b.y - a.y)); };

  dl->AddRectFilled(a, b, IM_COL32(255, 255, 255, 255));
  dl->AddText(ImVec2(p0.x + 4, p0.y + 2), kText, o.title.c_str());
  for (std::size_t k = 0; k < yt.size(); ++k) {
    const float y = sy(yt[k]);
    dl->AddLine(ImVec2(a.x, y), ImVec2(b.x, y), kGrid);
    const ImVec2 ts = ImGui::CalcTextSize(ylabels[k].c_str());
    dl->AddText(ImVec2(a.x - 5 - ts.x, y - ts.y / 2), kMuted, ylabels[k].c_str());
  }
  const auto xt = nice_ticks(xr.lo, xr.hi, std::max(2, int((b.x - a.x) / 90)));
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : xr.hi - xr.lo;
  for (double v : xt) {
    const float x = sx(v);
    dl->AddLine(ImVec2(x, a.y), ImVec2(x, b.y), kGrid);
    const std::string l = tick_label(v, xstep);
    const float w = ImGui::CalcTextSize(l.c_str()).x;
    dl->AddText(ImVec2(std::clamp(x - w / 2, a.x - 4, b.x - w), b.y + 3), kMuted, l.c_str());
  }
  const float xlw = ImGui::CalcTextSize(o.x_label.c_str()).x;
  dl->AddText(ImVec2((a.x + b.x - xlw) / 2, b.y + fh + 3), kMuted, o.x_label.c_str());

  // Lines: one vertex per point, or min/max per pixel column when points outnumber pixels.
  dl->PushClipRect(a, b, true);
  std::vector<ImVec2> pts;
  for (auto& s : series) {
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
      const double yv = s.y(i);
      if (!std::isfinite(yv) || (o.log_y && !(yv > 0))) {
        flush(), col = -1e9f;
        if (pts.size() > 1) dl->AddPolyline(pts.data(), int(pts.size()), s.color, 0, s.thickness);
        pts.clear();
        continue;
      }
      const float x = sx(s.x(i)), y = sy(yv);
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
    if (pts.size() > 1) dl->AddPolyline(pts.data(), int(pts.size()), s.color, 0, s.thickness);
    if (pts.size() == 1) dl->AddCircleFilled(pts[0], 2.5f, s.color);
  }
  dl->PopClipRect();
  dl->AddRect(a, b, kFrame);

  // Legend, top right inside the box.
  if (o.legend && !series.empty()) {
    float w = 0;
    for (auto& s : series) w = std::max(w, ImGui::CalcTextSize(s.label.c_str()).x);
    const ImVec2 la(b.x - w - 30, a.y + 4), lb(b.x - 4, a.y + 6 + series.size() * (fh + 1));
    dl->AddRectFilled(la, lb, IM_COL32(255, 255, 255, 215));
    dl->AddRect(la, lb, IM_COL32(200, 200, 200, 255));
    for (std::size_t k = 0; k < series.size(); ++k) {
      const float y = la.y + 2 + k * (fh + 1);
      dl->AddLine(ImVec2(la.x + 4, y + fh / 2), ImVec2(la.x + 18, y + fh / 2), series[k].color, 2.5f);
      dl->AddText(ImVec2(la.x + 22, y), kText, series[k].label.c_str());
    }
  }

  // Hover: a vertical rule and each series' value at the nearest sample.
  const ImVec2 m = ImGui::GetIO().MousePos;
  if (hovered && m.x >= a.x && m.x <= b.x) {
    dl->AddLine(ImVec2(m.x, a.y), ImVec2(m.x, b.y), IM_COL32(120, 120, 120, 160));
    const double xv = xr.lo + (m.x - a.x) / (b.x - a.x) * (xr.hi - xr.lo);
    ImGui::BeginTooltip();
    ImGui::Text("%s = %.6g", o.x_label.c_str(), xv);
    for (auto& s : series) {
      if (s.count == 0) continue;
      std::size_t lo = 0, hi = s.count - 1;  // first sample with x >= xv
      while (lo < hi) {
        const std::size_t mid = (lo + hi) / 2;
        (s.x(mid) < xv ? lo = mid + 1 : hi = mid);
      }
      ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(s.color), "%s: %.6g", s.label.c_str(), s.y(lo));
    }
    ImGui::EndTooltip();
  }
  ImGui::PopID();
}

}  // namespace apiclab::gui
