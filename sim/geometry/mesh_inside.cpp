#include "sim/geometry/mesh_inside.hpp"

// The only translation unit that includes CGAL (its headers are heavy; sim/CMakeLists.txt
// compiles this file apart, with CGAL's flags).
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cmath>
#include <numeric>

namespace apiclab {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Segment = K::Segment_3;

namespace {

// One triangle of the tree by its index; the vertices live in the shared Impl.
struct Primitive {
  using Id = std::uint32_t;
  using Point = K::Point_3;
  using Datum = K::Triangle_3;
  using Shared_data = const MeshWinding::Impl*;
  Id index = 0;
  Primitive() = default;
  template <class Iterator>
  Primitive(Iterator it, Shared_data) : index(*it) {}
  Id id() const { return index; }
  Datum datum(Shared_data m) const;
  Point reference_point(Shared_data m) const;
  static Shared_data construct_shared_data(Shared_data m) { return m; }
};

using Traits = CGAL::AABB_traits<K, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;

}  // namespace

struct MeshWinding::Impl {
  std::vector<Point> points;
  const std::vector<std::array<std::uint32_t, 3>>* triangles = nullptr;
  Vec3d lo{}, hi{};
  Tree tree;
};

namespace {

Primitive::Datum Primitive::datum(Shared_data m) const {
  const auto& t = (*m->triangles)[index];
  return {m->points[t[0]], m->points[t[1]], m->points[t[2]]};
}
Primitive::Point Primitive::reference_point(Shared_data m) const {
  return m->points[(*m->triangles)[index][0]];
}

// Signed crossings of the segment p→q with the triangles. Exact orientation predicates decide
// every case, so a segment through an edge or a vertex is seen as such (never counted twice or
// missed) and the caller turns the segment instead.
struct Crossings {
  const MeshWinding::Impl* m;
  Point p, q;
  int winding = 0;
  bool degenerate = false;  // through an edge or a vertex
  bool on_surface = false;  // p lies on a triangle
  bool q_on_surface = false;

  bool go_further() const { return !degenerate && !on_surface && !q_on_surface; }
  bool do_intersect(const Segment& s, const CGAL::AABB_node<Traits>& node) const {
    return CGAL::do_intersect(s, node.bbox());
  }
  void intersection(const Segment&, const Primitive& prim) {
    const auto& t = (*m->triangles)[prim.index];
    const Point &a = m->points[t[0]], &b = m->points[t[1]], &c = m->points[t[2]];
    const CGAL::Orientation op = CGAL::orientation(a, b, c, p);
    if (op == CGAL::COPLANAR) {
      // p in the triangle's plane: on the triangle, or the segment leaves the plane at p.
      if (K::Triangle_3(a, b, c).has_on(p)) on_surface = true;
      return;
    }
    const CGAL::Orientation oq = CGAL::orientation(a, b, c, q);
    if (oq == CGAL::COPLANAR) {  // q in the plane: on the triangle, or no crossing
      if (K::Triangle_3(a, b, c).has_on(q)) q_on_surface = true;
      return;
    }
    if (oq == op) return;
    // The line pq meets the triangle where the three edge sides agree (Plücker signs).
    const CGAL::Orientation s0 = CGAL::orientation(p, q, a, b), s1 = CGAL::orientation(p, q, b, c),
                            s2 = CGAL::orientation(p, q, c, a);
    const bool pos = s0 == CGAL::POSITIVE || s1 == CGAL::POSITIVE || s2 == CGAL::POSITIVE;
    const bool neg = s0 == CGAL::NEGATIVE || s1 == CGAL::NEGATIVE || s2 == CGAL::NEGATIVE;
    if (pos && neg) return;  // misses
    if (s0 == CGAL::COPLANAR || s1 == CGAL::COPLANAR || s2 == CGAL::COPLANAR) {
      degenerate = true;  // through an edge or a vertex
      return;
    }
    winding += oq == CGAL::POSITIVE ? 1 : -1;  // leaves towards the side the normal points to
  }
};

}  // namespace

MeshWinding::MeshWinding(const std::vector<Vec3d>& vertices,
                         const std::vector<std::array<std::uint32_t, 3>>& triangles,
                         const Vec3d& lo, const Vec3d& hi)
    : impl_(std::make_unique<Impl>()) {
  impl_->points.reserve(vertices.size());
  for (const Vec3d& v : vertices) impl_->points.emplace_back(v[0], v[1], v[2]);
  impl_->triangles = &triangles;
  impl_->lo = lo;
  impl_->hi = hi;
  std::vector<std::uint32_t> kept;
  kept.reserve(triangles.size());
  for (std::uint32_t k = 0; k < triangles.size(); ++k) {
    const auto& t = triangles[k];
    if (!CGAL::collinear(impl_->points[t[0]], impl_->points[t[1]], impl_->points[t[2]]))
      kept.push_back(k);
  }
  impl_->tree.insert(kept.begin(), kept.end(), static_cast<const Impl*>(impl_.get()));
  impl_->tree.build();
}

MeshWinding::~MeshWinding() = default;

namespace {
// Directions no mesh on round coordinates lines up with (x, y irrational-looking, z = ±1).
constexpr double kDirections[][2] = {
    {0.2718281828459045, 0.1414213562373095},  {-0.3141592653589793, 0.1732050807568877},
    {0.1618033988749895, -0.2236067977499790}, {-0.1259921049894873, -0.2645751311064591},
    {0.0577215664901533, 0.3302775637731995},  {0.3605551275463989, -0.0693147180559945},
};
constexpr int kAttempts = 2 * 6;
}  // namespace

MeshWinding::Vec3d MeshWinding::direction(int attempt) {
  const double* d = kDirections[attempt % 6];
  return {d[0], d[1], attempt % kAttempts < 6 ? 1.0 : -1.0};
}

MeshWinding::Result MeshWinding::winding(const Vec3d& x) const {
  const Impl& m = *impl_;
  Result r;
  for (int a = 0; a < 3; ++a)
    if (!(x[a] >= m.lo[a] && x[a] <= m.hi[a])) return r;  // outside the box (or NaN)
  if (m.tree.empty()) return r;
  // A segment from x out past the box; the next direction when it grazes an edge or a vertex.
  const Point p(x[0], x[1], x[2]);
  const double reach = 2 * (m.hi[2] - m.lo[2]);  // from inside the box to beyond it along z
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    const Vec3d d = direction(attempt);
    const Point q(x[0] + reach * d[0], x[1] + reach * d[1], x[2] + reach * d[2]);
    Crossings c{&m, p, q};
    m.tree.traversal(Segment(p, q), c);
    r.segments = attempt + 1;
    if (c.on_surface) {
      r.on_surface = true;
      return r;
    }
    if (!c.degenerate) {
      r.winding = c.winding;
      return r;
    }
  }
  r.on_surface = true;  // every segment grazed an edge or a vertex: taken as on the surface
  return r;
}

MeshWinding::Result MeshWinding::walk(const Vec3d& from, const Result& at_from,
                                      const Vec3d& to) const {
  const Impl& m = *impl_;
  for (int a = 0; a < 3; ++a)
    if (!(to[a] >= m.lo[a] && to[a] <= m.hi[a])) return {};  // outside the box (or NaN)
  if (at_from.on_surface || m.tree.empty()) return winding(to);
  const Point p(from[0], from[1], from[2]), q(to[0], to[1], to[2]);
  Crossings c{&m, p, q};
  m.tree.traversal(Segment(p, q), c);
  Result r;
  r.segments = 1;
  if (c.degenerate || c.on_surface) return winding(to);
  if (c.q_on_surface) {
    r.on_surface = true;
    return r;
  }
  r.winding = at_from.winding - c.winding;  // each exit through a front face leaves a layer
  return r;
}

}  // namespace apiclab
