// What the user asks of a drawing, PNG or GUI pane alike; zeros mean "choose automatically"
// (render/auto_scale.hpp resolves them into a SceneStyle).
#pragma once
#include <optional>

#include "render/camera.hpp"
#include "render/color.hpp"

namespace apiclab::render {

struct FigureStyle {
  ColorMode color = ColorMode::speed;
  float color_max = 0;  // top of the speed/noise colour scale
  bool vectors = false;
  bool surface = true, surface_vectors = false;  // object surfaces (EoL), arrows on them
  float vector_scale = 0;                        // world length of an arrow per unit of speed
  float vector_gain = 1;  // multiplies the automatic arrow length (the GUI's slider)
  int vector_every = 0;   // one arrow per this many particles
  bool grid = false, box = true, colliders = true, legend = true, header = true;
  float particle_scale = 1;
  int up_axis = 1;            // 3D: the axis that points up on screen (up_axis_from_gravity)
  std::optional<Box3> frame;  // the region to frame; default: the domain box
  double time_step = 0;       // time between frames: sets the digits of "t = ..."
};

}  // namespace apiclab::render
