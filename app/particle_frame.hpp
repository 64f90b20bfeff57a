// Framing on the bodies rather than the whole domain (render --fit particles, Fig 1).
#pragma once
#include <vector>

#include "render/renderer.hpp"
#include "sim/snapshot.hpp"

namespace apiclab {

// The box around every particle of the snapshots, with a quarter of its largest extent and
// two cells of room around it, clipped to the domain.
render::Box3 particle_frame(const std::vector<const Snapshot*>& snapshots);

// `b` (particles' extent) with `room` of its largest extent and two cells around it, clipped to
// `first`'s domain.
render::Box3 padded_frame(render::Box3 b, const Snapshot& first, float room = 0.25f);

// --fit auto: whether a frame on the bodies is worth it, its area (2D) or volume (3D) under
// half the domain's; otherwise the domain frames them well enough.
bool worth_fitting(const render::Box3& frame, const Snapshot& first);

}  // namespace apiclab
