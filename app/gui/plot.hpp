// One small line-plot widget drawn with ImDrawList (Debian packages no ImPlot): ticks with
// labels, grid, legend, automatic ranges, linear or log axes, and a hover readout. Every
// plot in the GUI and every chart of `apiclab figures` (drawn offscreen) goes through it.
#pragma once
#include <imgui.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "render/palette.hpp"

namespace apiclab::gui {

// A marker's shape: sweep charts tell configurations apart by it.
enum class Marker { circle, square, triangle, diamond, triangle_down, plus, cross, ring };
inline constexpr int kMarkerShapes = 8;

struct PlotSeries {
  std::string label;
  ImU32 color = render::packed_abgr(render::palette_color(0));
  std::size_t count = 0;
  std::function<double(std::size_t)> x, y;  // point i; x must not decrease
  float thickness = 1.6f;
  bool dashed = false;   // a dashed line (a second quantity in a scheme's color)
  bool markers = false;  // a dot on every sample (sparse data such as a convergence study)
  Marker marker = Marker::circle;
  std::function<Marker(std::size_t)> marker_of;         // per sample, when set (legend: `marker`)
  std::function<std::string(std::size_t)> point_label;  // a short text beside a sample's marker
};

// A marker of `radius` pixels centred at c.
void draw_marker(ImDrawList* dl, ImVec2 c, float radius, Marker m, ImU32 color);

struct PlotOptions {
  std::string title;
  std::string x_label = "t [s]";
  std::string y_label;  // drawn turned a quarter left of the y tick labels; empty: none
  bool log_x = false;   // non-positive values are left out
  bool log_y = false;   // non-positive values are left out
  // The legend sits in a band between the title and the plot box, its entries flowing in rows:
  // never over the data, and the axes' ranges come from the data alone. A series with an empty
  // label is left out of it; one without samples is a legend entry only.
  bool legend = true;
  bool interactive = true;      // false: no hover readout (offscreen figures)
  bool minor_log_grid = false;  // log axes: light grid lines at 2..9 times each decade
  // Scatter charts (the sweep viewer): hover picks the nearest marker of a series with markers
  // instead of reading every series at the mouse's x; point_tooltip, when set, writes the
  // tooltip of the picked point (series index, sample index).
  bool pick_points = false;
  std::function<void(std::size_t series, std::size_t point)> point_tooltip;
};

// The marker under the mouse (pick_points), and whether it was clicked this frame; and where
// the plot put its parts (screen pixels), for the layout tests.
struct PlotPick {
  bool hit = false, clicked = false;
  std::size_t series = 0, point = 0;
  ImVec2 box_min{0, 0}, box_max{0, 0};        // the data's box
  ImVec2 legend_min{0, 0}, legend_max{0, 0};  // the legend band (empty: no legend)
  double y_lo = 0, y_hi = 0;                  // the y axis's range
  std::vector<std::string> y_tick_labels;     // as drawn
  std::string y_offset;                       // tiny ranges: the value the ticks are offsets from
};

// Lays out `size` pixels at the cursor (width or height <= 0: what is left) and draws.
PlotPick plot(const char* id, ImVec2 size, const PlotOptions& options,
              const std::vector<PlotSeries>& series);

// Round tick positions covering [lo, hi], about `target` of them; log: powers of ten.
std::vector<double> nice_ticks(double lo, double hi, int target);
std::vector<double> log_ticks(double lo, double hi);
std::string tick_label(double v, double step);  // no more digits than the step needs
// Labels of linear ticks `step` apart that differ from each other: plain, or, where the range
// is tiny beside its values (an L_z of 0.01032124 ± 1e-9), offsets ("+5e-10") from `offset`,
// which is then set to the base's label.
std::vector<std::string> linear_tick_labels(const std::vector<double>& ticks, double step,
                                            std::string* offset);

}  // namespace apiclab::gui
