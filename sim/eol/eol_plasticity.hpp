// Plasticity (Fan et al. 2013, Sec 3.7): each object's F_p⁻¹ samples (plastic_samples.hpp) laid
// out at set-up, and eqs 35-37 at them after every step's transport.
#pragma once
#include <algorithm>
#include <cmath>

#include "sim/eol/eol_simulation.hpp"

namespace apiclab::eol {

// The samples are the grid nodes over the plastic rest shapes' bounds and a cell around, at
// their material coordinates at set-up (X = p + y), so each starts placed exactly at its node.
// A sample within a cell of a plastic shape takes that shape's material; the others never flow.
template <class T, int D>
void EolSimulation<T, D>::add_plastic_samples(EolObject<T, D>& o) const {
  Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (int s : o.shapes) {
    if (scene_.materials[std::size_t(scene_.objects[std::size_t(s)].material)].model !=
        MaterialModel::plastic)
      continue;
    Vec3d l, h;
    rest_[std::size_t(s)].bounds(D, l, h);
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], l[a]);
      hi[a] = std::max(hi[a], h[a]);
    }
  }
  if (!(lo[0] <= hi[0])) return;  // no plastic shape in this grid
  const EulerianGrid<T, D>& g = o.grid;
  const double dx = double(g.dx);
  std::array<int, D> first, count;
  for (int a = 0; a < D; ++a) {
    const double base = double(o.frame.p[a]) + double(g.origin[a]);
    const int l = int(std::floor((lo[a] - dx - base) / dx)),
              h = int(std::ceil((hi[a] + dx - base) / dx));
    first[std::size_t(a)] = std::clamp(l, 0, g.n[std::size_t(a)] - 1);
    count[std::size_t(a)] = std::clamp(h, 0, g.n[std::size_t(a)] - 1) - first[std::size_t(a)] + 1;
  }
  PlasticSamples<T, D>& s = o.plastic;
  s.n = count;
  s.h = g.dx;
  s.origin = g.X[g.index(first)];
  std::size_t total = 1;
  for (int a = 0; a < D; ++a) total *= std::size_t(count[std::size_t(a)]);
  s.fp_inv.assign(total, Mat<T, D>::Identity());
  s.identity.assign(total, 1);
  s.material.assign(total, -1);
  s.y.resize(total);
  for (std::size_t i = 0; i < total; ++i) {
    std::array<int, D> c;
    std::size_t r = i;
    for (int a = 0; a < D; ++a) {
      c[std::size_t(a)] = first[std::size_t(a)] + int(r % std::size_t(count[std::size_t(a)]));
      r /= std::size_t(count[std::size_t(a)]);
    }
    s.y[i] = g.y(g.index(c));
    Vec3d Z{0, 0, 0};
    for (int a = 0; a < D; ++a) Z[a] = double(s.position(i)[a]);
    double nearest = dx;
    for (int shape : o.shapes) {
      const int m = scene_.objects[std::size_t(shape)].material;
      const double phi = rest_[std::size_t(shape)].distance(Z, D);
      if (materials_[std::size_t(m)].model == MaterialModel::plastic && phi < nearest) {
        nearest = phi;
        s.material[i] = m;
      }
    }
  }
}

template <class T, int D>
void EolSimulation<T, D>::plastic_flow() {
  StageTimer timer{stages_.forces};  // the constitutive model's part of the step
  for (auto& o : objects_)
    if (!o.plastic.empty()) update_plastic_samples(o.grid, materials_, o.plastic, parallel_);
}

}  // namespace apiclab::eol
