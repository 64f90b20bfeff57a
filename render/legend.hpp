// The legend beside the panes, drawn with the renderer's overlay for PNGs and GUI alike: the
// colour bar of the speed or noise scale (or the materials' or objects' swatches), then a
// reference arrow of a round speed at the panes' arrow scale.
#pragma once
#include <string>
#include <vector>

#include "render/renderer.hpp"

namespace apiclab::render {

// "speed |v| [m/s]", "noise |v − v_PIC| [m/s]", "material", "object".
std::string legend_title(ColorMode mode);

// The colour bar's tick values: 0 and round steps up to `top`; none unless `top` is finite and
// positive.
std::vector<float> color_bar_ticks(float top);

// The legend's width in pixels for text of `font` pixels and padding `pad`.
float legend_width(Renderer& r, float font, float pad, ColorMode color, bool vectors,
                   const Snapshot& first);

// Draws the legend into `area` (its top is the top of the colour bar's title line).
// `pixels_per_unit`: the panes' pixels per world unit, for the arrow key (0: no key).
void draw_legend(Renderer& r, Rect area, float font, float pad, const SceneStyle& style,
                 const Snapshot& first, float pixels_per_unit);

}  // namespace apiclab::render
