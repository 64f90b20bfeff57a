// What every chart of `apiclab figures` shares: one colour and label per scheme, the chart
// size and the heading across the top.
#pragma once
#include <imgui.h>

#include <string>

#include "app/figures/chart_canvas.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"

namespace apiclab::figures {

// One colour and label per scheme, the same in every figure and the GUI (render/palette.hpp).
struct SchemeStyle {
  std::string label;
  ImU32 color;
};
SchemeStyle style_of(const std::string& scheme_key);
// The same with the scheme's parameter in the label, "XPIC(2)", "PolyPIC(9 modes)"
// (sim/mpm/schemes/scheme_label.hpp).
SchemeStyle style_of(const std::string& scheme_key, const SchemeParameters& parameters,
                     double flip_alpha);

constexpr int kChartW = 900, kChartH = 400;

// Draws the heading across the top and returns the y where the charts start.
float heading(ChartCanvas& canvas, const std::string& text, float width);

}  // namespace apiclab::figures
