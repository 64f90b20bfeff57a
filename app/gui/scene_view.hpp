// The panes: each snapshot drawn by the renderer in its own rect, one linked camera moved
// with the mouse (2D pan/zoom, 3D orbit), labels, failure banners, legend, hover readout.
#pragma once
#include <vector>

#include "app/gui/viewer_state.hpp"
#include "render/renderer.hpp"

namespace apiclab::gui {

// Rects of the particle views (below each pane's title strip) for `n` panes in `area`.
std::vector<render::Rect> pane_scene_rects(render::Rect area, std::size_t n);

// Handles camera input over `area`, draws the scenes with `r` (between the renderer's
// begin_frame and end_frame) and their overlays into ImGui's background draw list.
void draw_scene_panes(render::Renderer& r, ViewerState& st, const Published& pub, render::Rect area);

}  // namespace apiclab::gui
