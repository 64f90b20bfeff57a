#include "sim/eol/shape/mesh_distance.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/geometry/sampling.hpp"

namespace apiclab::eol {
namespace {

double point_segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

Eigen::Vector3d eigen(const Vec3d& v) { return {v[0], v[1], v[2]}; }

}  // namespace

double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();  // vertex region a
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();  // vertex region b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();  // edge ab
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();  // vertex region c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();  // edge ac
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)  // edge bc
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double area2 = va + vb + vc;  // inside the face; a degenerate face is its edges
  if (!(area2 > 0))
    return std::min({point_segment_distance(p, a, b), point_segment_distance(p, b, c),
                     point_segment_distance(p, c, a)});
  return (p - (a + ab * (vb / area2) + ac * (vc / area2))).norm();
}

MeshDistance::MeshDistance(const ObjMesh& obj, const ShapeDesc& shape, double cell)
    : s_(0.5 * cell), band_(1.5 * cell) {  // band ≥ cell/2 + √3 s = 1.37 cell (header)
  lo_ = {1e300, 1e300, 1e300};
  hi_ = {-1e300, -1e300, -1e300};
  vertices_ = place_mesh_vertices(shape, obj);
  triangles_ = obj.triangles;
  double volume6 = 0;  // orientation: the signed volume is positive when outward
  for (const auto& t : triangles_) {
    const Eigen::Vector3d a = eigen(vertices_[t[0]]), b = eigen(vertices_[t[1]]),
                          c = eigen(vertices_[t[2]]);
    volume6 += a.dot(b.cross(c));
    for (auto i : t)
      for (int k = 0; k < 3; ++k) {
        lo_[k] = std::min(lo_[k], vertices_[i][k]);
        hi_[k] = std::max(hi_[k], vertices_[i][k]);
      }
  }
  if (volume6 < 0)
    for (auto& t : triangles_) std::swap(t[1], t[2]);
  // The lattice: the mesh's box, the band and a spacing each side; an origin off the shape's
  // round numbers, so no lattice point's +z ray grazes an edge of an axis-aligned mesh.
  const double margin = band_ + s_ * 1.3819660112501051;
  for (int k = 0; k < 3; ++k) {
    origin_[k] = lo_[k] - margin;
    n_[std::size_t(k)] = int(std::ceil((hi_[k] + margin - origin_[k]) / s_)) + 1;
  }
  const int nx = n_[0], ny = n_[1], nz = n_[2];
  const double inf = std::numeric_limits<double>::infinity();
  phi_.assign(std::size_t(nx) * std::size_t(ny) * std::size_t(nz), inf);
  auto at = [&](int i, int j, int k) {
    return (std::size_t(k) * std::size_t(ny) + std::size_t(j)) * std::size_t(nx) + std::size_t(i);
  };
  // Each triangle's lattice box grown by the band (index ranges), bounding sphere (centre, radius).
  const std::size_t nt = triangles_.size();
  std::vector<std::array<int, 6>> box(nt);
  std::vector<Eigen::Vector3d> centre(nt);
  std::vector<double> radius(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = triangles_[t];
    centre[t] =
        (eigen(vertices_[tri[0]]) + eigen(vertices_[tri[1]]) + eigen(vertices_[tri[2]])) / 3;
    radius[t] = 0;
    for (auto v : tri) radius[t] = std::max(radius[t], (eigen(vertices_[v]) - centre[t]).norm());
  }
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      double a = 1e300, b = -1e300;
      for (auto v : triangles_[t]) {
        a = std::min(a, vertices_[v][k]);
        b = std::max(b, vertices_[v][k]);
      }
      box[t][std::size_t(2 * k)] = std::max(0, int(std::ceil((a - band_ - origin_[k]) / s_)));
      box[t][std::size_t(2 * k + 1)] =
          std::min(n_[std::size_t(k)] - 1, int(std::floor((b + band_ - origin_[k]) / s_)));
    }
  // The triangles whose grown box meets each z layer (compressed rows: first[k] … first[k + 1]).
  std::vector<std::size_t> first(std::size_t(nz) + 1, 0);
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = box[t][4]; k <= box[t][5]; ++k) ++first[std::size_t(k) + 1];
  for (int k = 0; k < nz; ++k) first[std::size_t(k) + 1] += first[std::size_t(k)];
  std::vector<std::uint32_t> layer(first[std::size_t(nz)]);
  {
    std::vector<std::size_t> fill(first.begin(), first.end() - 1);
    for (std::size_t t = 0; t < nt; ++t)
      for (int k = box[t][4]; k <= box[t][5]; ++k) layer[fill[std::size_t(k)]++] = std::uint32_t(t);
  }
  // Exact distances in the band, one z layer per task (no two tasks write the same point).
#pragma omp parallel for schedule(dynamic)
  for (int k = 0; k < nz; ++k)
    for (std::size_t e = first[std::size_t(k)]; e < first[std::size_t(k) + 1]; ++e) {
      const std::size_t t = layer[e];
      const auto& bx = box[t];
      const Eigen::Vector3d a = eigen(vertices_[triangles_[t][0]]),
                            b = eigen(vertices_[triangles_[t][1]]),
                            c = eigen(vertices_[triangles_[t][2]]);
      for (int j = bx[2]; j <= bx[3]; ++j)
        for (int i = bx[0]; i <= bx[1]; ++i) {
          const Eigen::Vector3d p = origin_ + s_ * Eigen::Vector3d(i, j, k);
          double& d = phi_[at(i, j, k)];
          // The triangle is at least |p − centre| − radius away: skip it when that cannot beat
          // the nearest so far or the band (the same minimum, several times fewer evaluations).
          const double reach = std::min(d, band_) + radius[t];
          if ((p - centre[t]).squaredNorm() >= reach * reach) continue;
          d = std::min(d, point_triangle_distance(p, a, b, c));
        }
    }
  for (double& d : phi_)
    if (d > band_) d = inf;
  // Beyond the band: the 26-neighbour chamfer distance, two raster passes (an upper bound of
  // the distance: a path through lattice points is never shorter than the straight line).
  auto sweep = [&](int sign) {
    for (int kk = 0; kk < nz; ++kk)
      for (int jj = 0; jj < ny; ++jj)
        for (int ii = 0; ii < nx; ++ii) {
          const int i = sign > 0 ? ii : nx - 1 - ii, j = sign > 0 ? jj : ny - 1 - jj,
                    k = sign > 0 ? kk : nz - 1 - kk;
          double& d = phi_[at(i, j, k)];
          for (int dk = -1; dk <= 0; ++dk)
            for (int dj = -1; dj <= 1; ++dj)
              for (int di = -1; di <= 1; ++di) {
                if (dk == 0 && (dj > 0 || (dj == 0 && di >= 0))) continue;  // the 13 before
                const int a = i + sign * di, b = j + sign * dj, c = k + sign * dk;
                if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
                d = std::min(
                    d, phi_[at(a, b, c)] + s_ * std::sqrt(double(di * di + dj * dj + dk * dk)));
              }
        }
  };
  sweep(+1);
  sweep(-1);
  const MeshSolid solid(obj, shape);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k) {
    std::vector<Vec3d> row(static_cast<std::size_t>(nx));
    std::vector<char> in;
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const Eigen::Vector3d p = origin_ + s_ * Eigen::Vector3d(i, j, k);
        row[std::size_t(i)] = {p[0], p[1], p[2]};
      }
      solid.inside_run(row, in);  // a row at a time: the same answers as inside(), faster
      for (int i = 0; i < nx; ++i)
        if (in[std::size_t(i)]) phi_[at(i, j, k)] *= -1;
    }
  }
}

double MeshDistance::operator()(const Vec3d& x) const {
  // Outside the lattice: the value at the nearest lattice point plus the way there (an upper
  // bound again; the lattice's edge lies beyond the band, all outside).
  Eigen::Vector3d u, clamped;
  for (int k = 0; k < 3; ++k) {
    const double top = double(n_[std::size_t(k)] - 1);
    const double uk = (x[std::size_t(k)] - origin_[k]) / s_;
    u[k] = std::isfinite(uk) ? std::clamp(uk, 0.0, top) : 0.0;
    clamped[k] = origin_[k] + s_ * u[k];
  }
  const double outside = (eigen(x) - clamped).norm();
  std::array<int, 3> c;
  Eigen::Vector3d f;
  for (int k = 0; k < 3; ++k) {
    c[std::size_t(k)] = std::min(int(u[k]), n_[std::size_t(k)] - 2);
    f[k] = u[k] - c[std::size_t(k)];
  }
  const std::size_t nx = std::size_t(n_[0]), nxy = nx * std::size_t(n_[1]);
  const std::size_t base = std::size_t(c[2]) * nxy + std::size_t(c[1]) * nx + std::size_t(c[0]);
  double value = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const int di = corner & 1, dj = (corner >> 1) & 1, dk = corner >> 2;
    const double w =
        (di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]);  // trilinear
    value += w * phi_[base + std::size_t(dk) * nxy + std::size_t(dj) * nx + std::size_t(di)];
  }
  return value + outside;
}

}  // namespace apiclab::eol
