// Colors: the perceptual map for speed and noise, the categorical palette for materials
// and objects, and the color modes users pick by key.
#pragma once
#include <cstdint>
#include <string_view>

#include "render/math.hpp"
#include "sim/scene/registry.hpp"

namespace apiclab::render {

struct Rgba8 {
  std::uint8_t r = 0, g = 0, b = 0, a = 255;
};

// The modes and their keys are in the choice registry (sim/scene/registry.hpp, color_mode_choices).
using ColorMode = apiclab::ColorMode;
// Throws std::invalid_argument naming the keys.
ColorMode parse_color_mode(std::string_view key);
inline bool is_scalar(ColorMode m) { return m == ColorMode::speed || m == ColorMode::noise; }

// Viridis (van der Walt & Smith, matplotlib), perceptually uniform, legible in grey;
// t in [0, 1], clamped.
Vec3 viridis(float t);
// Materials and objects: render/palette.hpp's palette, cycling.
Rgba8 category_color(int index);
Rgba8 to_rgba8(Vec3 rgb, float alpha = 1);

}  // namespace apiclab::render
