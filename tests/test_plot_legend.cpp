// The plot widget's legend never covers a curve: the y range leaves a band at the
// top for it. Drawn headless (ImGui with its font atlas built and no renderer); the test reads
// the draw list: no vertex of a curve lies inside the legend's box.
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

// Draws the series in a plot and returns how many curve vertices (full-alpha, the curves'
// colours, drawn before the legend) fall inside the legend box; -1 when no legend was found.
long covered_vertices(const std::vector<PlotSeries>& series, PlotOptions o) {
  start_headless_imgui();
  ImGui::NewFrame();
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(420, 260));
  ImGui::Begin("plot test");
  o.interactive = false;
  apiclab::gui::plot("p", ImVec2(400, 240), o, series);
  const ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImU32 kLegendFill = IM_COL32(255, 255, 255, 215);
  long legend_start = -1;
  Box box{1e9f, 1e9f, -1e9f, -1e9f};
  for (int i = 0; i < dl->VtxBuffer.Size; ++i) {
    const ImDrawVert& v = dl->VtxBuffer[i];
    if (v.col != kLegendFill) continue;
    if (legend_start < 0) legend_start = i;
    box = {std::min(box.x0, v.pos.x), std::min(box.y0, v.pos.y), std::max(box.x1, v.pos.x),
           std::max(box.y1, v.pos.y)};
  }
  long covered = legend_start < 0 ? -1 : 0;
  for (long i = 0; i < legend_start; ++i) {
    const ImDrawVert& v = dl->VtxBuffer[int(i)];
    for (const PlotSeries& s : series)
      if (v.col == s.color && box.holds(v.pos)) ++covered;
  }
  ImGui::End();
  ImGui::EndFrame();
  ImGui::DestroyContext();
  return covered;
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

TEST(PlotLegend, NeverCoversACurveInAnyCorner) {
  // Rising and falling lines reach both top corners: no corner inside the data is free.
  const std::vector<PlotSeries> both = {
      line(IM_COL32(200, 0, 0, 255), [](double x) { return x; }),
      line(IM_COL32(0, 0, 200, 255), [](double x) { return 1 - x; })};
  using C = PlotOptions::Corner;
  for (C corner : {C::top_right, C::top_left, C::bottom_right, C::bottom_left, C::best})
    for (bool log_y : {false, true}) {
      PlotOptions o;
      o.legend_corner = corner;
      o.log_y = log_y;
      std::vector<PlotSeries> s = both;
      if (log_y)  // positive data on a log axis
        s = {line(IM_COL32(200, 0, 0, 255), [](double x) { return 1e-16 + x; }),
             line(IM_COL32(0, 0, 200, 255), [](double x) { return 1.000001 - x; })};
      EXPECT_EQ(covered_vertices(s, o), 0) << "corner " << int(corner) << ", log " << log_y;
    }
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
