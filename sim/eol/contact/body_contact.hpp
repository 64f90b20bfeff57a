// Contact rows against prescribed rigid bodies (boxes, rods, and planes that turn or follow a
// path; sim/geometry/collider_body.hpp), beside the plane rows of surface_contact.hpp. Each
// simplex of Γ near a body is clipped by the body's tangent plane at the point of the body
// nearest its centroid (exact on a box's face; on a rod's round side the tangent plane departs
// from the surface by h²/(8r) over a simplex of size h), and its rows are those of eq 28 with
// that plane's normal N: j_s = ∫_{Γ∩Ω} Φ_s (n·N) N dΓ. The body's velocity differs from point to
// point, v_body(x) = ν + ω × (x − c), so each quadrature point adds its own share to eq 29's
// right-hand side: the row's rate jᵀv_body = Σ w Φ_s (n·N) N·v_body(x_q). Rows are grouped as a
// plane's are, by collision cells along the surface: N rounded in the body's frame to a lattice
// of directions (a box's face normals exactly), then the cell of the quadrature point along
// that direction's tangents, measured from the body's center. Cells of the world grid would
// cut a face at every grid line it crosses and leave slivers of rows.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/eol/contact/surface_contact.hpp"
#include "sim/geometry/collider_body.hpp"

namespace apiclab::eol {

// The colliders that scene_planes leaves out (impulse_solve.hpp): boxes, rods, turning planes.
inline std::vector<ColliderDesc> scene_bodies(const SceneDesc& s) {
  std::vector<ColliderDesc> bodies;
  for (const ColliderDesc& c : s.colliders)
    if (!plane_row_collider(c)) bodies.push_back(c);
  return bodies;
}

inline void place_bodies(const std::vector<ColliderDesc>& bodies, int dim, double t,
                         std::vector<ColliderPose>& poses) {
  poses.clear();
  for (const ColliderDesc& c : bodies) poses.push_back(collider_pose(c, dim, t));
}

template <class T, int D>
Vec3d to_vec3d(const Vec<T, D>& x) {
  Vec3d r{0, 0, 0};
  for (int a = 0; a < D; ++a) r[std::size_t(a)] = double(x[a]);
  return r;
}

template <class T, int D>
Vec<T, D> from_vec3d(const Vec3d& x) {
  Vec<T, D> r;
  for (int a = 0; a < D; ++a) r[a] = T(x[std::size_t(a)]);
  return r;
}

// Whether a world box [lo, hi] comes within a body's reach of its center.
template <class T, int D>
bool box_may_touch(const Vec<T, D>& lo, const Vec<T, D>& hi,
                   const std::vector<ColliderPose>& poses) {
  for (const ColliderPose& p : poses) {
    double d2 = 0;
    for (int a = 0; a < D; ++a) {
      const double c = p.center[std::size_t(a)];
      const double e = std::max({double(lo[a]) - c, c - double(hi[a]), 0.0});
      d2 += e * e;
    }
    if (!(d2 > p.reach * p.reach)) return true;
  }
  return false;
}

// The node rows (solver.contact nodes) for a node inside a body: the projection of u − v_body.
template <class T, int D>
void apply_bodies(Vec<T, D>& u, const Vec<T, D>& x, const std::vector<ColliderPose>& poses) {
  for (const ColliderPose& p : poses) {
    const Vec3d at = to_vec3d(x);
    const ColliderPose::Distance d = p.distance(at);
    if (d.phi > 0) continue;
    const Vec<T, D> n = from_vec3d<T, D>(d.normal), vb = from_vec3d<T, D>(p.velocity_at(at));
    const T un = (u - vb).dot(n);
    switch (p.condition) {
      case BoundaryCondition::sticky:
        u = vb;
        break;
      case BoundaryCondition::separate:
        if (un < T(0)) u -= un * n;
        break;
      case BoundaryCondition::slip:
      case BoundaryCondition::periodic:
        u -= un * n;
        break;
    }
  }
}

// Appends to `rows` one object's rows against every body (y, simplex, R, p as in
// assemble_surface_rows; node numbers shifted by node_offset). Body k's rows carry −1 − 8k − kind
// in key[0], apart from the planes' keys.
template <class T, int D>
void assemble_body_rows(const EulerianGrid<T, D>& g, const std::vector<Vec<T, D>>& y,
                        const std::vector<std::uint32_t>& simplex, const Mat<T, D>& R,
                        const Vec<T, D>& p, const std::vector<ColliderPose>& poses, T cell,
                        std::uint32_t node_offset, ContactRows<T, D>& rows) {
  using contact_detail::Piece;
  const std::size_t first_row = rows.rows();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const ColliderPose& body = poses[k];
    const bool sticky = body.condition == BoundaryCondition::sticky;
    const bool bilateral = body.condition != BoundaryCondition::separate;
    for (std::size_t f = 0; f < simplex.size(); f += std::size_t(D)) {
      Piece<T, D> s;
      s.n = D;
      Vec<T, D> centroid = Vec<T, D>::Zero();
      bool behind = false;
      for (int v = 0; v < D; ++v) {
        s.p[std::size_t(v)] = y[simplex[f + std::size_t(v)]];
        const Vec<T, D> x = R * s.p[std::size_t(v)] + p;
        centroid += x / T(D);
        behind |= body.distance(to_vec3d(x)).phi <= 0;
      }
      // The tangent plane at the body's point nearest the centroid: N·x + c ≤ 0 inside.
      const ColliderPose::Distance near = body.distance(to_vec3d(centroid));
      // A body thinner than the simplex can cross it with no vertex inside: then the body's
      // distance at the centroid is below the simplex's reach from it.
      if (!behind) {
        T reach = 0;
        for (int v = 0; v < D; ++v)
          reach = std::max(reach, Vec<T, D>(R * s.p[std::size_t(v)] + p - centroid).norm());
        if (!(T(near.phi) < reach)) continue;
      }
      const Vec<T, D> N = from_vec3d<T, D>(near.normal);
      const Vec<T, D> q = centroid - T(near.phi) * N;
      const Vec<T, D> ny = R.transpose() * N;
      const T c = (p - q).dot(N);
      Vec<T, D> n;  // Γ's outward normal (world), as assemble_surface_rows
      if constexpr (D == 2) {
        const Vec<T, 2> t = s.p[1] - s.p[0];
        n = Vec<T, 2>(t[1], -t[0]);
      } else {
        n = (s.p[1] - s.p[0]).cross(Vec<T, 3>(s.p[2] - s.p[0]));
      }
      if (!(n.norm() > T(0))) continue;
      n = R * n.normalized();
      n = n.dot(N) * N;
      const auto tangents = plane_tangents<T, D>(N);
      // The row group's direction: N in the body's frame rounded to eighths, back in world.
      std::int64_t direction = 0;
      Vec3d rounded{0, 0, 0};
      for (int a = 0; a < 3; ++a) {
        const double nb = near.normal[0] * body.axes[std::size_t(a)][0] +
                          near.normal[1] * body.axes[std::size_t(a)][1] +
                          near.normal[2] * body.axes[std::size_t(a)][2];
        const double q8 = std::round(8 * nb);
        direction = direction * 17 + std::int64_t(q8) + 8;
        for (int b = 0; b < 3; ++b)
          rounded[std::size_t(b)] += q8 * body.axes[std::size_t(a)][std::size_t(b)];
      }
      Vec<T, D> group = from_vec3d<T, D>(rounded);
      group = group.norm() > T(0) ? Vec<T, D>(group.normalized()) : N;
      const auto along = plane_tangents<T, D>(group);
      const Vec<T, D> center = from_vec3d<T, D>(body.center);
      Piece<T, D> back;
      contact_detail::clip(s, ny, c, back);
      if (back.n == 0) continue;
      const PointRows<T, D> rows_at{first_row,   -1, sticky ? D : 1, bilateral,
                                    node_offset, n,  tangents};
      split_by_cells(g, back, 0, [&](const Piece<T, D>& piece) {
        integrate_piece(piece, [&](const Vec<T, D>& at, T w) {
          const Vec<T, D> x = R * at + p;
          const Vec<T, D> vb = from_vec3d<T, D>(body.velocity_at(to_vec3d(x)));
          std::array<std::int64_t, D + 1> key;
          key[0] = -1 - std::int64_t(k) * 8;
          for (int a = 0; a + 1 < D; ++a)
            key[std::size_t(a + 1)] =
                std::int64_t(std::floor((x - center).dot(along[std::size_t(a)]) / cell));
          key[D] = direction;
          add_point_rows(rows_at, key, g.cell_weights(at), w, body.moving ? &vb : nullptr, rows);
        });
      });
    }
  }
}

}  // namespace apiclab::eol
