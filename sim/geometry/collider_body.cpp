#include "sim/geometry/collider_body.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace apiclab {
namespace {

using M3 = std::array<Vec3d, 3>;  // columns

Vec3d add(const Vec3d& a, const Vec3d& b, double s = 1) {
  return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
}
double dot(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3d scaled(const Vec3d& a, double s) { return {s * a[0], s * a[1], s * a[2]}; }
double norm(const Vec3d& a) { return std::sqrt(dot(a, a)); }
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3d rotate(const M3& m, const Vec3d& v) {
  return add(add(scaled(m[0], v[0]), m[1], v[1]), m[2], v[2]);
}

// Rodrigues: the turn by `angle` radians about the unit axis k, as columns.
M3 turn(const Vec3d& k, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  M3 r;
  for (int j = 0; j < 3; ++j) {
    Vec3d e{0, 0, 0};
    e[size_t(j)] = 1;
    r[size_t(j)] = add(add(scaled(e, c), cross(k, e), s), k, (1 - c) * dot(k, e));
  }
  return r;
}

constexpr double kRad = std::numbers::pi / 180;

// The axis of turns: z in 2D.
Vec3d turn_axis(const ColliderDesc& c, int dim) { return dim == 2 ? Vec3d{0, 0, 1} : c.axis; }

// The path at t: point, turn (radians) and their slopes on the segment t lies in (a key's time
// starts the segment after it; held still before the first key and from the last).
struct PathState {
  Vec3d point{}, velocity{};
  double angle = 0, rate = 0;
};
PathState path_at(const std::vector<ColliderKey>& keys, double t) {
  PathState s;
  if (t < keys.front().t || keys.size() == 1 || t >= keys.back().t) {
    const ColliderKey& k = t < keys.front().t ? keys.front() : keys.back();
    s.point = k.point;
    s.angle = k.degrees * kRad;
    return s;
  }
  const auto next = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](double x, const ColliderKey& k) { return x < k.t; });
  const ColliderKey &a = *(next - 1), &b = *next;
  const double span = b.t - a.t, f = (t - a.t) / span;
  s.point = add(scaled(a.point, 1 - f), b.point, f);
  s.velocity = scaled(add(b.point, a.point, -1), 1 / span);
  s.angle = ((1 - f) * a.degrees + f * b.degrees) * kRad;
  s.rate = (b.degrees - a.degrees) * kRad / span;
  return s;
}

}  // namespace

bool collider_moves(const ColliderDesc& c) {
  if (c.path.size() > 1) return true;
  for (int a = 0; a < 3; ++a)
    if (c.velocity[size_t(a)] != 0 || c.angular_velocity[size_t(a)] != 0) return true;
  return false;
}

ColliderPose collider_pose(const ColliderDesc& c, int dim, double t) {
  ColliderPose p;
  p.type = c.type;
  p.dim = dim;
  p.condition = c.condition;
  p.moving = collider_moves(c);
  M3 q;  // the turn since t = 0
  if (!c.path.empty()) {
    const PathState s = path_at(c.path, t);
    const Vec3d k = turn_axis(c, dim);
    q = turn(k, s.angle);
    p.center = s.point;
    p.velocity = s.velocity;
    p.spin = scaled(k, s.rate);
  } else {
    Vec3d w = c.angular_velocity;
    if (dim == 2) w[0] = w[1] = 0;
    const double rate = norm(w);
    q = rate > 0 ? turn(scaled(w, 1 / rate), rate * t) : turn({0, 0, 1}, 0);
    p.center = add(c.point, c.velocity, t);
    p.velocity = c.velocity;
    p.spin = w;
  }
  if (dim == 2) p.center[2] = p.velocity[2] = 0;
  const M3 start = turn(turn_axis(c, dim), c.type == ColliderType::plane ? 0 : c.degrees * kRad);
  for (int j = 0; j < 3; ++j) p.axes[size_t(j)] = rotate(q, start[size_t(j)]);
  p.normal = rotate(q, c.normal);
  switch (c.type) {
    case ColliderType::plane:
      break;
    case ColliderType::box:
      p.half = scaled(c.size, 0.5);
      if (dim == 2) p.half[2] = 0;
      p.reach = norm(p.half);
      break;
    case ColliderType::rod:
      p.half = {0.5 * c.length, c.radius, 0};
      p.reach = p.half[0] + c.radius;
      break;
  }
  return p;
}

ColliderPose::Distance ColliderPose::distance(const Vec3d& x) const {
  if (type == ColliderType::plane) return {dot(add(x, center, -1), normal), normal};
  const Vec3d r = add(x, center, -1);
  Vec3d y{dot(r, axes[0]), dot(r, axes[1]), dim == 3 ? dot(r, axes[2]) : 0};  // body frame
  Vec3d n{0, 0, 0};                                                           // body frame
  double phi = 0;
  if (type == ColliderType::box) {
    Vec3d out{0, 0, 0};
    double inside = -std::numeric_limits<double>::infinity();
    int face = 0;
    for (int a = 0; a < dim; ++a) {
      const double q = std::abs(y[size_t(a)]) - half[size_t(a)];
      out[size_t(a)] = std::max(q, 0.0) * (y[size_t(a)] < 0 ? -1 : 1);
      if (q > inside) inside = q, face = a;
    }
    const double o = norm(out);
    if (o > 0) {
      phi = o;
      n = scaled(out, 1 / o);
    } else {
      phi = inside;
      n[size_t(face)] = y[size_t(face)] < 0 ? -1 : 1;
    }
  } else {
    y[0] -= std::clamp(y[0], -half[0], half[0]);  // from the segment's nearest point
    const double d = norm(y);
    phi = d - half[1];
    n = d > 0 ? scaled(y, 1 / d) : Vec3d{0, 1, 0};
  }
  return {phi, rotate(axes, n)};
}

Vec3d ColliderPose::velocity_at(const Vec3d& x) const {
  Vec3d v = add(velocity, cross(spin, add(x, center, -1)));
  if (dim == 2) v[2] = 0;
  return v;
}

}  // namespace apiclab
