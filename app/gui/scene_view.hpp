// The panes: each snapshot drawn by the renderer in its own rect, one linked camera moved
// with the mouse (2D pan/zoom, 3D orbit), labels, failure banners, legend, hover readout.
// The scene area of each pane is drawn exactly as a PNG pane is (render/figure.hpp).
#pragma once
#include <vector>

#include "app/gui/viewer_state.hpp"
#include "render/renderer.hpp"

namespace apiclab::gui {

// Rects of the particle views (below each pane's title strip) for `n` panes in `area`.
std::vector<render::Rect> pane_scene_rects(render::Rect area, std::size_t n);

// Handles camera input over `area`, draws the scenes with `r` (between the renderer's
// begin_frame and end_frame) through render::draw_pane_scene with the PNGs' scales
// (render/auto_scale.hpp) and legend (render/legend.hpp, the renderer's overlay); titles,
// failure banners and the hover readout go into ImGui's background draw list.
// Returns the rects of the particle views, one per pane.
std::vector<render::Rect> draw_scene_panes(render::Renderer& r, ViewerState& st,
                                           const Published& pub, render::Rect area);

}  // namespace apiclab::gui
