// Contact rows between objects in 3D (Fan et al. 2013 Sec 3.5, eqs 27-28): object_contact.hpp's
// rows for closed, outward-oriented triangle meshes. Γ_A ∩ B is found triangle by triangle of A:
// each of B's triangles that crosses the triangle's plane gives a segment of B's section,
// oriented so that B's inside lies on its left (direction n_A × n_B). The triangle is cut into
// pieces P, one per cell of A's grid (split_by_cells), and each P ∩ B is bounded by the segments
// clipped to P and by the parts of P's edges inside B (a ray-crossing count). P ∩ B may be
// non-convex or hold holes; it is integrated through its boundary, as a fan of signed triangles
// from P's centroid: each lies in P, so in one cell, where the 6-point rule is exact for Φ_s. A
// triangle that no segment crosses is wholly inside B or outside (one crossing count). A piece's
// row is the collision cell of its part's centroid, one row per (pair, cell) as in 2D.
// Written by hand: CGAL's corefinement would add a heavy header to the step and needs meshes
// free of self-intersection at every placement; a section, a clip and a ray count are 200 lines.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "sim/eol/contact/object_contact.hpp"

namespace apiclab::eol {

// The triangles of one object's world surface bucketed (simplex_buckets.hpp), and whether a
// point lies inside the closed surface.
template <class T>
class TriangleGrid : public SimplexBuckets<T, 3> {
 public:
  using V = Vec<T, 3>;
  using SimplexBuckets<T, 3>::vertex;
  using SimplexBuckets<T, 3>::index;
  // Inside the closed surface: crossings of the ray from q along +x. The ray's (y, z) is taken
  // as (q_y + ε, q_z + ε²) (simulation of simplicity), each edge's sign computed from its
  // lower-numbered vertex, so a ray through an edge or vertex counts one of its triangles.
  bool inside(const V& q, std::vector<std::uint32_t>& scratch) const {
    if ((q.array() < this->lo().array()).any() || (q.array() > this->hi().array()).any())
      return false;
    this->candidates(q, V(this->hi()[0], q[1], q[2]), scratch);
    bool in = false;
    for (std::uint32_t s : scratch) {
      const V &a = vertex(s, 0), &b = vertex(s, 1), &c = vertex(s, 2);
      if ((b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]) == T(0)) continue;
      T e[3];
      int sign[3];
      for (int k = 0; k < 3; ++k) sign[k] = edge_sign(index(s, k), index(s, (k + 1) % 3), q, e[k]);
      if (sign[0] != sign[1] || sign[1] != sign[2]) continue;
      // e[k] is the edge opposite vertex k + 2: barycentric weights of c, a, b.
      const T sum = e[0] + e[1] + e[2];
      if (sum == T(0)) continue;
      const T xh = (e[0] * c[0] + e[1] * a[0] + e[2] * b[0]) / sum;
      if (xh > q[0]) in = !in;
    }
    return in;
  }

 private:
  // The side of q of edge i → j in the (y, z) plane, with the tie-break above; `raw` the
  // unperturbed value (twice the signed area of i, j, q there).
  int edge_sign(std::uint32_t i, std::uint32_t j, const V& q, T& raw) const {
    const bool swap = j < i;
    const V& p0 = this->x()[swap ? j : i];
    const V& p1 = this->x()[swap ? i : j];
    T e = (p1[1] - p0[1]) * (q[2] - p0[2]) - (p1[2] - p0[2]) * (q[1] - p0[1]);
    raw = swap ? -e : e;
    if (e == T(0)) e = -(p1[2] - p0[2]);
    if (e == T(0)) e = p1[1] - p0[1];
    const int sg = e > T(0) ? 1 : -1;
    return swap ? -sg : sg;
  }
};

template <class T>
struct SurfaceIndexOf<T, 3> {
  using type = TriangleGrid<T>;
};

namespace object_contact_3d_detail {

using P2 = Vec<double, 2>;

inline double cross2(const P2& a, const P2& b) { return a[0] * b[1] - a[1] * b[0]; }

// An oriented segment in a triangle's plane (2D coordinates of that plane).
struct Seg {
  P2 a, b;
};

// The segment where B's triangle s crosses the plane n·(x − w0) = 0 (world), oriented along
// n × n_B; false when s does not cross it. Each crossing point is computed from its edge's
// lower-numbered vertex, so neighbouring triangles share it bit for bit.
template <class T>
bool section(const TriangleGrid<T>& b, std::uint32_t s, const Vec<T, 3>& n, const Vec<T, 3>& w0,
             Vec<T, 3>& q0, Vec<T, 3>& q1) {
  T d[3];
  for (int k = 0; k < 3; ++k) d[k] = n.dot(b.vertex(s, k) - w0);
  Vec<T, 3> q[2];
  int found = 0;
  for (int k = 0; k < 3 && found < 2; ++k) {
    const int j = (k + 1) % 3;
    if ((d[k] > T(0)) == (d[j] > T(0))) continue;
    const bool swap = b.index(s, j) < b.index(s, k);
    const int i0 = swap ? j : k, i1 = swap ? k : j;
    const Vec<T, 3>& p0 = b.vertex(s, i0);
    q[found++] = p0 + (d[i0] / (d[i0] - d[i1])) * (b.vertex(s, i1) - p0);
  }
  if (found < 2) return false;
  const Vec<T, 3> nb =
      (b.vertex(s, 1) - b.vertex(s, 0)).cross(Vec<T, 3>(b.vertex(s, 2) - b.vertex(s, 0)));
  const bool flip = (q[1] - q[0]).dot(n.cross(nb)) < T(0);
  q0 = q[flip ? 1 : 0];
  q1 = q[flip ? 0 : 1];
  return true;
}

// Where segment a0-a1 crosses b0-b1, as a fraction of a0-a1 (false when parallel or apart).
inline bool crossing(const P2& a0, const P2& a1, const P2& b0, const P2& b1, double& t) {
  const P2 da = a1 - a0, db = b1 - b0, r = b0 - a0;
  const double den = cross2(da, db);
  if (!(std::abs(den) > 1e-14 * da.norm() * db.norm())) return false;
  t = cross2(r, db) / den;
  const double u = cross2(r, da) / den;
  return t >= 0 && t <= 1 && u >= 0 && u <= 1;
}

// The part of `seg` inside the convex counter-clockwise polygon p (n corners); false if none.
inline bool clip_to(const std::array<P2, 16>& p, int n, Seg& seg) {
  double lo = 0, hi = 1;
  for (int k = 0; k < n; ++k) {
    const P2 &e0 = p[std::size_t(k)], &e1 = p[std::size_t((k + 1) % n)];
    const double f0 = cross2(e1 - e0, seg.a - e0), f1 = cross2(e1 - e0, seg.b - e0);
    if (f0 < 0 && f1 < 0) return false;
    if (f0 < 0) lo = std::max(lo, f0 / (f0 - f1));
    if (f1 < 0) hi = std::min(hi, f0 / (f0 - f1));
  }
  if (!(hi > lo)) return false;
  const P2 d = seg.b - seg.a;
  seg = {seg.a + lo * d, seg.a + hi * d};
  return true;
}

}  // namespace object_contact_3d_detail

// Appends the rows of one side of a pair, Γ_A ∩ B (A's nodes, n_A), as append_side_rows does in
// 2D (object_contact.hpp), and adds the side's share of |Ω| = ∫_{∂Ω} x·n dΓ / 3 to `volume`.
template <class T>
void append_side_rows(const ContactObject<T, 3>& A, const std::vector<Vec<T, 3>>& xa,
                      const TriangleGrid<T>& b, bool /*first*/, std::int64_t pair_key, T cell,
                      std::map<std::array<std::int64_t, 4>, std::uint32_t>& row_of,
                      ContactRows<T, 3>& rows, T& volume) {
  using namespace object_contact_3d_detail;
  using V = Vec<T, 3>;
  using contact_detail::Piece;
  const auto& y = *A.y;
  const auto& simplex = *A.simplex;
  std::vector<std::uint32_t> near, scratch;
  std::vector<std::pair<V, V>> cut;  // B's section in the triangle's plane (world)
  std::vector<Seg> segs, chain;
  std::vector<std::pair<V, T>> points;  // one piece's quadrature: y, signed weight
  std::vector<double> cuts;
  for (std::size_t f = 0; f < simplex.size(); f += 3) {
    const V& w0 = xa[simplex[f]];
    const V& w1 = xa[simplex[f + 1]];
    const V& w2 = xa[simplex[f + 2]];
    const V lo = w0.cwiseMin(w1).cwiseMin(w2), hi = w0.cwiseMax(w1).cwiseMax(w2);
    if ((hi.array() < b.lo().array()).any() || (lo.array() > b.hi().array()).any()) continue;
    V n = (w1 - w0).cross(V(w2 - w0));
    if (!(n.norm() > T(0))) continue;
    n.normalize();
    b.candidates(lo, hi, near);
    cut.clear();
    for (std::uint32_t s : near) {
      V q0, q1;
      if (!section(b, s, n, w0, q0, q1)) continue;
      const V slo = q0.cwiseMin(q1), shi = q0.cwiseMax(q1);
      if ((shi.array() < lo.array()).any() || (slo.array() > hi.array()).any()) continue;
      cut.push_back({q0, q1});
    }
    if (cut.empty() && !b.inside(V((w0 + w1 + w2) / T(3)), scratch)) continue;
    // The triangle's plane in A's intermediate domain: origin t0, axes e1, e2 (e1 × e2 = n_y).
    const V t0 = y[simplex[f]], t1 = y[simplex[f + 1]], t2 = y[simplex[f + 2]];
    const V ny = (t1 - t0).cross(V(t2 - t0)).normalized();
    const V e1 = (t1 - t0).normalized(), e2 = ny.cross(e1);
    auto to2 = [&](const V& q) { return P2(double(e1.dot(q - t0)), double(e2.dot(q - t0))); };
    auto to3 = [&](const P2& q) { return V(t0 + T(q[0]) * e1 + T(q[1]) * e2); };
    segs.clear();
    for (const auto& [q0, q1] : cut)
      segs.push_back({to2(A.R.transpose() * (q0 - A.p)), to2(A.R.transpose() * (q1 - A.p))});
    const V nw = A.R * ny;
    Piece<T, 3> tri;
    tri.n = 3;
    tri.p[0] = t0;
    tri.p[1] = t1;
    tri.p[2] = t2;
    split_by_cells(*A.grid, tri, 0, [&](const Piece<T, 3>& piece) {
      std::array<P2, 16> p2;
      for (int k = 0; k < piece.n; ++k) p2[std::size_t(k)] = to2(piece.p[std::size_t(k)]);
      P2 c = P2::Zero();
      for (int k = 0; k < piece.n; ++k) c += p2[std::size_t(k)];
      c /= double(piece.n);
      // ∂(P ∩ B): B's section clipped to P, and the parts of P's edges inside B.
      chain.clear();
      for (Seg s : segs)
        if (clip_to(p2, piece.n, s)) chain.push_back(s);
      if (chain.empty()) {  // no section in P: P is wholly in B or out
        if (!segs.empty() && !b.inside(V(A.R * to3(c) + A.p), scratch)) return;
        for (int k = 0; k < piece.n; ++k)
          chain.push_back({p2[std::size_t(k)], p2[std::size_t((k + 1) % piece.n)]});
      } else {
        for (int k = 0; k < piece.n; ++k) {
          const P2 &a = p2[std::size_t(k)], &e = p2[std::size_t((k + 1) % piece.n)];
          cuts.assign({0.0, 1.0});
          for (const Seg& s : segs) {
            double t;
            if (crossing(a, e, s.a, s.b, t)) cuts.push_back(t);
          }
          std::sort(cuts.begin(), cuts.end());
          for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
            if (!(cuts[i + 1] - cuts[i] > 1e-12)) continue;
            const P2 mid = a + (0.5 * (cuts[i] + cuts[i + 1])) * (e - a);
            if (b.inside(V(A.R * to3(mid) + A.p), scratch))
              chain.push_back({a + cuts[i] * (e - a), a + cuts[i + 1] * (e - a)});
          }
        }
      }
      // The fan of signed triangles (c, a, b): Dunavant's 6-point rule on each.
      constexpr double a1 = 0.445948490915965, wt1 = 0.223381589678011;
      constexpr double a2 = 0.091576213509771, wt2 = 0.109951743655322;
      points.clear();
      double area = 0, piece_area = 0;
      for (int k = 1; k + 1 < piece.n; ++k)
        piece_area += 0.5 * cross2(p2[std::size_t(k)] - p2[0], p2[std::size_t(k + 1)] - p2[0]);
      for (const Seg& s : chain) {
        const double signed_area = 0.5 * cross2(s.a - c, s.b - c);
        if (signed_area == 0) continue;
        area += signed_area;
        for (const auto& [al, w] : {std::pair{a1, wt1}, std::pair{a2, wt2}}) {
          const double be = 1 - 2 * al;
          const T ww = T(w * signed_area);
          points.push_back({to3(al * c + al * s.a + be * s.b), ww});
          points.push_back({to3(al * c + be * s.a + al * s.b), ww});
          points.push_back({to3(be * c + al * s.a + al * s.b), ww});
        }
      }
      if (!(area > 1e-12 * piece_area)) return;  // a touching edge or point: no measure
      V centre = V::Zero();
      for (const auto& [at, w] : points) centre += w * at;
      const V xc = A.R * (centre / T(area)) + A.p;
      const std::array<std::int64_t, 4> key{pair_key, std::int64_t(std::floor(xc[0] / cell)),
                                            std::int64_t(std::floor(xc[1] / cell)),
                                            std::int64_t(std::floor(xc[2] / cell))};
      auto [it, fresh] = row_of.try_emplace(key, std::uint32_t(rows.rows()));
      if (fresh) {
        rows.key.push_back(key);
        rows.bilateral.push_back(0);
      }
      // Every point lies in P, so in one cell: the corners' terms summed over the piece.
      const auto cw0 = A.grid->cell_weights(to3(c));
      std::array<T, 8> phi_sum{};
      for (const auto& [at, w] : points) {
        volume += w * (A.R * at + A.p).dot(nw) / T(3);
        const auto cw = A.grid->cell_weights(at);
        for (int corner = 0; corner < 8; ++corner) {
          const T phi = cw.weight[std::size_t(corner)];
          if (cw.index[std::size_t(corner)] == cw0.index[std::size_t(corner)]) {
            phi_sum[std::size_t(corner)] += w * phi;
          } else if (phi != T(0)) {  // a point on a cell face taken by the next cell
            rows.row.push_back(it->second);
            rows.node.push_back(A.node_offset + std::uint32_t(cw.index[std::size_t(corner)]));
            rows.coeff.push_back((w * phi) * nw);
          }
        }
      }
      for (int corner = 0; corner < 8; ++corner) {
        if (phi_sum[std::size_t(corner)] == T(0)) continue;
        rows.row.push_back(it->second);
        rows.node.push_back(A.node_offset + std::uint32_t(cw0.index[std::size_t(corner)]));
        rows.coeff.push_back(phi_sum[std::size_t(corner)] * nw);
      }
    });
  }
}

}  // namespace apiclab::eol
