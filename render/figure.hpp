// A whole frame as `apiclab render` and `apiclab compare` write it: a header line (scene,
// kernel, integrator, time), one pane per snapshot side by side (labelled with its scheme
// when there are several), and one legend (color scale or materials, arrow scale) shared
// by all panes, so that schemes can be compared by eye.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "render/renderer.hpp"

namespace apiclab::render {

// What the user asks for; zeros mean "choose automatically".
struct FigureStyle {
  ColorMode color = ColorMode::speed;
  float color_max = 0;  // top of the speed/noise scale
  bool vectors = false;
  float vector_scale = 0;  // world length of an arrow per unit of speed
  int vector_every = 0;    // one arrow per this many particles
  bool grid = false, box = true, colliders = true, legend = true, header = true;
  float particle_scale = 1;
  int up_axis = 1;            // 3D: the axis that points up on screen (against gravity)
  std::optional<Box3> frame;  // the region to frame; default: the domain box
  double time_step = 0;       // time between frames: sets the digits of "t = ..."
};

// Automatic scales kept steady through a sequence of frames (a video, the GUI): the color
// scale only grows and the arrow scale only shrinks, in steps of round numbers.
struct FigureState {
  float color_max = 0;
  float vector_scale = 0;
};

// Draws one frame into the bound framebuffer (begin_frame ... end_frame included); `view`,
// when given, replaces the automatic framing of every pane (the GUI's camera).
void draw_figure(Renderer& r, int width, int height, const std::vector<const Snapshot*>& panes,
                 const FigureStyle& style, FigureState& state, const View* view = nullptr);

// Where each pane's scene lands in a width x height figure (the GUI picks cameras with it).
std::vector<Rect> figure_scene_rects(Renderer& r, int width, int height, int panes,
                                     const Snapshot& first, const FigureStyle& style);

// The smallest of 1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 (x 10^k) not below v: scales end on
// round numbers (0 for v <= 0).
float nice_ceil(float v);

// "APIC", "FLIP α=0.95", "PIC".
std::string scheme_label(const Snapshot& s);

}  // namespace apiclab::render
