// The plot widget's legend never covers a curve: it sits in a band above the data's box, and the
// axes' ranges are the data's. Drawn headless (ImGui with its font atlas built and no renderer);
// the tests read the layout plot() reports and the draw list.
#include <gtest/gtest.h>
#include <imgui.h>

#include <cmath>
#include <limits>

#include "app/gui/plot.hpp"

namespace {

using apiclab::gui::PlotOptions;
using apiclab::gui::PlotSeries;

struct Box {
  float x0, y0, x1, y1;
  bool holds(ImVec2 p) const { return p.x > x0 && p.x < x1 && p.y > y0 && p.y < y1; }
};

// A headless ImGui context (its font atlas built, no renderer) of an 800 × 600 display.
ImGuiIO& start_headless_imgui() {
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini in the working directory
  unsigned char* pixels = nullptr;
  int w = 0, h = 0;
  io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
  io.DisplaySize = ImVec2(800, 600);
  io.DeltaTime = 1 / 60.0f;
  return io;
}

// Draws the series in a plot of `size` and returns its layout; `covered` counts the curve
// vertices (the series' colours) inside the legend band, right of the legend's own samples.
apiclab::gui::PlotPick draw_plot(const std::vector<PlotSeries>& series, PlotOptions o, ImVec2 size,
                                 long* covered = nullptr) {
  start_headless_imgui();
  ImGui::NewFrame();
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(size.x + 20, size.y + 20));
  ImGui::Begin("plot test");
  o.interactive = false;
  const apiclab::gui::PlotPick p = apiclab::gui::plot("p", size, o, series);
  const ImDrawList* dl = ImGui::GetWindowDrawList();
  const Box band{p.legend_min.x, p.legend_min.y, p.legend_max.x, p.legend_max.y};
  if (covered) {
    *covered = 0;
    for (int i = 0; i < dl->VtxBuffer.Size; ++i)
      for (const PlotSeries& s : series)
        if (dl->VtxBuffer[i].col == s.color && band.holds(dl->VtxBuffer[i].pos) &&
            p.box_min.y < dl->VtxBuffer[i].pos.y)
          ++*covered;
  }
  ImGui::End();
  ImGui::EndFrame();
  ImGui::DestroyContext();
  return p;
}

PlotSeries line(ImU32 color, double (*f)(double), std::size_t n = 200) {
  PlotSeries s;
  s.label = "a series with a long label [kg m/s]";
  s.color = color;
  s.count = n;
  s.x = [n](std::size_t i) { return double(i) / double(n - 1); };
  s.y = [n, f](std::size_t i) { return f(double(i) / double(n - 1)); };
  return s;
}

// The legend sits in a band above the data's box, inside the plot, and the axis is the data's:
// eight series on a log axis (the drift plot of four panes) no longer stretch it to 1e+14.
TEST(PlotLegend, SitsAboveTheBoxAndLeavesTheAxisToTheData) {
  for (bool log_y : {false, true})
    for (int n : {2, 8}) {
      std::vector<PlotSeries> s;
      for (int k = 0; k < n; ++k)
        s.push_back(line(
            IM_COL32(20 * k, 0, 200, 255),
            log_y ? +[](double x) { return 1e-16 + 1e-2 * x; } : +[](double x) { return x; }));
      PlotOptions o;
      o.log_y = log_y;
      long covered = -1;
      const auto p = draw_plot(s, o, ImVec2(310, 300), &covered);
      const std::string what = "log " + std::to_string(log_y) + ", " + std::to_string(n);
      EXPECT_LT(p.legend_min.y, p.legend_max.y) << what;
      EXPECT_LE(p.legend_max.y, p.box_min.y) << what;  // above the data, never over it
      EXPECT_GE(p.legend_min.x, 0) << what;
      EXPECT_LE(p.legend_max.x, 310) << what;
      EXPECT_GT(p.box_max.y - p.box_min.y, 100) << what;  // the data keep most of the height
      EXPECT_EQ(covered, 0) << what;
      if (log_y)
        EXPECT_LT(p.y_hi, 0.1) << what;  // data to 1e-2, padded by a twentieth of 14 decades
      else
        EXPECT_LT(p.y_hi, 1.1) << what;
    }
}

// A series with an empty label has no legend entry; a long legend ends in "+N more" and stays
// within its band.
TEST(PlotLegend, EmptyLabelsAreLeftOutAndALongLegendIsCounted) {
  std::vector<PlotSeries> s = {line(IM_COL32(200, 0, 0, 255), [](double x) { return x; })};
  s[0].label.clear();
  EXPECT_EQ(draw_plot(s, PlotOptions{}, ImVec2(300, 200)).legend_max.y, 0);
  std::vector<PlotSeries> many(60, line(IM_COL32(200, 0, 0, 255), [](double x) { return x; }));
  const auto p = draw_plot(many, PlotOptions{}, ImVec2(300, 200));
  EXPECT_GT(p.legend_max.y, p.legend_min.y);
  EXPECT_LE(p.legend_max.y - p.legend_min.y, 0.35f * 200 + 1);
  EXPECT_LE(p.legend_max.y, p.box_min.y);
}

// A tiny range beside its values (rotating-disk's L_z: 0.01032124 ± 1e-9) gets distinct tick
// labels: offsets from a base the title line shows.
TEST(PlotTicks, TinyRangesGetDistinctLabels) {
  for (double base : {0.01032124, -3.5, 1e5, 1.0})
    for (double span : {1e-9, 1e-6, 1e-3}) {
      PlotSeries s = line(IM_COL32(200, 0, 0, 255), [](double x) { return x; });
      s.y = [base, span](std::size_t i) { return base + span * double(i) / 199.0; };
      const auto p = draw_plot({s}, PlotOptions{}, ImVec2(310, 300));
      const auto& l = p.y_tick_labels;
      ASSERT_GE(l.size(), 2u) << base << " + " << span;
      for (std::size_t i = 1; i < l.size(); ++i)
        EXPECT_NE(l[i - 1], l[i]) << base << " + " << span << ": " << l[i];
      for (const std::string& t : l) EXPECT_LE(t.size(), 9u) << t;
      const double relative = span / std::abs(base);  // below 1e-12: padded to ±1e-3 of it
      if (relative < 1e-5 && relative > 1e-12) {
        EXPECT_FALSE(p.y_offset.empty()) << base << " + " << span;
      }
    }
  std::string offset;
  const auto l =
      apiclab::gui::linear_tick_labels({0.0103212395, 0.01032124, 0.0103212405}, 5e-10, &offset);
  EXPECT_EQ(offset, "0.01032124");
  EXPECT_EQ(l, (std::vector<std::string>{"-5e-10", "0", "+5e-10"}));
}

}  // namespace

// Axis ticks: never a lone tick (the drift plot's 0.04 … 1.25 s axis showed only "1.000000"),
// and labels with no more digits than the step needs.
TEST(PlotTicks, AtLeastTwoTicksAndShortLabels) {
  using apiclab::gui::nice_ticks;
  using apiclab::gui::tick_label;
  for (auto [lo, hi] : {std::pair{0.04, 1.25}, {0.9, 1.1}, {1e-3, 2.0}, {-0.3, 0.2}, {5.0, 7.0}})
    for (int target : {1, 2, 4}) {
      const std::vector<double> t = nice_ticks(lo, hi, target);
      ASSERT_GE(t.size(), 2u) << lo << " … " << hi << ", target " << target;
      for (double v : t) EXPECT_TRUE(v >= lo - 1e-12 && v <= hi + 1e-12) << v;
    }
  const std::vector<double> t = nice_ticks(0.04, 1.25, 2);
  for (double v : t) EXPECT_LE(tick_label(v, t[1] - t[0]).size(), 4u) << tick_label(v, t[1] - t[0]);
  EXPECT_EQ(tick_label(0.25, 0.25), "0.25");
  EXPECT_EQ(tick_label(2, 1), "2");
}

// The GUI soak hung the window on a colour bar whose top was inf (render/legend.cpp): a float
// sum of tick steps that never passes the end. Axis ticks had the same loop: a range a few ulp
// wide (1e16 … 1e16 + 4, step 1 below the ulp of 2) never advanced, an infinite range recursed
// without end. Now every range gives a bounded, finite list.
TEST(PlotTicks, AnyRangeGivesFewFiniteTicks) {
  using apiclab::gui::log_ticks;
  using apiclab::gui::nice_ticks;
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  const double big = std::numeric_limits<double>::max(), tiny = 5e-324;
  for (auto [lo, hi] : {std::pair{1e16, 1e16 + 4},
                        {-big, big},
                        {-inf, inf},
                        {0.0, inf},
                        {nan, 1.0},
                        {1.0, nan},
                        {1.0, 1.0},
                        {2.0, 1.0},
                        {tiny, 3 * tiny},
                        {1e300, 1e300 * (1 + 1e-15)}})
    for (int target : {1, 4, 1000}) {
      const std::vector<double> t = nice_ticks(lo, hi, target);
      EXPECT_LE(t.size(), 64u) << lo << " … " << hi;
      for (double v : t) EXPECT_TRUE(std::isfinite(v) && v >= lo - 1e-9 * std::abs(lo)) << v;
    }
  EXPECT_EQ(nice_ticks(1e16, 1e16 + 4, 4).front(), 1e16);
  EXPECT_GE(nice_ticks(1e16, 1e16 + 4, 4).size(), 2u);
  for (auto [lo, hi] : {std::pair{0.0, 1.0}, {tiny, 1.0}, {1e-300, inf}, {nan, 1.0}, {-1.0, 1.0}})
    EXPECT_LE(log_ticks(lo, hi).size(), 700u) << lo << " … " << hi;
  EXPECT_TRUE(log_ticks(0.0, 1.0).empty());
}

// Whole plots of values at double's ends (a run that blew up: energies of 1e308 of both signs,
// a drift of a denormal on a log axis, inf and NaN among them) draw in bounded time with every
// vertex finite.
TEST(PlotTicks, ExtremeSeriesDrawFiniteVertices) {
  start_headless_imgui();
  const double big = std::numeric_limits<double>::max();
  const std::vector<std::vector<double>> ys = {
      {-big, big, 1, std::numeric_limits<double>::infinity(), std::nan("")},
      {5e-324, 1e-320, 1e-310},
      {1e16, 1e16 + 2, 1e16 + 4}};
  const std::vector<double> x = {0, 1, 2, 3, 4};
  for (const std::vector<double>& y : ys)
    for (bool log_y : {false, true}) {
      PlotSeries s;
      s.label = "extreme";
      s.color = IM_COL32(200, 0, 0, 255);
      s.count = y.size();
      s.x = [&x](std::size_t i) { return x[i]; };
      s.y = [&y](std::size_t i) { return y[i]; };
      PlotOptions o;
      o.log_y = log_y;
      o.minor_log_grid = true;
      ImGui::NewFrame();
      ImGui::SetNextWindowPos(ImVec2(0, 0));
      ImGui::SetNextWindowSize(ImVec2(420, 260));
      ImGui::Begin("extreme");
      apiclab::gui::plot("p", ImVec2(400, 240), o, {s});
      const ImDrawList* dl = ImGui::GetWindowDrawList();
      int not_finite = 0;
      for (int i = 0; i < dl->VtxBuffer.Size; ++i) {
        not_finite +=
            !std::isfinite(dl->VtxBuffer[i].pos.x) || !std::isfinite(dl->VtxBuffer[i].pos.y);
      }
      const int vertices = dl->VtxBuffer.Size;
      ImGui::End();
      ImGui::EndFrame();
      EXPECT_LT(vertices, 100000) << "log_y " << log_y << ", first " << y[0];
      EXPECT_EQ(not_finite, 0) << "of " << vertices << ", log_y " << log_y << ", first " << y[0];
    }
  ImGui::DestroyContext();
}

// Scatter picking (pick_points, the sweep viewer's charts): the marker under the mouse is
// picked, with its series and index; a press on it is a click; far from every marker nothing is.
// Headless ImGui over a few frames, the mouse placed at a marker's centre as drawn.
TEST(PlotPick, HoverPicksTheNearestMarkerAndAPressClicksIt) {
  ImGuiIO& io = start_headless_imgui();
  const std::vector<double> xa = {1, 2, 3}, ya = {1, 4, 9}, xb = {1.5, 2.5}, yb = {8, 2};
  auto points = [](const char* label, ImU32 color, const std::vector<double>& x,
                   const std::vector<double>& y) {
    PlotSeries s;
    s.label = label;
    s.color = color;
    s.count = x.size();
    s.x = [&x](std::size_t i) { return x[i]; };
    s.y = [&y](std::size_t i) { return y[i]; };
    s.markers = true;
    s.thickness = 0;  // markers only, no line between them
    return s;
  };
  const ImU32 red = IM_COL32(200, 0, 0, 255), blue = IM_COL32(0, 0, 200, 255);
  const std::vector<PlotSeries> series = {points("a", red, xa, ya), points("b", blue, xb, yb)};
  PlotOptions o;
  o.pick_points = true;
  o.legend = false;
  std::size_t tooltip_series = 99, tooltip_point = 99;
  o.point_tooltip = [&](std::size_t k, std::size_t i) { tooltip_series = k, tooltip_point = i; };
  ImVec2 blue_first(0, 0);  // centre of series b's first marker, read from the draw list
  auto frame = [&](bool read_marker) {
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(420, 260));
    ImGui::Begin("pick test");
    const apiclab::gui::PlotPick pick = apiclab::gui::plot("p", ImVec2(400, 240), o, series);
    if (read_marker) {  // the first blue fan: its vertices' mean is the marker's centre
      const ImDrawList* dl = ImGui::GetWindowDrawList();
      ImVec2 sum(0, 0);
      int n = 0;
      for (int i = 0; i < dl->VtxBuffer.Size && n < 12; ++i)
        if (dl->VtxBuffer[i].col == blue)
          sum.x += dl->VtxBuffer[i].pos.x, sum.y += dl->VtxBuffer[i].pos.y, ++n;
      blue_first = ImVec2(sum.x / float(n), sum.y / float(n));
    }
    ImGui::End();
    ImGui::EndFrame();
    return pick;
  };
  io.MousePos = ImVec2(5, 5);  // outside the plot box
  EXPECT_FALSE(frame(true).hit);
  ASSERT_GT(blue_first.x, 0);
  io.MousePos = ImVec2(blue_first.x + 2, blue_first.y - 1);
  frame(false);  // the window becomes hovered
  const auto hover = frame(false);
  EXPECT_TRUE(hover.hit);
  EXPECT_FALSE(hover.clicked);
  EXPECT_EQ(hover.series, 1u);
  EXPECT_EQ(hover.point, 0u);
  EXPECT_EQ(tooltip_series, 1u);
  EXPECT_EQ(tooltip_point, 0u);
  io.MouseDown[0] = true;
  const auto press = frame(false);
  EXPECT_TRUE(press.hit && press.clicked);
  EXPECT_EQ(press.series, 1u);
  io.MouseDown[0] = false;
  frame(false);
  // 40 pixels from every marker, inside the box: no pick.
  io.MousePos = ImVec2(blue_first.x, blue_first.y + 40);
  frame(false);
  EXPECT_FALSE(frame(false).hit);
  ImGui::DestroyContext();
}
