// Contact rows between objects, Fan et al. 2013 Sec 3.5, eqs 27-28. Two objects A and B overlap
// in Ω = A ∩ B, bounded by Γ_A ∩ B and Γ_B ∩ A; with each surface moving with its own grid's
// velocity (v^A = Σ_s Φ^A_s u^A_s on Γ_A, likewise on Γ_B), the rate of |Ω| is eq 27,
//   d|Ω|/dt = ∫_{Γ_A ∩ B} v^A·n_A dΓ + ∫_{Γ_B ∩ A} v^B·n_B dΓ,
// n each surface's own outward normal (a moving surface: no plane's direction to keep, unlike
// surface_contact.hpp). So a row has entries on both objects' nodes, j_s = ∫ Φ_s n dΓ (eq 28),
// and jᵀu is the rate of the overlap it covers. The rows are split by a collision grid on the
// spatial domain (Sec 3.5): a quadrature point's row is the world cell it lies in, one row per
// (pair, cell), so a turning body cannot trade penetration on one side for separation on the
// other. An overlap deeper than about a collision cell puts the lens's two arcs in different
// cells, and those rows hold one object's nodes only (still feasible: u = 0 meets every row).
//
// Γ_A ∩ B: each segment of A is cut at its crossings with B's segments, and each part is kept
// when its midpoint is inside B (a crossing count). Degenerate pairs: parts of no length (a
// touching point) are dropped; where the two surfaces run along each other, facing (touching
// faces) both sides keep the stretch, so its row is the objects' approach rate, and running the
// same way (coincident surfaces) only the first object's side does, so |Ω| counts it once. The kept
// parts are cut at A's grid lines and integrated exactly as surface_contact.hpp does (Φ_s is
// quadratic along a segment in one cell: 2-point Gauss). Detection: B's segments in a uniform grid
// over B's box (simplex_buckets.hpp). Triangle meshes (3D): object_contact_3d.hpp.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "sim/eol/contact/simplex_buckets.hpp"
#include "sim/eol/contact/surface_contact.hpp"

namespace apiclab::eol {

// One object as the rows see it: its grid, its surface placed by Algorithm 2 (intermediate
// positions y and oriented simplices), its frame (x = R y + p) and where its nodes start in
// the global node numbering (J's columns: object k's node i is node_offset_k + i).
template <class T, int D>
struct ContactObject {
  const EulerianGrid<T, D>* grid = nullptr;
  const std::vector<Vec<T, D>>* y = nullptr;
  const std::vector<std::uint32_t>* simplex = nullptr;
  Mat<T, D> R = Mat<T, D>::Identity();
  Vec<T, D> p = Vec<T, D>::Zero();
  std::uint32_t node_offset = 0;
  Vec<T, D> world(std::size_t k) const { return R * (*y)[k] + p; }
};

// What the assembly found for one overlapping pair: the objects, |Ω| (the divergence theorem
// on Γ_A ∩ B and Γ_B ∩ A) and its rows [first_row, first_row + rows).
template <class T>
struct OverlapPair {
  int a = 0, b = 0;
  T volume = T(0);
  std::uint32_t first_row = 0, rows = 0;
};

// The segments of one object's world surface bucketed (simplex_buckets.hpp), and whether a point
// lies inside the closed polyline.
template <class T>
class SegmentGrid : public SimplexBuckets<T, 2> {
 public:
  using V = Vec<T, 2>;
  // Inside the closed polyline: crossings of the ray from q along +x (half-open in y, so a ray
  // through a vertex counts it once).
  bool inside(const V& q, std::vector<std::uint32_t>& scratch) const {
    if ((q.array() < this->lo().array()).any() || (q.array() > this->hi().array()).any())
      return false;
    this->candidates(q, V(this->hi()[0], q[1]), scratch);
    bool in = false;
    for (std::uint32_t s : scratch) {
      const V& a = this->vertex(s, 0);
      const V& b = this->vertex(s, 1);
      if ((a[1] > q[1]) == (b[1] > q[1])) continue;
      const T xc = a[0] + (q[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
      if (xc > q[0]) in = !in;
    }
    return in;
  }
  std::pair<V, V> segment(std::uint32_t s) const {
    return {this->vertex(s, 0), this->vertex(s, 1)};
  }
};

// The bucket grid over one object's world surface: SegmentGrid (2D), TriangleGrid (3D,
// object_contact_3d.hpp).
template <class T, int D>
struct SurfaceIndexOf;

template <class T>
struct SurfaceIndexOf<T, 2> {
  using type = SegmentGrid<T>;
};

namespace object_contact_detail {

// Where segment a0-a1 crosses segment b0-b1, as a fraction of a0-a1 (false when parallel or
// apart).
template <class T>
bool crossing(const Vec<T, 2>& a0, const Vec<T, 2>& a1, const Vec<T, 2>& b0, const Vec<T, 2>& b1,
              T& t) {
  const Vec<T, 2> da = a1 - a0, db = b1 - b0, r = b0 - a0;
  const T den = da[0] * db[1] - da[1] * db[0];
  if (!(std::abs(den) > T(1e-14) * da.norm() * db.norm())) return false;
  t = (r[0] * db[1] - r[1] * db[0]) / den;
  const T s = (r[0] * da[1] - r[1] * da[0]) / den;
  return t >= T(0) && t <= T(1) && s >= T(0) && s <= T(1);
}

// A part of segment s of A, from fraction t0 to t1.
template <class T>
struct Part {
  std::size_t s;
  T t0, t1;
};

// Where segment a0-a1 runs along segment b0-b1 (collinear to round-off): the shared stretch as
// fractions [t0, t1] of a0-a1, and whether the two run the same way (same outward normal).
template <class T>
bool shared_stretch(const Vec<T, 2>& a0, const Vec<T, 2>& a1, const Vec<T, 2>& b0,
                    const Vec<T, 2>& b1, T& t0, T& t1, bool& same) {
  const Vec<T, 2> da = a1 - a0;
  const T len2 = da.squaredNorm();
  auto off = [&](const Vec<T, 2>& q) {
    const Vec<T, 2> r = q - a0;
    return std::abs(da[0] * r[1] - da[1] * r[0]) <= T(1e-12) * (len2 + r.squaredNorm());
  };
  if (!(len2 > T(0)) || !off(b0) || !off(b1)) return false;
  const T s0 = (b0 - a0).dot(da) / len2, s1 = (b1 - a0).dot(da) / len2;
  t0 = std::max(T(0), std::min(s0, s1));
  t1 = std::min(T(1), std::max(s0, s1));
  same = s1 > s0;
  return t1 > t0;
}

// Γ_A ∩ B: every part of A's segments inside B. A part along a segment of B counts when the
// two surfaces face each other (objects touching there: both sides keep it, so the row is
// their approach rate) and, where they face the same way (coincident surfaces), only on the
// pair's first side (`first`), so Ω's boundary is counted once.
template <class T>
void parts_inside(const std::vector<Vec<T, 2>>& xa, const std::vector<std::uint32_t>& simplex,
                  const SegmentGrid<T>& b, bool first, std::vector<Part<T>>& parts) {
  std::vector<std::uint32_t> near, scratch;
  std::vector<T> cuts;
  std::vector<std::array<T, 3>> shared;  // t0, t1, 1 when the same way
  for (std::size_t s = 0; 2 * s < simplex.size(); ++s) {
    const Vec<T, 2>& a0 = xa[simplex[2 * s]];
    const Vec<T, 2>& a1 = xa[simplex[2 * s + 1]];
    const Vec<T, 2> lo = a0.cwiseMin(a1), hi = a0.cwiseMax(a1);
    if ((hi.array() < b.lo().array()).any() || (lo.array() > b.hi().array()).any()) continue;
    b.candidates(lo, hi, near);
    cuts.assign({T(0), T(1)});
    shared.clear();
    for (std::uint32_t k : near) {
      const auto [b0, b1] = b.segment(k);
      T t, t0, t1;
      bool same;
      if (shared_stretch(a0, a1, b0, b1, t0, t1, same)) {
        cuts.insert(cuts.end(), {t0, t1});
        shared.push_back({t0, t1, T(same)});
      } else if (crossing(a0, a1, b0, b1, t)) {
        cuts.push_back(t);
      }
    }
    std::sort(cuts.begin(), cuts.end());
    for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
      if (!(cuts[c + 1] - cuts[c] > T(1e-12))) continue;  // a touching point: no measure
      const T mid = T(0.5) * (cuts[c] + cuts[c + 1]);
      int along = -1;  // -1: not along B; 0: facing B; 1: the same way as B
      for (const auto& sh : shared)
        if (mid > sh[0] && mid < sh[1]) along = int(sh[2]);
      const bool keep = along == 0 || (along == 1 && first) ||
                        (along < 0 && b.inside(Vec<T, 2>(a0 + mid * (a1 - a0)), scratch));
      if (keep) parts.push_back({s, cuts[c], cuts[c + 1]});
    }
  }
}

}  // namespace object_contact_detail

// Appends the rows of one side of a pair, Γ_A ∩ B (A's nodes, n_A), to `rows` through `row_of`
// (collision cell key → row), and adds the side's share of |Ω| to `volume`. `first`: A is the
// pair's first object.
template <class T>
void append_side_rows(const ContactObject<T, 2>& A, const std::vector<Vec<T, 2>>& xa,
                      const SegmentGrid<T>& b, bool first, std::int64_t pair_key, T cell,
                      std::map<std::array<std::int64_t, 3>, std::uint32_t>& row_of,
                      ContactRows<T, 2>& rows, T& volume) {
  using contact_detail::Piece;
  std::vector<object_contact_detail::Part<T>> parts;
  object_contact_detail::parts_inside(xa, *A.simplex, b, first, parts);
  const auto& y = *A.y;
  const auto& simplex = *A.simplex;
  for (const auto& [s, t0, t1] : parts) {
    const Vec<T, 2> y0 = y[simplex[2 * s]], y1 = y[simplex[2 * s + 1]];
    const Vec<T, 2> tangent = y1 - y0;
    if (!(tangent.norm() > T(0))) continue;
    const Vec<T, 2> n = A.R * Vec<T, 2>(tangent[1], -tangent[0]).normalized();
    Piece<T, 2> piece;
    piece.n = 2;
    piece.p[0] = y0 + t0 * tangent;
    piece.p[1] = y0 + t1 * tangent;
    split_by_cells(*A.grid, piece, 0, [&](const Piece<T, 2>& in_cell) {
      integrate_piece(in_cell, [&](const Vec<T, 2>& at, T w) {
        const Vec<T, 2> x = A.R * at + A.p;
        volume += w * x.dot(n) / T(2);  // |Ω| = ∫_{∂Ω} x·n dΓ / D
        const std::array<std::int64_t, 3> key{pair_key, std::int64_t(std::floor(x[0] / cell)),
                                              std::int64_t(std::floor(x[1] / cell))};
        auto [it, fresh] = row_of.try_emplace(key, std::uint32_t(rows.rows()));
        if (fresh) {
          rows.key.push_back(key);
          rows.bilateral.push_back(0);
        }
        const auto cw = A.grid->cell_weights(at);
        for (int corner = 0; corner < 4; ++corner) {
          const T phi = cw.weight[std::size_t(corner)];
          if (phi == T(0)) continue;
          rows.row.push_back(it->second);
          rows.node.push_back(A.node_offset + std::uint32_t(cw.index[std::size_t(corner)]));
          rows.coeff.push_back((w * phi) * n);
        }
      });
    });
  }
}

// Appends the unilateral rows (jᵀu ≤ 0) of every overlapping pair of `objects` to `rows`, one
// per pair and collision cell of size `cell`; their keys are (−1 − pair index, cell), apart
// from the planes' (surface_contact.hpp's keys start at 0). Returns the overlapping pairs.
template <class T, int D>
std::vector<OverlapPair<T>> assemble_object_rows(const std::vector<ContactObject<T, D>>& objects,
                                                 T cell, ContactRows<T, D>& rows) {
  const std::size_t count = objects.size();
  std::vector<std::vector<Vec<T, D>>> x(count);
  std::vector<std::pair<Vec<T, D>, Vec<T, D>>> box(count);  // each surface's world box
  for (std::size_t k = 0; k < count; ++k) {
    x[k].resize(objects[k].y->size());
    box[k] = {Vec<T, D>::Constant(T(INFINITY)), Vec<T, D>::Constant(-T(INFINITY))};
    for (std::size_t v = 0; v < x[k].size(); ++v) {
      x[k][v] = objects[k].world(v);
      box[k].first = box[k].first.cwiseMin(x[k][v]);
      box[k].second = box[k].second.cwiseMax(x[k][v]);
    }
  }
  // The bucket grids only of surfaces whose boxes meet another's.
  std::vector<typename SurfaceIndexOf<T, D>::type> grids(count);
  std::vector<char> built(count, 0);
  auto grid = [&](std::size_t k) -> const typename SurfaceIndexOf<T, D>::type& {
    if (!built[k]) grids[k].build(x[k], *objects[k].simplex);
    built[k] = 1;
    return grids[k];
  };
  std::vector<OverlapPair<T>> pairs;
  std::map<std::array<std::int64_t, D + 1>, std::uint32_t> row_of;
  for (std::size_t a = 0; a < count; ++a)
    for (std::size_t b = a + 1; b < count; ++b) {
      if ((box[a].second.array() < box[b].first.array()).any() ||
          (box[b].second.array() < box[a].first.array()).any())
        continue;
      OverlapPair<T> pair;
      pair.a = int(a);
      pair.b = int(b);
      pair.first_row = std::uint32_t(rows.rows());
      const std::int64_t key = -1 - std::int64_t(a * count + b);
      row_of.clear();
      append_side_rows(objects[a], x[a], grid(b), true, key, cell, row_of, rows, pair.volume);
      append_side_rows(objects[b], x[b], grid(a), false, key, cell, row_of, rows, pair.volume);
      pair.rows = std::uint32_t(rows.rows()) - pair.first_row;
      if (pair.rows > 0) pairs.push_back(pair);
    }
  return pairs;
}

}  // namespace apiclab::eol
