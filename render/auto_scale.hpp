// The automatic scales, one set of rules for the PNGs of `render`/`compare` and the GUI panes.
// One speed scale, a round number at or above the 99.5% quantile of |v| over the panes, sets
// both the top of the speed colours and the length of the arrows, so an arrow means the same
// speed whatever the colour mode. The noise colours top out at their own quantile, but never
// below a floor relative to the speed scale: round-off (1e-16) stays dark, not full range.
#pragma once
#include <vector>

#include "render/figure_style.hpp"
#include "render/renderer.hpp"

namespace apiclab::render {

inline constexpr float kScaleQuantile = 0.995f;
inline constexpr float kNoiseFloor = 1e-3f;        // of the speed scale
inline constexpr float kArrowSpacings = 2.5f;      // an arrow at the speed scale spans this many
inline constexpr float kPixelsPerArrow = 12 * 12;  // about one arrow per 12 x 12 pixels of scene

// How the scales follow a run: `grow` only ever raises them (colours keep their meaning and
// arrows only shorten), `first_frame` keeps the first non-zero values for the whole run, `fixed`
// keeps the values already held (render and compare: found by a first pass over every frame).
enum class ScaleHold { grow, first_frame, fixed };

// The scales of a run, shared by all its panes; hold one across frames.
struct ScaleState {
  ScaleHold hold = ScaleHold::grow;
  float speed = 0;   // speed scale: top of the speed colours, reference speed of the arrows
  float noise = 0;   // top of the noise colours
  float radius = 0;  // median drawing radius of the latest panes: sets the arrows' spacing
  void reset() { speed = noise = radius = 0; }
};
using FigureState = ScaleState;  // the name the frame loops know it by

// Updates `state` from the panes; panes that failed are left out unless all did (a blow-up
// would swamp the scales of the others). A fixed hold changes nothing.
void update_scales(ScaleState& state, const std::vector<const Snapshot*>& panes);

// The top of the colour scale for `mode` (1 where nothing moves; unused for categories).
float color_top(const ScaleState& state, ColorMode mode);

// Every automatic value of `style` resolved for panes of `scene_rect`'s size from scales
// already updated: the colour top, arrow density and arrow length.
SceneStyle resolve_scene_style(const FigureStyle& style, const std::vector<const Snapshot*>& panes,
                               Rect scene_rect, const ScaleState& state);

// The smallest of 1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 (x 10^k) not below v: scales end on
// round numbers (0 for v <= 0 and for inf or NaN; FLT_MAX where the round number overflows).
float nice_ceil(float v);
// The largest of 1, 2, 5 (x 10^k) not above v (0 for v <= 0).
float nice_floor(float v);

}  // namespace apiclab::render
