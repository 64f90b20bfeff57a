// The view's own numbers (not scene parameters): their ranges, and the rule that keeps a value
// typed into a slider (ImGui's ctrl+click turns it into a text field) inside them. The GUI soak
// typed 1e38 into "particle size" and drew half a pane as one particle; NaN passes a clamp.
#pragma once
#include <algorithm>
#include <cmath>

namespace apiclab::gui {

struct ViewLimit {
  float lo, hi, fallback;
};
inline constexpr ViewLimit kParticleScale{0.25f, 4.0f, 1.0f};  // x the automatic particle size
inline constexpr ViewLimit kVectorGain{0.1f, 10.0f, 1.0f};     // x the automatic arrow length
inline constexpr ViewLimit kColorMax{0.0f, 1e9f, 0.0f};        // top of the colour scale
// The camera's half height (2D) or distance (3D), metres: a long wheel turn must not zoom to 0
// or inf, after which every projected point is NaN.
inline constexpr ViewLimit kViewSize{1e-9f, 1e9f, 1.0f};

// The value inside [lo, hi]; a non-finite one (NaN, inf typed) becomes the fallback.
inline float within(float value, const ViewLimit& limit) {
  return std::isfinite(value) ? std::clamp(value, limit.lo, limit.hi) : limit.fallback;
}

}  // namespace apiclab::gui
