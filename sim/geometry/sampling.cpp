#include "sim/geometry/sampling.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <mutex>
#include <random>

#include "sim/geometry/mesh_inside.hpp"
#include "sim/geometry/obj_mesh.hpp"
#include "sim/scene/input_file.hpp"

namespace apiclab {
namespace {

Eigen::Vector3d to_eigen(const Vec3d& v) { return {v[0], v[1], v[2]}; }
Vec3d from_eigen(const Eigen::Vector3d& v) { return {v[0], v[1], v[2]}; }

Eigen::Matrix3d rotation_of(const ShapeDesc& s) {
  Eigen::Vector3d axis = to_eigen(s.rotation_axis);
  if (s.rotation_degrees == 0 || axis.norm() == 0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(s.rotation_degrees * M_PI / 180.0, axis.normalized()).toRotationMatrix();
}

// Position relative to the shape center, in the shape's unrotated frame.
Eigen::Vector3d local_point(const ShapeDesc& s, const Vec3d& x) {
  return rotation_of(s).transpose() * (to_eigen(x) - to_eigen(s.center));
}

// Distance from the (unit) axis through the origin and position along it.
void axial(const Eigen::Vector3d& p, const Vec3d& axis_in, double& radial, double& along) {
  Eigen::Vector3d a = to_eigen(axis_in).normalized();
  along = p.dot(a);
  radial = (p - along * a).norm();
}

}  // namespace

void shape_bounds(const ShapeDesc& s, int dim, Vec3d& lo, Vec3d& hi) {
  if (s.type == ShapeType::box && s.rotation_degrees == 0) {
    lo = s.min;
    hi = s.max;
    return;
  }
  double r = 0;
  if (s.type == ShapeType::box) {
    for (int a = 0; a < dim; ++a) r += 0.25 * (s.max[a] - s.min[a]) * (s.max[a] - s.min[a]);
    r = std::sqrt(r);
  } else if (s.type == ShapeType::ball) {
    r = s.radius;
  } else if (s.type == ShapeType::annulus) {
    r = dim == 3 ? std::hypot(s.outer, 0.5 * s.length) : s.outer;
  } else {
    r = s.outer;
  }
  for (int a = 0; a < 3; ++a) {
    lo[a] = a < dim ? s.center[a] - r : 0;
    hi[a] = a < dim ? s.center[a] + r : 0;
  }
}

bool inside_shape(const ShapeDesc& s, const Vec3d& x, int dim) {
  Eigen::Vector3d p = local_point(s, x);
  if (dim == 2) p[2] = 0;
  switch (s.type) {
    case ShapeType::box:
      for (int a = 0; a < dim; ++a) {
        double half = 0.5 * (s.max[a] - s.min[a]);
        if (std::abs(p[a]) > half) return false;
      }
      return true;
    case ShapeType::ball:
      return p.squaredNorm() <= s.radius * s.radius;
    case ShapeType::annulus: {
      if (dim == 2) {
        double r = p.norm();
        return r >= s.inner && r <= s.outer;
      }
      double radial, along;
      axial(p, s.axis, radial, along);
      return radial >= s.inner && radial <= s.outer && std::abs(along) <= 0.5 * s.length;
    }
    case ShapeType::torus: {
      double radial, along;
      axial(p, s.axis, radial, along);
      double R = 0.5 * (s.inner + s.outer), r = 0.5 * (s.outer - s.inner);
      return (radial - R) * (radial - R) + along * along <= r * r;
    }
    case ShapeType::mesh:
      return false;  // needs a MeshSolid
  }
  return false;
}

std::vector<Vec3d> place_mesh_vertices(const ShapeDesc& shape, const ObjMesh& obj) {
  const Eigen::Matrix3d R = rotation_of(shape);
  std::vector<Vec3d> out;
  out.reserve(obj.vertices.size());
  for (const auto& p : obj.vertices)
    out.push_back(from_eigen(R * (shape.scale * Eigen::Vector3d(p[0], p[1], p[2])) +
                             to_eigen(shape.translate)));
  return out;
}

struct MeshSolid::Search {
  std::once_flag built;
  std::unique_ptr<MeshWinding> winding;
};

MeshSolid::MeshSolid(const std::string& path, const ShapeDesc& shape)
    : MeshSolid(load_obj_mesh(path), shape) {}  // checked: numbers, indices, closed surface

MeshSolid::MeshSolid(const ObjMesh& obj, const ShapeDesc& shape)
    : vertices_(place_mesh_vertices(shape, obj)),
      triangles_(obj.triangles),
      search_(std::make_unique<Search>()) {
  const double inf = std::numeric_limits<double>::infinity();
  lo_ = {inf, inf, inf};
  hi_ = {-inf, -inf, -inf};
  // Within ±1e307 (NaN fails): the inside test's segments, twice the box long, stay finite.
  for (const auto& t : triangles_)
    for (std::uint32_t i : t)
      for (int a = 0; a < 3; ++a) {
        const double x = vertices_[i][std::size_t(a)];
        finite_ = finite_ && std::abs(x) <= 1e307;
        lo_[std::size_t(a)] = std::min(lo_[std::size_t(a)], x);
        hi_[std::size_t(a)] = std::max(hi_[std::size_t(a)], x);
      }
}

MeshSolid::~MeshSolid() = default;
MeshSolid::MeshSolid(MeshSolid&&) noexcept = default;

const MeshWinding& MeshSolid::search() const {
  // Exact predicates: a ray-parity test in floating point miscounts rays through edges and
  // vertices, which a lattice hits on a mesh with round coordinates.
  std::call_once(search_->built, [&] {
    search_->winding = std::make_unique<MeshWinding>(vertices_, triangles_, lo_, hi_);
  });
  return *search_->winding;
}

bool MeshSolid::inside(const Vec3d& p) const {
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= lo_[a] && p[a] <= hi_[a])) return false;
  const MeshWinding::Result r = search().winding(p);
  return r.on_surface || r.winding != 0;
}

void MeshSolid::inside_run(const std::vector<Vec3d>& points, std::vector<char>& in) const {
  in.assign(points.size(), 0);
  if (points.empty()) return;
  const MeshWinding& w = search();
  MeshWinding::Result r = w.winding(points[0]);
  in[0] = r.on_surface || r.winding != 0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    r = w.walk(points[i - 1], r, points[i]);
    in[i] = r.on_surface || r.winding != 0;
  }
}

double MeshSolid::volume() const {
  // In the box's frame, per axis in units of its extent: no cancellation far from the origin,
  // no overflow inside the sum for a huge mesh.
  const Eigen::Vector3d m = 0.5 * to_eigen(lo_) + 0.5 * to_eigen(hi_);
  Eigen::Vector3d unit = to_eigen(hi_) - to_eigen(lo_);
  for (int a = 0; a < 3; ++a)
    if (!(unit[a] > 0)) unit[a] = 1;
  auto local = [&](std::uint32_t i) -> Eigen::Vector3d {
    return ((to_eigen(vertices_[i]) - m).array() / unit.array()).matrix();
  };
  double v = 0;
  for (const auto& t : triangles_) v += local(t[0]).dot(local(t[1]).cross(local(t[2]))) / 6.0;
  return std::abs(v) * unit[0] * unit[1] * unit[2];
}

std::unique_ptr<MeshSolid> load_mesh_solid(const SceneDesc& scene, int object_index) {
  auto mesh = std::make_unique<MeshSolid>(resolve_mesh_file(scene, object_index),
                                          scene.objects[size_t(object_index)].shape);
  check_mesh_placement(scene, object_index, *mesh);
  return mesh;
}

void check_mesh_placement(const SceneDesc& scene, int object_index, const MeshSolid& mesh) {
  const std::string where =
      scene.source + ": key 'objects." + std::to_string(object_index) + ".shape': ";
  if (!mesh.finite())
    throw SceneError(where +
                     "the mesh placed by scale, rotation and translate is too large: its "
                     "coordinates reach beyond 1e307 (near a double's range)");
  auto g = [](double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", x);
    return std::string(b);
  };
  const Vec3d lo = mesh.lower(), hi = mesh.upper();
  for (int a = 0; a < scene.dim; ++a)
    if (lo[a] < scene.domain.min[a] || hi[a] > scene.domain.max[a])
      throw SceneError(where + "mesh lies outside the domain on axis " + std::string(1, "xyz"[a]) +
                       ": it spans [" + g(lo[a]) + ", " + g(hi[a]) + "], the domain [" +
                       g(scene.domain.min[a]) + ", " + g(scene.domain.max[a]) + "]");
}

std::vector<Vec3d> poisson_disk(const Vec3d& lo, const Vec3d& hi, double r, int dim,
                                std::uint64_t seed, bool periodic) {
  // Bridson 2007: background grid of cell r/√d holds at most one sample; k = 30 tries.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double cell = r / std::sqrt(double(dim));
  std::array<int, 3> n{1, 1, 1};
  for (int a = 0; a < dim; ++a) n[a] = std::max(1, int(std::ceil((hi[a] - lo[a]) / cell)));
  std::vector<int> grid(size_t(n[0]) * n[1] * n[2], -1);
  std::vector<Vec3d> samples, active;
  auto cell_of = [&](const Vec3d& x, int a) {
    return std::clamp(int((x[a] - lo[a]) / cell), 0, n[a] - 1);
  };
  auto index = [&](int i, int j, int k) { return (size_t(k) * n[1] + j) * n[0] + i; };
  auto far_enough = [&](const Vec3d& x) {
    int c[3] = {cell_of(x, 0), cell_of(x, 1), dim == 3 ? cell_of(x, 2) : 0};
    int reach = 2;
    for (int dk = (dim == 3 ? -reach : 0); dk <= (dim == 3 ? reach : 0); ++dk)
      for (int dj = -reach; dj <= reach; ++dj)
        for (int di = -reach; di <= reach; ++di) {
          int ii = c[0] + di, jj = c[1] + dj, kk = c[2] + dk;
          int q[3] = {ii, jj, kk};
          bool skip = false;
          for (int a = 0; a < dim; ++a) {
            if (q[a] < 0 || q[a] >= n[a]) {
              if (!periodic) {
                skip = true;
                break;
              }
              q[a] = (q[a] % n[a] + n[a]) % n[a];
            }
          }
          if (skip) continue;
          int s = grid[index(q[0], q[1], q[2])];
          if (s < 0) continue;
          double d2 = 0;
          for (int a = 0; a < dim; ++a) {
            double d = x[a] - samples[s][a];
            if (periodic) {
              double L = hi[a] - lo[a];
              d -= L * std::round(d / L);
            }
            d2 += d * d;
          }
          if (d2 < r * r) return false;
        }
    return true;
  };
  auto add = [&](const Vec3d& x) {
    grid[index(cell_of(x, 0), cell_of(x, 1), dim == 3 ? cell_of(x, 2) : 0)] = int(samples.size());
    samples.push_back(x);
    active.push_back(x);
  };
  Vec3d first{0, 0, 0};
  for (int a = 0; a < dim; ++a) first[a] = lo[a] + uni(rng) * (hi[a] - lo[a]);
  add(first);
  while (!active.empty()) {
    size_t pick = size_t(uni(rng) * double(active.size())) % active.size();
    Vec3d base = active[pick];
    bool found = false;
    for (int attempt = 0; attempt < 30 && !found; ++attempt) {
      // Uniform in the spherical shell [r, 2r) around the base sample.
      Vec3d dir{0, 0, 0};
      double norm2 = 0;
      do {
        norm2 = 0;
        for (int a = 0; a < dim; ++a) {
          dir[a] = 2 * uni(rng) - 1;
          norm2 += dir[a] * dir[a];
        }
      } while (norm2 > 1 || norm2 < 1e-12);
      double rad = r * (1 + uni(rng));
      Vec3d x{0, 0, 0};
      bool in = true;
      for (int a = 0; a < dim; ++a) {
        x[a] = base[a] + rad * dir[a] / std::sqrt(norm2);
        if (x[a] < lo[a] || x[a] >= hi[a]) {
          if (!periodic) {
            in = false;
            break;
          }
          double L = hi[a] - lo[a];
          x[a] = lo[a] + std::fmod(std::fmod(x[a] - lo[a], L) + L, L);
        }
      }
      if (in && far_enough(x)) {
        add(x);
        found = true;
      }
    }
    if (!found) {
      active[pick] = active.back();
      active.pop_back();
    }
  }
  return samples;
}

std::string resolve_mesh_file(const SceneDesc& scene, int object_index) {
  namespace fs = std::filesystem;
  const ShapeDesc& shape = scene.objects[size_t(object_index)].shape;
  const std::string key = "objects." + std::to_string(object_index);
  fs::path file = shape.file;
  if (file.is_relative()) {
    // Beside the scene, in the folder above it (assets/scenes/x.json -> assets/meshes/),
    // then in the folders the app names.
    const fs::path folder = fs::path(scene.source).parent_path();
    std::vector<fs::path> candidates{folder / file, folder.parent_path() / file};
    for (const auto& dir : scene.asset_dirs) candidates.push_back(fs::path(dir) / file);
    for (const auto& c : candidates)
      if (fs::exists(c)) {
        file = c;
        break;
      }
  }
  if (!fs::exists(file))
    throw SceneError(scene.source + ": key '" + key + ".shape.file': mesh file '" + shape.file +
                     "' not found");
  if (std::string problem = input_file_problem(file.string(), "mesh file"); !problem.empty())
    throw SceneError(scene.source + ": key '" + key + ".shape.file': '" + file.string() + "' " +
                     problem);
  return file.string();
}

SampledParticles sample_object(const SceneDesc& scene, int object_index) {
  const ObjectDesc& obj = scene.objects[size_t(object_index)];
  const ShapeDesc& shape = obj.shape;
  const int dim = scene.dim;
  const std::string key = "objects." + std::to_string(object_index);
  std::unique_ptr<MeshSolid> mesh;
  Vec3d lo{0, 0, 0}, hi{0, 0, 0};
  if (shape.type == ShapeType::mesh) {
    mesh = load_mesh_solid(scene, object_index);  // finite and inside the domain
    lo = mesh->lower();
    hi = mesh->upper();
  } else {
    shape_bounds(shape, dim, lo, hi);
  }
  auto inside = [&](const Vec3d& x) {
    return mesh ? mesh->inside(x) : inside_shape(shape, x, dim);
  };

  SampledParticles out;
  const SamplingDesc& smp = obj.sampling;
  if (smp.type == SamplingType::poisson) {
    std::vector<Vec3d> pts = poisson_disk(lo, hi, smp.radius, dim, smp.seed);
    size_t total = pts.size();
    for (auto& x : pts)
      if (inside(x)) out.positions.push_back(x);
    double box = 1;
    for (int a = 0; a < dim; ++a) box *= hi[a] - lo[a];
    // Poisson samples are uniform: each represents an equal share of the box.
    double vol = total ? box / double(total) : 0;
    out.volumes.assign(out.positions.size(), vol);
    out.spacing = smp.radius;
  } else {
    double s = smp.type == SamplingType::lattice ? smp.spacing
                                                 : scene.domain.dx / std::pow(smp.ppc, 1.0 / dim);
    // Grid-aligned: sample k sits at domain.min + (k + ½) s, so s = dx/2 gives 4 per full cell in
    // 2D.
    std::array<long, 3> k0{0, 0, 0}, k1{0, 0, 0};
    for (int a = 0; a < dim; ++a) {
      k0[a] = long(std::floor((lo[a] - scene.domain.min[a]) / s - 0.5));
      k1[a] = long(std::ceil((hi[a] - scene.domain.min[a]) / s - 0.5));
    }
    double count = 1;
    for (int a = 0; a < dim; ++a) count *= double(k1[a] - k0[a] + 1);
    if (count > 5e7)
      throw SceneError(scene.source + ": key '" + key +
                       ".sampling': more than 5e7 lattice sites; spacing too small");
    std::vector<Vec3d> row;
    std::vector<char> in;
    for (long k = k0[2]; k <= k1[2]; ++k)
      for (long j = k0[1]; j <= k1[1]; ++j) {
        row.clear();
        for (long i = k0[0]; i <= k1[0]; ++i)
          row.push_back({scene.domain.min[0] + (i + 0.5) * s, scene.domain.min[1] + (j + 0.5) * s,
                         dim == 3 ? scene.domain.min[2] + (k + 0.5) * s : 0.0});
        if (mesh) {
          mesh->inside_run(row, in);  // a row at a time: the same answers as inside(), faster
        } else {
          in.resize(row.size());
          for (std::size_t i = 0; i < row.size(); ++i) in[i] = inside(row[i]);
        }
        for (std::size_t i = 0; i < row.size(); ++i)
          if (in[i]) out.positions.push_back(row[i]);
      }
    out.volumes.assign(out.positions.size(), std::pow(s, dim));
    out.spacing = s;
  }
  if (out.positions.empty())
    throw SceneError(scene.source + ": key '" + key +
                     "': no particle falls inside the shape (sampling too coarse?)");
  for (auto& x : out.positions)
    for (int a = 0; a < dim; ++a)
      if (x[a] < scene.domain.min[a] || x[a] > scene.domain.max[a])
        throw SceneError(scene.source + ": key '" + key + "': particles fall outside the domain");
  // Initial velocity: v + ω × (x − center).
  Eigen::Vector3d center = mesh ? 0.5 * (to_eigen(lo) + to_eigen(hi)) : to_eigen(shape.center);
  Eigen::Vector3d w = to_eigen(obj.angular_velocity);
  out.velocities.reserve(out.positions.size());
  for (auto& x : out.positions) {
    Eigen::Vector3d v = to_eigen(obj.velocity) + w.cross(to_eigen(x) - center);
    if (dim == 2) v[2] = 0;
    out.velocities.push_back(from_eigen(v));
  }
  return out;
}

}  // namespace apiclab
