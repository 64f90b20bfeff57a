// What the EoL solver shows (Fan et al. 2013, Sec 3.8 and Figs 2, 6): every node that holds
// material as a dot at its world position with its spatial velocity (the renderer's particle
// path, so colours, vectors and auto-scaling work unchanged), and each object's grid as a
// GridLayer in its frame with the node fields mass, speed and det(∇X) (empty nodes NaN), and
// its surface as placed by Algorithm 2 (Sec 3.8) with the interpolated spatial velocity (placed
// here, on a copy, when the last step did not reach a frame time).
#pragma once
#include <limits>
#include <string>
#include <vector>

#include "sim/eol/eol_simulation.hpp"

namespace apiclab::eol {
namespace detail {

// Every node the rest shape covers, as a dot at x with u.
template <class T, int D>
void add_node_dots(const EolObject<T, D>& o, Snapshot& s) {
  const EulerianGrid<T, D>& g = o.grid;
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (!(g.fill[i] >= T(0.5))) continue;
    for (int a = 0; a < D; ++a) {
      s.positions.push_back(float(o.x[i][a]));
      s.velocities.push_back(float(o.u[i][a]));
    }
    s.material.push_back(g.material[i]);
    s.object.push_back(o.owner[i]);
    s.radius.push_back(float(0.5 * double(g.dx)));
  }
}

// The object's grid in its frame, with the node fields mass, speed and det(∇X) (empty: NaN).
template <class T, int D>
GridLayer grid_layer(const EolObject<T, D>& o, const std::string& name) {
  const EulerianGrid<T, D>& g = o.grid;
  GridLayer layer;
  layer.name = name;
  const Mat<T, D> R = o.frame.rotation();
  for (int r = 0; r < D; ++r)
    for (int c = 0; c < D; ++c) layer.rotation[std::size_t(3 * r + c)] = double(R(r, c));
  const Vec<T, D> node0 = R * g.origin + o.frame.p;
  for (int a = 0; a < D; ++a) {
    layer.translation[std::size_t(a)] = double(node0[a]);
    layer.nodes[std::size_t(a)] = g.n[std::size_t(a)];
  }
  layer.dx = double(g.dx);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  GridLayer::Field mass{"mass", {}}, speed{"speed", {}}, det{"det_grad_X", {}};
  for (std::size_t i = 0; i < g.size(); ++i) {
    const bool full = g.mass[i] > T(0);
    mass.values.push_back(full ? float(g.mass[i]) : nan);
    speed.values.push_back(full ? float(o.u[i].norm()) : nan);
    det.values.push_back(full ? float(g.gradient(g.X, i).determinant()) : nan);
  }
  layer.fields = {std::move(mass), std::move(speed), std::move(det)};
  return layer;
}

// The surface at its placed intermediate points y, in world positions with the interpolated u.
template <class T, int D>
SurfaceLayer surface_layer(const EolObject<T, D>& o, const std::vector<Vec<T, D>>& placed,
                           const std::string& name) {
  SurfaceLayer surface;
  surface.name = name;
  for (std::size_t v = 0; v < o.surface.size(); ++v) {
    const Vec<T, D> x = o.world(placed[v]), u = o.grid.interpolate(o.u, placed[v]);
    for (int a = 0; a < D; ++a) {
      surface.positions.push_back(float(x[a]));
      surface.velocities.push_back(float(u[a]));
    }
  }
  surface.elements = o.surface.simplex;
  return surface;
}

}  // namespace detail

template <class T, int D>
std::shared_ptr<Snapshot> EolSimulation<T, D>::snapshot() const {
  std::shared_ptr<Snapshot> s = scene_snapshot();
  s->scheme = lagrangian_ ? "eol" : "eulerian";
  s->kernel = "multilinear";
  s->integrator = "explicit";
  for (const EolObject<T, D>& o : objects_) {
    detail::add_node_dots(o, *s);
    // eulerian: one object's grid is the world's; with several, each object's field has its name.
    const bool world = !lagrangian_ && objects_.size() == 1;
    const std::string name = world ? "world" : scene_.objects[std::size_t(o.shapes[0])].name;
    s->grids.push_back(detail::grid_layer(o, name));
    s->surfaces.push_back(detail::surface_layer(o, placed_surface(o), name));
  }
  return s;
}

}  // namespace apiclab::eol
