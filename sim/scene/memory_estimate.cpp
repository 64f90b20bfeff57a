#include "sim/scene/memory_estimate.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "sim/eol/shape/rest_shape.hpp"
#include "sim/geometry/sampling.hpp"
#include "sim/mpm/block_partition.hpp"
#include "sim/mpm/grid.hpp"
#include "sim/mpm/kernels.hpp"
#include "sim/mpm/particles.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"
#include "sim/mpm/stencil.hpp"

namespace apiclab {
namespace {

// Volume (3D) or area (2D) of a shape, before rotation (rotations keep it).
double shape_volume(const SceneDesc& scene, int object_index) {
  const ShapeDesc& s = scene.objects[size_t(object_index)].shape;
  const int dim = scene.dim;
  switch (s.type) {
    case ShapeType::box: {
      double v = 1;
      for (int a = 0; a < dim; ++a) v *= s.max[a] - s.min[a];
      return v;
    }
    case ShapeType::ball:
      return dim == 2 ? M_PI * s.radius * s.radius : 4.0 / 3.0 * M_PI * std::pow(s.radius, 3);
    case ShapeType::annulus: {
      const double area = M_PI * (s.outer * s.outer - s.inner * s.inner);
      return dim == 2 ? area : area * s.length;
    }
    case ShapeType::torus: {  // 2 pi^2 R r^2 with the tube's centre radius R and radius r
      const double R = 0.5 * (s.inner + s.outer), r = 0.5 * (s.outer - s.inner);
      return 2 * M_PI * M_PI * R * r * r;
    }
    case ShapeType::mesh:
      return load_mesh_solid(scene, object_index)->volume();  // placed: scaled, in the domain
  }
  return 0;
}

// Poisson disk sampling fills the shape's bounding box, then keeps the samples inside
// (sim/geometry/sampling.cpp): its transient count goes with the box.
double box_volume(const SceneDesc& scene, int object_index, double shape_vol) {
  const ShapeDesc& s = scene.objects[size_t(object_index)].shape;
  if (s.type == ShapeType::mesh) return shape_vol;  // a lower bound: the mesh's own volume
  Vec3d lo, hi;
  shape_bounds(s, scene.dim, lo, hi);
  double v = 1;
  for (int a = 0; a < scene.dim; ++a) v *= hi[a] - lo[a];
  return v;
}

double particle_count(const SceneDesc& scene) {
  double n = 0;
  for (int o = 0; o < int(scene.objects.size()); ++o) {
    const ObjectDesc& obj = scene.objects[size_t(o)];
    const SamplingDesc& smp = obj.sampling;
    if (smp.type == SamplingType::triangulated) {
      n += (std::round((obj.shape.max[0] - obj.shape.min[0]) / smp.spacing) + 1) *
           (std::round((obj.shape.max[1] - obj.shape.min[1]) / smp.spacing) + 1);
      continue;
    }
    const double v = shape_volume(scene, o);
    switch (smp.type) {
      case SamplingType::ppc:
        n += v / std::pow(scene.domain.dx, scene.dim) * smp.ppc;
        break;
      case SamplingType::lattice:
        n += v / std::pow(smp.spacing, scene.dim);
        break;
      case SamplingType::poisson:  // at most one sample per r^d of the bounding box
        n += box_volume(scene, o, v) / std::pow(smp.radius, scene.dim);
        break;
      case SamplingType::triangulated:
        break;
    }
  }
  return n;
}

// The grid stores only the active box (sim/mpm/grid.hpp, sim/mpm/block_partition.hpp): the blocks
// of B cells that hold particles, widened by the stencil's reach; periodic axes whole. Estimated
// from the objects' bounding boxes at the start, so a small object in a huge domain is not refused;
// a box that grows later (objects flying apart) can exceed it.
double grid_nodes(const SceneDesc& scene) {
  const int dim = scene.dim;
  Vec3d lo{}, hi{};
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::numeric_limits<double>::max();
    hi[a] = -lo[a];
  }
  for (int o = 0; o < int(scene.objects.size()); ++o) {
    const ShapeDesc& shape = scene.objects[size_t(o)].shape;
    Vec3d olo{}, ohi{};
    if (shape.type == ShapeType::mesh) {
      const auto mesh = load_mesh_solid(scene, o);
      olo = mesh->lower();
      ohi = mesh->upper();
    } else {
      shape_bounds(shape, dim, olo, ohi);
    }
    for (int a = 0; a < dim; ++a) {
      lo[a] = std::min(lo[a], olo[a]);
      hi[a] = std::max(hi[a], ohi[a]);
    }
  }
  const double dx = scene.domain.dx;
  const double B = BlockPartition<double, 2>::block_cells(scene.solver.kernel);
  double n = 1;
  for (int a = 0; a < dim; ++a) {
    const double cells = (scene.domain.max[a] - scene.domain.min[a]) / dx;
    if (scene.domain.periodic(a)) {
      n *= std::round(cells);
      continue;
    }
    if (scene.objects.empty()) return 0;
    // As BlockPartition::sort: node 0 lies two ghost nodes below the domain's minimum.
    const double nodes = std::ceil(cells - 1e-9) + 1 + 2 * 2;
    auto block = [&](double x) {
      const double cell = std::floor((x - (scene.domain.min[a] - 2 * dx)) / dx);
      const double clamped = std::min(std::max(cell, 0.0), nodes - 1);
      return std::min(std::floor(clamped / B), std::ceil(nodes / B) - 1);
    };
    const double first = std::max(0.0, B * block(lo[a]) - 2);
    const double last = std::min(nodes, B * (block(hi[a]) + 1) + 3);
    n *= std::max(0.0, last - first);
  }
  return n;
}

// The arrays MpmSimulation<T, D> keeps (sim/mpm/mpm.hpp, grid.hpp, particles.hpp).
template <class T, int D>
void bytes_per_item(const SceneDesc& scene, MemoryEstimate& e) {
  using V = Vec<T, D>;
  using M = Mat<T, D>;
  // Grid: mass, velocity, velocity_new, force and the 8-lane P2G accumulator.
  e.bytes_per_node = sizeof(T) + 3 * sizeof(V) + sizeof(typename Grid<T, D>::NodeLanes);
  // Particles and the sort's scratch copy, the stress, one stencil cache, the drawing radius,
  // id table and the sort keys and order.
  const double particles = 2 * (2 * sizeof(V) + 2 * sizeof(M) + 2 * sizeof(T) + 3 * 4);
  double stencil = 0;
  switch (scene.solver.kernel) {
    case KernelType::linear:
      stencil = sizeof(Stencil<T, D, LinearKernel>);
      break;
    case KernelType::quadratic:
      stencil = sizeof(Stencil<T, D, QuadraticKernel>);
      break;
    case KernelType::cubic:
      stencil = sizeof(Stencil<T, D, CubicKernel>);
      break;
  }
  e.bytes_per_particle = particles + sizeof(M) + stencil + 4 + 4 + 8;
  // XPIC(m > 1): the series term and its sum per node (sim/mpm/schemes/xpic_passes.hpp).
  if (scene.solver.scheme == Scheme::xpic && scene.solver.xpic_order > 1)
    e.bytes_per_node += 2 * sizeof(V);
  if (scene.solver.scheme == Scheme::polypic)  // its higher modes, and their sort copy
    e.bytes_per_particle +=
        2.0 * polypic::extra_modes(polypic::kept_modes(scene.solver.polypic_modes, D), D) *
        sizeof(V);
  if (scene.solver.integrator != Integrator::symplectic) {
    // Implicit: F at y and the stiffness operator per particle; Newton and CG vectors on the
    // nodes (Sec 4.2).
    e.bytes_per_particle += sizeof(M) + sizeof(Eigen::Matrix<T, D * D, D * D>);
    e.bytes_per_node += 6 * sizeof(V) + 4;
  }
}

// The Eulerian-on-Lagrangian family (sim/eol): no particles, one grid per object, around the
// object (eol) or over the domain (eulerian), sized as EolSimulation::add_object_grid sizes them.
// Without it a tiny solver.cell or a large solver.grid_extent allocated until std::bad_alloc (fuzz
// finding).
void eol_estimate(const SceneDesc& scene, MemoryEstimate& e) {
  const EolSolverDesc& s = scene.solver.eol;
  auto nodes = [&](const Vec3d& lo, const Vec3d& hi, double dx, int padding) {
    double n = 1;
    for (int a = 0; a < scene.dim; ++a)
      n *= std::ceil((hi[a] - lo[a]) / dx - 1e-9) + 1 + 2 * padding;
    return n;
  };
  if (scene.solver.method == "eulerian") {
    e.grid_nodes = double(scene.objects.size()) *
                   nodes(scene.domain.min, scene.domain.max, scene.domain.dx, 0);
  } else {
    const double dx = s.cell > 0 ? s.cell : scene.domain.dx;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
      const ObjectDesc& o = scene.objects[i];
      Vec3d lo{}, hi{};
      if (o.shape.type == ShapeType::mesh) {  // read as the sampler reads it (bounds only)
        const auto mesh = load_mesh_solid(scene, int(i));
        lo = mesh->lower();
        hi = mesh->upper();
      } else {
        eol::rest_bounds(o.shape, scene.dim, lo, hi);
      }
      if (s.grid_extent > 0)
        for (int a = 0; a < scene.dim; ++a) {
          lo[a] = 0;
          hi[a] = s.grid_extent;
        }
      e.grid_nodes += nodes(lo, hi, dx, s.grid_extent > 0 ? 0 : s.padding);
    }
  }
  // Double precision only. Per node: r, x, u, force, scratch, v* and the owner
  // (eol_simulation.hpp), the grid's own fields, the elastic forces' and the extrapolation's
  // scratch, counted generously as six more vectors and two matrices.
  const double vec = scene.dim * sizeof(double), mat = scene.dim * vec;
  e.bytes_per_node = 12 * vec + 2 * mat + 4;
  e.particles = 0;
  e.bytes_per_particle = 0;
}

}  // namespace

std::string format_bytes(double b) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (b >= 1000 && u < 6) {
    b /= 1000;
    ++u;
  }
  std::ostringstream s;
  s.precision(b < 10 ? 2 : 3);
  s << b << " " << units[u];
  return s.str();
}

std::string MemoryEstimate::text() const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "about %s (%.3g grid nodes x %.0f B + %.3g particles x %.0f B)",
                format_bytes(bytes()).c_str(), grid_nodes, bytes_per_node, particles,
                bytes_per_particle);
  return buf;
}

MemoryEstimate estimate_memory(const SceneDesc& scene, Precision precision) {
  MemoryEstimate e;
  if (scene.solver.method == "eol" || scene.solver.method == "eulerian") {
    eol_estimate(scene, e);
    return e;
  }
  e.grid_nodes = grid_nodes(scene);
  e.particles = particle_count(scene);
  const bool single = precision == Precision::single;
  if (scene.dim == 2)
    single ? bytes_per_item<float, 2>(scene, e) : bytes_per_item<double, 2>(scene, e);
  else
    single ? bytes_per_item<float, 3>(scene, e) : bytes_per_item<double, 3>(scene, e);
  return e;
}

MemoryEstimate estimate_roundtrip_memory(int resolution, Scheme scheme, int xpic_order) {
  SceneDesc s;
  s.dim = 2;
  s.solver.scheme = scheme;
  s.solver.xpic_order = xpic_order;
  s.domain.max = {2 * M_PI, 2 * M_PI, 0};
  s.domain.dx = 2 * M_PI / resolution;
  s.domain.walls.fill(BoundaryCondition::periodic);
  MemoryEstimate e;
  e.grid_nodes = double(resolution) * double(resolution);
  // Poisson disk at separation dx/3 over the whole periodic square.
  e.particles = std::pow(3.0 * resolution, 2);
  bytes_per_item<double, 2>(s, e);
  e.bytes_per_node += 2 * sizeof(Vec<double, 2>);  // the probe's before/after velocities
  return e;
}

std::optional<double> available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string name, unit;
  double value = 0;
  while (in >> name >> value) {
    std::getline(in, unit);
    if (name == "MemAvailable:") return value * 1024;  // the file's kB are KiB
  }
  return std::nullopt;
}

std::optional<double> memory_cap_bytes(const SceneDesc& scene) {
  if (scene.solver.max_memory_gb) return *scene.solver.max_memory_gb * 1e9;
  return available_memory_bytes();
}

void check_memory(const MemoryEstimate& estimate, std::optional<double> cap_bytes,
                  const std::string& what) {
  if (!cap_bytes || estimate.bytes() <= *cap_bytes) return;
  const auto available = available_memory_bytes();
  throw SceneError(what + ": needs " + estimate.text() + ", more than the cap of " +
                   format_bytes(*cap_bytes) +
                   (available ? " (available memory " + format_bytes(*available) + ")" : "") +
                   "; use a coarser dx or sampling, or set the cap with --max-memory or "
                   "solver.max_memory_gb");
}

void check_memory(const SceneDesc& scene, Precision precision) {
  check_memory(estimate_memory(scene, precision), memory_cap_bytes(scene), scene.source);
}

}  // namespace apiclab
