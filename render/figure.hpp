// A whole frame as `apiclab render` and `apiclab compare` write it: a header line (scene,
// kernel, integrator, time), one pane per snapshot side by side (labelled with its scheme
// when there are several), and one legend (render/legend.hpp) shared by all panes, so that
// schemes can be compared by eye. The GUI draws its panes with draw_pane_scene and the same
// scales (render/auto_scale.hpp) and legend; only the layout around them is its own.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "render/auto_scale.hpp"
#include "render/figure_style.hpp"
#include "render/renderer.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"

namespace apiclab::render {

// Draws one frame into the bound framebuffer (begin_frame ... end_frame included), the
// automatic scales held in `state` across frames.
void draw_figure(Renderer& r, int width, int height, const std::vector<const Snapshot*>& panes,
                 const FigureStyle& style, ScaleState& state);

// Where each pane's scene lands in a width x height figure.
std::vector<Rect> figure_scene_rects(Renderer& r, int width, int height, int panes,
                                     const Snapshot& first, const FigureStyle& style);

// One pane's scene: `s` through `view` into `rect`. Returns the pixels per world unit at
// the scene's centre (the legend's arrow key uses it). PNG panes and GUI panes both draw here.
float draw_pane_scene(Renderer& r, const Snapshot& s, const View& view, Rect rect,
                      const SceneStyle& style);

// "APIC", "FLIP(α=0.95)", "XPIC(3)": a registry key's label with its scheme's parameter
// (sim/mpm/schemes/scheme_label.hpp); a key outside the registry as render::scheme_label(key) gives
// it.
std::string scheme_label(std::string_view key, double flip_alpha,
                         const SchemeParameters& parameters);
std::string scheme_label(const Snapshot& s);  // of the snapshot's scheme and parameters

}  // namespace apiclab::render
