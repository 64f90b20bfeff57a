#include "app/particle_frame.hpp"

#include <algorithm>

namespace apiclab {

render::Box3 particle_frame(const std::vector<const Snapshot*>& snapshots) {
  const Snapshot& first = *snapshots.front();
  render::Box3 b = render::particle_box(first);
  for (const Snapshot* s : snapshots) {
    const render::Box3 q = render::particle_box(*s);
    for (int k = 0; k < 3; ++k)
      b.min[k] = std::min(b.min[k], q.min[k]), b.max[k] = std::max(b.max[k], q.max[k]);
  }
  const render::Box3 domain = render::domain_box(first);
  const render::Vec3 size = b.size();
  const float room = 0.25f * std::max({size.x, size.y, size.z}) + 2 * float(first.dx);
  for (int k = 0; k < first.dim; ++k) {
    b.min[k] = std::max(b.min[k] - room, domain.min[k]);
    b.max[k] = std::min(b.max[k] + room, domain.max[k]);
  }
  return b;
}

}  // namespace apiclab
