#include "app/particle_frame.hpp"

#include <algorithm>
#include <cmath>

namespace apiclab {

render::Box3 particle_frame(const std::vector<const Snapshot*>& snapshots) {
  const Snapshot& first = *snapshots.front();
  render::Box3 b = render::particle_box(first);
  for (const Snapshot* s : snapshots) {
    const render::Box3 q = render::particle_box(*s);
    for (int k = 0; k < 3; ++k)
      b.min[k] = std::min(b.min[k], q.min[k]), b.max[k] = std::max(b.max[k], q.max[k]);
  }
  return padded_frame(b, first);
}

render::Box3 padded_frame(render::Box3 b, const Snapshot& first, float room_fraction) {
  const render::Box3 domain = render::domain_box(first);
  const render::Vec3 size = b.size();
  const float room = room_fraction * std::max({size.x, size.y, size.z}) + 2 * float(first.dx);
  for (int k = 0; k < first.dim; ++k) {
    b.min[k] = std::max(b.min[k] - room, domain.min[k]);
    b.max[k] = std::min(b.max[k] + room, domain.max[k]);
  }
  return b;
}

bool worth_fitting(const render::Box3& frame, const Snapshot& first) {
  const render::Vec3 f = frame.size(), d = render::domain_box(first).size();
  double framed = 1, domain = 1;
  for (int k = 0; k < first.dim; ++k) framed *= double(f[k]), domain *= double(d[k]);
  return std::isfinite(framed) && framed > 0 && framed < 0.5 * domain;
}

}  // namespace apiclab
