// What the EoL solver shows (Fan et al. 2013, Sec 3.8 and Figs 2, 6): every node that holds
// material as a dot at its world position with its spatial velocity (the renderer's particle
// path, so colours, vectors and auto-scaling work unchanged), and each object's grid as a
// GridLayer in its frame with the node fields mass, speed and det(∇X) (empty nodes NaN), and
// its surface as placed by Algorithm 2 (Sec 3.8) with the interpolated spatial velocity (placed
// here, on a copy, when the last step did not land on a frame time).
#pragma once
#include <limits>

#include "sim/eol/eol_simulation.hpp"

namespace apiclab::eol {

template <class T, int D>
std::shared_ptr<Snapshot> EolSimulation<T, D>::snapshot() const {
  auto s = std::make_shared<Snapshot>();
  s->dim = D;
  s->step = steps_;
  s->time = time_;
  s->scene_name = scene_.name;
  s->scheme = lagrangian_ ? "eol" : "eulerian";
  s->kernel = "multilinear";
  s->integrator = "explicit";
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    const EolObject<T, D>& o = objects_[k];
    const EulerianGrid<T, D>& g = o.grid;
    for (std::size_t i = 0; i < g.size(); ++i) {
      if (!(g.fill[i] >= T(0.5))) continue;  // the nodes the rest shape covers
      for (int a = 0; a < D; ++a) {
        s->positions.push_back(float(o.x[i][a]));
        s->velocities.push_back(float(o.u[i][a]));
      }
      s->material.push_back(g.material[i]);
      s->object.push_back(o.owner[i]);
      s->radius.push_back(float(0.5 * double(g.dx)));
    }
    GridLayer layer;
    layer.name = lagrangian_ ? scene_.objects[std::size_t(o.shapes[0])].name : "world";
    const Mat<T, D> R = o.frame.rotation();
    for (int r = 0; r < D; ++r)
      for (int c = 0; c < D; ++c) layer.rotation[std::size_t(3 * r + c)] = double(R(r, c));
    const Vec<T, D> node0 = R * g.origin + o.frame.p;
    for (int a = 0; a < D; ++a) {
      layer.translation[std::size_t(a)] = double(node0[a]);
      layer.nodes[std::size_t(a)] = g.n[std::size_t(a)];
    }
    layer.dx = double(g.dx);
    GridLayer::Field mass{"mass", {}}, speed{"speed", {}}, det{"det_grad_X", {}};
    for (std::size_t i = 0; i < g.size(); ++i) {
      const bool full = g.mass[i] > T(0);
      mass.values.push_back(full ? float(g.mass[i]) : nan);
      speed.values.push_back(full ? float(o.u[i].norm()) : nan);
      det.values.push_back(full ? float(g.gradient(g.X, i).determinant()) : nan);
    }
    layer.fields = {std::move(mass), std::move(speed), std::move(det)};
    SurfaceLayer surface;
    surface.name = layer.name;
    const std::vector<Vec<T, D>> placed = placed_surface(o);
    for (std::size_t v = 0; v < o.surface.size(); ++v) {
      const Vec<T, D> x = o.world(placed[v]), u = g.interpolate(o.u, placed[v]);
      for (int a = 0; a < D; ++a) {
        surface.positions.push_back(float(x[a]));
        surface.velocities.push_back(float(u[a]));
      }
    }
    surface.elements = o.surface.simplex;
    s->grids.push_back(std::move(layer));
    s->surfaces.push_back(std::move(surface));
  }
  s->domain_min = scene_.domain.min;
  s->domain_max = scene_.domain.max;
  s->dx = scene_.domain.dx;
  s->colliders = scene_.colliders;
  for (const auto& m : scene_.materials) s->material_names.push_back(m.name);
  s->failure = failure_;
  return s;
}

}  // namespace apiclab::eol
