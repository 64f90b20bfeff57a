// The surface of a rest shape in material space (Fan et al. 2013, Sec 3.8: "We store a surface
// mesh for our object in the material domain"): a polyline (2D) or triangle mesh (3D) on
// φ₀ = 0, built once from the signed distance. Marching simplices (each sampling cell split
// into D! Kuhn simplices, which tile conformingly and need no case tables) find the crossings;
// each vertex is then projected onto φ₀ = 0 along ∇φ₀ (Newton on the exact distance), so the
// vertices lie on the rest shape to round-off. Written by hand: Debian's candidates (VTK, CGAL)
// are whole toolkits for a 60-line loop.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include "sim/eol/shape/rest_shape.hpp"
#include "sim/math.hpp"

namespace apiclab::eol {

template <int D>
struct RestSurface {
  std::vector<Vec<double, D>> X;       // vertex material coordinates X_s
  std::vector<std::int32_t> owner;     // the scene object per vertex
  std::vector<std::uint32_t> simplex;  // D vertex indices per segment (2D) / triangle (3D)
  std::size_t size() const { return X.size(); }
  std::size_t simplices() const { return simplex.size() / std::size_t(D); }
};

// φ₀ of `shape` at material point X.
template <int D>
double rest_phi(const ShapeDesc& shape, const Vec<double, D>& X) {
  Vec3d p{0, 0, 0};
  for (int a = 0; a < D; ++a) p[std::size_t(a)] = X[a];
  return rest_distance(shape, p, D);
}

// Moves X onto φ₀ = 0: X ← X − φ ∇φ / |∇φ|² (central differences of step h·1e-4), at most
// 8 times, until |φ| ≤ 1e-14 of the shape's size.
template <int D>
Vec<double, D> project_to_rest_surface(const ShapeDesc& shape, Vec<double, D> X, double h,
                                       double size) {
  const double step = 1e-4 * h;
  for (int it = 0; it < 8; ++it) {
    const double phi = rest_phi<D>(shape, X);
    if (std::abs(phi) <= 1e-14 * size) break;
    Vec<double, D> grad;
    for (int a = 0; a < D; ++a) {
      Vec<double, D> e = Vec<double, D>::Zero();
      e[a] = step;
      grad[a] =
          (rest_phi<D>(shape, Vec<double, D>(X + e)) - rest_phi<D>(shape, Vec<double, D>(X - e))) /
          (2 * step);
    }
    const double g2 = grad.squaredNorm();
    if (!(g2 > 1e-12)) break;
    X -= (phi / g2) * grad;
  }
  return X;
}

// The boundary of `shape` sampled at spacing h (h ≲ the grid cell), appended to `out`.
template <int D>
void append_rest_surface(const ShapeDesc& shape, std::int32_t owner, double h,
                         RestSurface<D>& out) {
  Vec3d lo3, hi3;
  rest_bounds(shape, D, lo3, hi3);
  // An origin off the shape's round numbers, so no sample lands exactly on φ₀ = 0.
  std::array<int, D> n;
  Vec<double, D> origin;
  double size = 0;
  for (int a = 0; a < D; ++a) {
    origin[a] = lo3[std::size_t(a)] - h * 1.3819660112501051;
    n[std::size_t(a)] = int(std::ceil((hi3[std::size_t(a)] - origin[a]) / h)) + 2;
    size = std::max(size, hi3[std::size_t(a)] - lo3[std::size_t(a)]);
  }
  auto index = [&](const std::array<int, D>& c) {
    std::size_t i = 0;
    for (int a = D - 1; a >= 0; --a) i = i * std::size_t(n[std::size_t(a)]) + std::size_t(c[a]);
    return i;
  };
  auto position = [&](const std::array<int, D>& c) {
    Vec<double, D> x = origin;
    for (int a = 0; a < D; ++a) x[a] += h * c[std::size_t(a)];
    return x;
  };
  std::size_t count = 1;
  for (int a = 0; a < D; ++a) count *= std::size_t(n[std::size_t(a)]);
  std::vector<double> phi(count);
  for (std::size_t i = 0; i < count; ++i) {
    std::array<int, D> c;
    std::size_t r = i;
    for (int a = 0; a < D; ++a) {
      c[std::size_t(a)] = int(r % std::size_t(n[std::size_t(a)]));
      r /= std::size_t(n[std::size_t(a)]);
    }
    phi[i] = rest_phi<D>(shape, position(c));
  }
  std::map<std::pair<std::size_t, std::size_t>, std::uint32_t> edge_vertex;
  // The crossings before projection: φ is linear on each simplex, so there they lie on a
  // plane that separates its inside corners from its outside ones (orientation is read there).
  const std::size_t first = out.X.size();
  std::vector<Vec<double, D>> linear;
  struct Node {
    std::size_t index;
    Vec<double, D> x;
  };
  // The vertex on the edge a–b (one inside, one outside), shared by every simplex using it.
  auto crossing = [&](const Node& a, const Node& b) {
    const auto key = std::minmax(a.index, b.index);
    auto it = edge_vertex.find(key);
    if (it != edge_vertex.end()) return it->second;
    const double t = phi[a.index] / (phi[a.index] - phi[b.index]);
    const Vec<double, D> x = a.x + t * (b.x - a.x);
    const auto v = std::uint32_t(out.X.size());
    linear.push_back(x);
    out.X.push_back(project_to_rest_surface<D>(shape, x, h, size));
    out.owner.push_back(owner);
    edge_vertex.emplace(key, v);
    return v;
  };
  std::array<int, D> perm;
  std::array<int, D> cell{};
  for (;;) {
    std::iota(perm.begin(), perm.end(), 0);
    do {  // the Kuhn simplex 0 → e_π0 → e_π0 + e_π1 → … → (1, …, 1)
      std::array<Node, D + 1> s;
      std::array<int, D> c = cell;
      s[0] = {index(c), position(c)};
      for (int k = 0; k < D; ++k) {
        ++c[std::size_t(perm[std::size_t(k)])];
        s[std::size_t(k + 1)] = {index(c), position(c)};
      }
      std::vector<Node> in, outside;
      for (const Node& v : s) (phi[v.index] < 0 ? in : outside).push_back(v);
      if (in.empty() || outside.empty()) continue;
      std::vector<std::uint32_t> ring;  // crossings in cyclic order
      if (in.size() == 1 || outside.size() == 1) {
        const bool one_in = in.size() == 1;
        for (const Node& o : one_in ? outside : in)
          ring.push_back(one_in ? crossing(in[0], o) : crossing(o, outside[0]));
      } else {  // 3D, two in and two out: the quad a–c, a–d, b–d, b–c
        ring = {crossing(in[0], outside[0]), crossing(in[0], outside[1]),
                crossing(in[1], outside[1]), crossing(in[1], outside[0])};
      }
      const Vec<double, D> outward = outside[0].x - in[0].x;
      auto at = [&](std::uint32_t v) { return linear[v - first]; };
      if constexpr (D == 2) {
        // Oriented so that the tangent turned by −90° points out (the contact rows' normal).
        const Vec<double, 2> t = at(ring[1]) - at(ring[0]);
        if (Vec<double, 2>(t[1], -t[0]).dot(outward) < 0) std::swap(ring[0], ring[1]);
        out.simplex.insert(out.simplex.end(), {ring[0], ring[1]});
      } else {
        for (std::size_t k = 1; k + 1 < ring.size(); ++k) {
          std::array<std::uint32_t, 3> t{ring[0], ring[k], ring[k + 1]};
          const Vec<double, 3> normal =
              (at(t[1]) - at(t[0])).cross(Vec<double, 3>(at(t[2]) - at(t[0])));
          if (normal.dot(outward) < 0) std::swap(t[1], t[2]);  // counter-clockwise from outside
          out.simplex.insert(out.simplex.end(), t.begin(), t.end());
        }
      }
    } while (std::next_permutation(perm.begin(), perm.end()));
    int a = 0;
    while (a < D && ++cell[std::size_t(a)] == n[std::size_t(a)] - 1) cell[std::size_t(a++)] = 0;
    if (a == D) break;
  }
}

// Splits every triangle 1 → 4 at its edges' midpoints until no edge is longer than `longest`.
// Shared edges take the same midpoint, so the mesh stays closed, manifold and oriented, and the
// midpoints of flat triangles lie on them: it is still exactly the rest shape.
inline void subdivide_to(double longest, std::vector<Vec<double, 3>>& X,
                         std::vector<std::uint32_t>& tri, std::size_t first_tri) {
  for (;;) {
    double worst = 0;
    for (std::size_t t = first_tri; t < tri.size(); t += 3)
      for (int e = 0; e < 3; ++e)
        worst = std::max(
            worst, (X[tri[t + std::size_t(e)]] - X[tri[t + std::size_t((e + 1) % 3)]]).norm());
    if (!(worst > longest)) return;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    const auto at = [&](std::uint32_t a, std::uint32_t b) {
      const auto [it, added] = mid.try_emplace(std::minmax(a, b), std::uint32_t(X.size()));
      if (added) X.push_back(0.5 * (X[a] + X[b]));
      return it->second;
    };
    std::vector<std::uint32_t> out(tri.begin(), tri.begin() + std::ptrdiff_t(first_tri));
    for (std::size_t t = first_tri; t < tri.size(); t += 3) {
      const std::uint32_t a = tri[t], b = tri[t + 1], c = tri[t + 2];
      const std::uint32_t ab = at(a, b), bc = at(b, c), ca = at(c, a);
      out.insert(out.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
    }
    tri = std::move(out);
  }
}

// The surface of a rest shape: a mesh's own triangles (closed and manifold, checked when read,
// and exactly the rest shape: marching on its sampled distance would only approximate it at the
// cell), split until no edge is longer than the grid's cell 2h; any other shape's marching
// simplices above. Algorithm 2 places the vertices alone: a triangle over many cells stays flat
// while the material under it deforms, and a body pressing between its vertices meets no vertex
// (the shipped cylinder.obj had 0.4 m sides on a 0.025 m grid and the rod met no row).
template <int D>
void append_rest_surface(const RestShape& rest, std::int32_t owner, double h, RestSurface<D>& out) {
  if constexpr (D == 3) {
    if (rest.mesh) {
      const auto first = std::uint32_t(out.X.size());
      const std::size_t first_tri = out.simplex.size();
      for (const Vec3d& v : rest.mesh->vertices())
        out.X.push_back(Vec<double, 3>(v[0], v[1], v[2]));
      for (const auto& t : rest.mesh->triangles())
        for (std::uint32_t v : t) out.simplex.push_back(first + v);
      subdivide_to(2 * h, out.X, out.simplex, first_tri);
      out.owner.resize(out.X.size(), owner);
      return;
    }
  }
  append_rest_surface<D>(rest.shape, owner, h, out);
}

}  // namespace apiclab::eol
