#include "render/color.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "render/palette.hpp"

namespace apiclab::render {

ColorMode parse_color_mode(std::string_view key) {
  return parse_choice(color_mode_choices(), key, "color mode");
}

Vec3 viridis(float t) {
  // Degree-6 polynomial fit to matplotlib's table (Matt Zucker, CC0); error below 1%.
  static const Vec3 c[7] = {{0.2777273272f, 0.0054073445f, 0.3340998053f},
                            {0.1050930431f, 1.4046135299f, 1.3845901626f},
                            {-0.3308618287f, 0.2148475595f, 0.0950951630f},
                            {-4.6342304990f, -5.7991009734f, -19.3324409563f},
                            {6.2282699363f, 14.1799333668f, 56.6905526007f},
                            {4.7763849977f, -13.7451453777f, -65.3530326334f},
                            {-5.4354558559f, 4.6458526122f, 26.3124352496f}};
  t = std::clamp(t, 0.0f, 1.0f);
  Vec3 r = c[6];
  for (int i = 5; i >= 0; --i) r = c[i] + r * t;
  return {std::clamp(r.x, 0.0f, 1.0f), std::clamp(r.y, 0.0f, 1.0f), std::clamp(r.z, 0.0f, 1.0f)};
}

Rgba8 category_color(int index) { return palette_color(index); }

Rgba8 to_rgba8(Vec3 c, float alpha) {
  auto q = [](float v) { return std::uint8_t(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); };
  return {q(c.x), q(c.y), q(c.z), q(alpha)};
}

}  // namespace apiclab::render
