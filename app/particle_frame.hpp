// Framing on the bodies rather than the whole domain (render --fit particles, Fig 1).
#pragma once
#include <vector>

#include "render/renderer.hpp"
#include "sim/snapshot.hpp"

namespace apiclab {

// The box around every particle of the snapshots, with a quarter of its largest extent and
// two cells of room around it, clipped to the domain.
render::Box3 particle_frame(const std::vector<const Snapshot*>& snapshots);

}  // namespace apiclab
