// The surface contact rows of Fan et al. 2013, Sec 3.5, against the scene's planes (walls and
// colliders). Ω is the part of the object behind a plane; the velocity-level constraint is that
// Ω does not grow (eq 27), d|Ω|/dt = ∫_{Γ∩Ω} v·n dΓ ≤ 0 (for a fixed plane only the object's
// surface Γ moves Ω's boundary; n is Γ's outward normal). With the grid's multilinear shape
// functions Φ_s, v = Σ_s Φ_s u_s and each row is j_s = ∫_{Γ∩Ω} Φ_s n dΓ (eq 28). A plane moving
// with velocity v_b holds the velocity relative to it: jᵀ(u − v_b) ≤ 0, eq 29's right-hand side
// −jᵀv_b (ContactRows::rate).
//
// Against a fixed plane with normal N the row keeps only the plane's direction of Γ's normal:
// j_s = ∫_{Γ∩Ω} Φ_s (n·N) N dΓ, so jᵀu is the rate of |Ω| under the normal part (u·N) N of the
// motion. For every translation this is eq 27's rate exactly (sliding along the plane does not
// change |Ω|, and ∫_{Γ∩Ω} n dΓ = −|cap| N by the divergence theorem). What it drops, eq 28's
// tangential parts ∫ Φ_s (n − (n·N) N), sums to zero over Γ∩Ω but not over one collision cell:
// on a faceted surface (marching simplices) the cells' tangential pushes leave a net sideways
// force, and a ball resting on the floor slid 13 mm in 0.5 s (3D, dx 1/16) where with N it
// does not move (test_eol_surface_contact.cpp). A frictionless plane pushes along N only.
//
// Γ is the surface placed by Algorithm 2 (surface_placement.hpp). Each simplex is clipped to the
// plane's back side, then cut at the grid lines of the intermediate domain so that every piece
// lies in one cell, where Φ_s is one multilinear polynomial: along a segment piece (2D) it is
// quadratic, so 2-point Gauss is exact; on a triangle piece (3D) cubic, so the 6-point degree-4
// rule (Dunavant 1985) is exact. The rows are grouped by a collision grid along the plane (Sec
// 3.5: "decomposed via a collision grid ... to enhance the resolution of constraints"): a
// quadrature point's row is the collision cell its world position falls in.
//
// Boundary conditions: separate, the unilateral row jᵀu ≤ 0; slip, the bilateral row jᵀu = 0;
// sticky, the bilateral normal row and D − 1 tangential rows ∫ Φ_s t dΓ (the mean tangential
// velocity of the contact patch is zero). Geometry written by hand: a segment and a convex
// polygon clipped by axis planes (Sutherland–Hodgman) are 40 lines; no Debian package is smaller.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/eol/contact/impulse_solve.hpp"
#include "sim/eol/grid/eulerian_grid.hpp"
#include "sim/eol/surface/rest_surface.hpp"

namespace apiclab::eol {

// J in triplet form: entry e of row `row[e]` at node `node[e]` with vector coefficient
// `coeff[e]` (world axes; its dot with the node's world velocity u is the entry's term of jᵀu).
// Rows in order of first appearance; `bilateral[k]` per row. Buffers are reused step to step.
template <class T, int D>
struct ContactRows {
  std::vector<std::uint32_t> row;
  std::vector<std::uint32_t> node;
  std::vector<Vec<T, D>> coeff;
  std::vector<std::uint8_t> bilateral;
  // Per row, its collision cell's key: plane, kind (0 normal, 1.. tangent) and cell coordinates.
  std::vector<std::array<std::int64_t, D + 1>> key;
  // Per row, the rate jᵀv_b its jᵀu is held to (a moving plane's rows: the constraint is on the
  // velocity relative to the plane); rows past its end hold 0, so it is empty while no body moves.
  std::vector<T> rate;
  // add_point_rows' memory: the normal rows the last quadrature points went to, and the row and
  // first entry of the run of points that went to one row.
  std::array<std::size_t, 4> recent{};
  std::size_t run_row = SIZE_MAX, run_from = 0;
  std::size_t rows() const { return bilateral.size(); }
  void clear() {
    recent = {};
    run_row = SIZE_MAX;
    run_from = 0;
    rate.clear();
    row.clear();
    node.clear();
    coeff.clear();
    bilateral.clear();
    key.clear();
  }
};

namespace contact_detail {

// A convex polygon (3D) or segment (2D) in the intermediate domain, fixed capacity (a triangle
// clipped by a plane and a cell's 6 faces has at most 9 corners).
template <class T, int D>
struct Piece {
  std::array<Vec<T, D>, 16> p;
  int n = 0;
};

// Sutherland–Hodgman: the part of `in` where s·y + c ≤ 0 (a closed polygon; for a segment,
// n = 2, the same rule keeps the inside part of the segment).
template <class T, int D>
void clip(const Piece<T, D>& in, const Vec<T, D>& s, T c, Piece<T, D>& out) {
  out.n = 0;
  if (in.n == 2) {  // a segment: not closed
    const T da = s.dot(in.p[0]) + c, db = s.dot(in.p[1]) + c;
    if (da > T(0) && db > T(0)) return;
    Vec<T, D> a = in.p[0], b = in.p[1];
    if (da > T(0)) a = in.p[0] + (da / (da - db)) * (in.p[1] - in.p[0]);
    if (db > T(0)) b = in.p[0] + (da / (da - db)) * (in.p[1] - in.p[0]);
    out.p[0] = a;
    out.p[1] = b;
    out.n = 2;
    return;
  }
  for (int k = 0; k < in.n; ++k) {
    const Vec<T, D>& a = in.p[std::size_t(k)];
    const Vec<T, D>& b = in.p[std::size_t((k + 1) % in.n)];
    const T da = s.dot(a) + c, db = s.dot(b) + c;
    if (da <= T(0)) out.p[std::size_t(out.n++)] = a;
    if ((da <= T(0)) != (db <= T(0))) out.p[std::size_t(out.n++)] = a + (da / (da - db)) * (b - a);
  }
  if (out.n < 3) out.n = 0;
}

}  // namespace contact_detail

// An orthonormal tangent basis of a plane with unit normal n (2D: n turned by +90°).
template <class T, int D>
std::array<Vec<T, D>, D - 1> plane_tangents(const Vec<T, D>& n) {
  std::array<Vec<T, D>, D - 1> t;
  if constexpr (D == 2) {
    t[0] = Vec<T, 2>(-n[1], n[0]);
  } else {
    const int a = std::abs(n[0]) < std::abs(n[1]) ? (std::abs(n[0]) < std::abs(n[2]) ? 0 : 2)
                                                  : (std::abs(n[1]) < std::abs(n[2]) ? 1 : 2);
    Vec<T, 3> e = Vec<T, 3>::Zero();
    e[a] = T(1);
    t[0] = n.cross(e).normalized();
    t[1] = n.cross(t[0]);
  }
  return t;
}

// Quadrature on a piece in one cell: points (intermediate domain) and weights (measure).
template <class T, int D, class Emit>
void integrate_piece(const contact_detail::Piece<T, D>& piece, Emit&& emit) {
  if constexpr (D == 2) {
    const T g = T(0.5) / std::sqrt(T(3));  // 2-point Gauss on [0, 1]: ½ ± 1/(2√3)
    const Vec<T, 2> a = piece.p[0], b = piece.p[1];
    const T len = (b - a).norm();
    if (!(len > T(0))) return;
    emit(Vec<T, 2>(a + (T(0.5) - g) * (b - a)), T(0.5) * len);
    emit(Vec<T, 2>(a + (T(0.5) + g) * (b - a)), T(0.5) * len);
  } else {
    // Dunavant's 6-point rule, exact to degree 4 (Φ_s on a plane is at most cubic).
    constexpr double a1 = 0.445948490915965, w1 = 0.223381589678011;
    constexpr double a2 = 0.091576213509771, w2 = 0.109951743655322;
    for (int k = 1; k + 1 < piece.n; ++k) {
      const Vec<T, 3>& p0 = piece.p[0];
      const Vec<T, 3>& p1 = piece.p[std::size_t(k)];
      const Vec<T, 3>& p2 = piece.p[std::size_t(k + 1)];
      const T area = T(0.5) * (p1 - p0).cross(Vec<T, 3>(p2 - p0)).norm();
      if (!(area > T(0))) continue;
      for (const auto& [a, w] : {std::pair{a1, w1}, std::pair{a2, w2}}) {
        const T b = T(1 - 2 * a);
        emit(Vec<T, 3>(T(a) * p0 + T(a) * p1 + b * p2), T(w) * area);
        emit(Vec<T, 3>(T(a) * p0 + b * p1 + T(a) * p2), T(w) * area);
        emit(Vec<T, 3>(b * p0 + T(a) * p1 + T(a) * p2), T(w) * area);
      }
    }
  }
}

// Cuts `piece` at the grid lines of axis `axis` and on, calling `done` with each part that lies
// in one cell.
template <class T, int D, class Done>
void split_by_cells(const EulerianGrid<T, D>& g, const contact_detail::Piece<T, D>& piece, int axis,
                    Done&& done) {
  if (axis == D) {
    done(piece);
    return;
  }
  T lo = piece.p[0][axis], hi = lo;
  for (int k = 1; k < piece.n; ++k) {
    lo = std::min(lo, piece.p[std::size_t(k)][axis]);
    hi = std::max(hi, piece.p[std::size_t(k)][axis]);
  }
  const long first = long(std::floor((lo - g.origin[axis]) / g.dx));
  const long last = long(std::floor((hi - g.origin[axis]) / g.dx));
  if (first == last) {
    split_by_cells(g, piece, axis + 1, done);
    return;
  }
  Vec<T, D> e = Vec<T, D>::Zero();
  e[axis] = T(1);
  contact_detail::Piece<T, D> below, slab;
  for (long c = first; c <= last; ++c) {
    const T y0 = g.origin[axis] + g.dx * T(c), y1 = y0 + g.dx;
    clip(piece, Vec<T, D>(-e), y0, below);  // y_a ≥ y0
    if (below.n == 0) continue;
    clip(below, e, -y1, slab);  // y_a ≤ y1
    if (slab.n == 0) continue;
    split_by_cells(g, slab, axis + 1, done);
  }
}

// Where one quadrature point's share of eq 28 goes: its normal row along n (the key's first
// entry as given) and, for a sticky condition (kinds = D), its D − 1 tangent rows, whose key[0]
// steps by `step` from the normal row's; rows are looked up from first_row on and appended when
// new; node numbers shifted by node_offset.
template <class T, int D>
struct PointRows {
  std::size_t first_row = 0;
  std::int64_t step = 1;
  int kinds = 1;
  bool bilateral = false;
  std::uint32_t node_offset = 0;
  Vec<T, D> n;
  std::array<Vec<T, D>, D - 1> tangents;
};

// Adds w Φ_s dir to each of the point's rows for the 2^D corners of its cell (cell weights cw),
// and, on a moving boundary (velocity vb), the rows' rates jᵀv_b.
template <class T, int D, class CellWeights>
void add_point_rows(const PointRows<T, D>& group, std::array<std::int64_t, D + 1> key,
                    const CellWeights& cw, T w, const Vec<T, D>* vb, ContactRows<T, D>& rows) {
  const std::int64_t key0 = key[0];
  for (int kind = 0; kind < group.kinds; ++kind) {
    key[0] = key0 + group.step * kind;
    // The points of one piece share a cell and a few collision cells: the recent rows first, then
    // the scan (a face lying on a plane has hundreds of rows and tens of thousands of points).
    std::uint32_t r = std::uint32_t(group.first_row);
    bool found = false;
    for (std::size_t k = 0; k < rows.recent.size() && !found; ++k) {
      const std::size_t guess = rows.recent[k] + std::size_t(kind);
      found = guess >= group.first_row && guess < rows.key.size() && rows.key[guess] == key;
      if (found) r = std::uint32_t(guess);
    }
    while (!found && r < rows.key.size() && rows.key[r] != key) ++r;
    if (kind == 0 && !found) {
      std::rotate(rows.recent.rbegin(), rows.recent.rbegin() + 1, rows.recent.rend());
      rows.recent[0] = r;
    }
    if (r == rows.key.size()) {
      rows.key.push_back(key);
      rows.bilateral.push_back(kind > 0 || group.bilateral);
    }
    // A run of points with the same row adds into the run's entries at the same node (one cell's
    // 2^D nodes, mostly), so J holds about an entry per row and node, not per point and corner.
    if (r != rows.run_row) {
      rows.run_row = r;
      rows.run_from = rows.row.size();
    }
    const Vec<T, D> dir = kind == 0 ? group.n : group.tangents[std::size_t(kind - 1)];
    for (int corner = 0; corner < (1 << D); ++corner) {
      const T phi = cw.weight[std::size_t(corner)];
      if (phi == T(0)) continue;
      const Vec<T, D> term = (w * phi) * dir;
      const std::uint32_t node = group.node_offset + std::uint32_t(cw.index[std::size_t(corner)]);
      std::size_t e = rows.run_from;
      while (e < rows.node.size() && (rows.node[e] != node || rows.row[e] != r)) ++e;
      if (e < rows.node.size()) {
        rows.coeff[e] += term;
      } else {
        rows.row.push_back(r);
        rows.node.push_back(node);
        rows.coeff.push_back(term);
      }
      if (vb) {
        if (rows.rate.size() < rows.rows()) rows.rate.resize(rows.rows(), T(0));
        rows.rate[r] += term.dot(*vb);
      }
    }
  }
}

// Appends to `rows` the rows of eq 28 for one object against every plane. y: the surface's
// intermediate positions (Algorithm 2), `simplex` its oriented segments or triangles, R and p the
// frame (world x = R y + p), `cell` the collision grid's cell size. Plane k's rows carry k in
// their key, so several planes (a domain corner) give separate rows.
template <class T, int D>
void assemble_surface_rows(const EulerianGrid<T, D>& g, const std::vector<Vec<T, D>>& y,
                           const std::vector<std::uint32_t>& simplex, const Mat<T, D>& R,
                           const Vec<T, D>& p, const std::vector<PlaneConstraint<T, D>>& planes,
                           T cell, ContactRows<T, D>& rows) {
  using contact_detail::Piece;
  for (std::size_t k = 0; k < planes.size(); ++k) {
    const PlaneConstraint<T, D>& plane = planes[k];
    // In the intermediate domain the plane is ny·y + c ≤ 0 behind it.
    const Vec<T, D> ny = R.transpose() * plane.normal;
    const T c = (p - plane.point).dot(plane.normal);
    const auto tangents = plane_tangents<T, D>(plane.normal);
    const bool sticky = plane.condition == BoundaryCondition::sticky;
    const bool bilateral = plane.condition != BoundaryCondition::separate;
    const bool moving = !plane.velocity.isZero(T(0));
    for (std::size_t f = 0; f < simplex.size(); f += std::size_t(D)) {
      Piece<T, D> s;
      s.n = D;
      bool behind = false;
      for (int v = 0; v < D; ++v) {
        s.p[std::size_t(v)] = y[simplex[f + std::size_t(v)]];
        behind |= ny.dot(s.p[std::size_t(v)]) + c <= T(0);
      }
      if (!behind) continue;
      // Γ's outward normal (world): a segment's tangent turned by −90°, a triangle's
      // counter-clockwise normal (rest_surface.hpp orients both).
      Vec<T, D> n;
      if constexpr (D == 2) {
        const Vec<T, 2> t = s.p[1] - s.p[0];
        n = Vec<T, 2>(t[1], -t[0]);
      } else {
        n = (s.p[1] - s.p[0]).cross(Vec<T, 3>(s.p[2] - s.p[0]));
      }
      if (!(n.norm() > T(0))) continue;
      n = R * n.normalized();
      n = n.dot(plane.normal) * plane.normal;  // the plane's direction only (see above)
      Piece<T, D> back;
      contact_detail::clip(s, ny, c, back);
      if (back.n == 0) continue;
      const PointRows<T, D> rows_at{0, 1, sticky ? D : 1, bilateral, 0, n, tangents};
      split_by_cells(g, back, 0, [&](const Piece<T, D>& piece) {
        integrate_piece(piece, [&](const Vec<T, D>& at, T w) {
          const Vec<T, D> x = R * at + p - plane.point;
          std::array<std::int64_t, D + 1> key;
          key[0] = std::int64_t(k) * 8;
          for (int a = 0; a + 1 < D; ++a)
            key[std::size_t(a + 1)] =
                std::int64_t(std::floor(x.dot(tangents[std::size_t(a)]) / cell));
          key[D] = 0;
          add_point_rows(rows_at, key, g.cell_weights(at), w, moving ? &plane.velocity : nullptr,
                         rows);
        });
      });
    }
  }
}

}  // namespace apiclab::eol
