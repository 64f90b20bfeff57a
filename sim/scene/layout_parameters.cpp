#include "sim/scene/layout_parameters.hpp"

#include <cmath>
#include <limits>
#include <random>

namespace apiclab {
namespace {

using S = SceneDesc;
using V = LayoutValue;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr Range kPositive{0, kInf, true, true};
constexpr Range kAnyReal{-kInf, kInf, true, true};
constexpr Range kSeed{0, 9223372036854775807.0, false, false};

ObjectDesc& object(S& s, int i) { return s.objects[size_t(i)]; }
const ObjectDesc& object(const S& s, int i) { return s.objects[size_t(i)]; }
V scalar(double x) { return {{x, 0, 0}}; }
ColliderDesc& collider(S& s, int i) { return s.colliders[size_t(i)]; }
const ColliderDesc& collider(const S& s, int i) { return s.colliders[size_t(i)]; }

double norm(const Vec3d& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

std::vector<LayoutParameter> declare() {
  using F = LayoutForm;
  return {
      {.key = "dim",
       .label = "dimension",
       .unit = "1",
       .form = F::count,
       .range = Range{2, 3, false, false},
       .default_value = {2, 0, 0},
       .help = "2 or 3: the number of components of every point, vector and velocity",
       .set = [](S& s, int, const V& v) { s.dim = int(v.x[0]); },
       .get = [](const S& s, int) { return scalar(s.dim); }},
      // Shapes (sim/geometry/shapes.hpp).
      {.key = "objects.*.shape.min",
       .label = "box min",
       .unit = "m",
       .form = F::point,
       .range = kAnyReal,
       .required = true,
       .types = "box",
       .help = "lower corner of the box",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.min = v.x; },
       .get = [](const S& s, int i) { return V{object(s, i).shape.min}; }},
      {.key = "objects.*.shape.max",
       .label = "box max",
       .unit = "m",
       .form = F::point,
       .range = kAnyReal,
       .required = true,
       .types = "box",
       .help = "upper corner of the box; must exceed min on every axis",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.max = v.x; },
       .get = [](const S& s, int i) { return V{object(s, i).shape.max}; }},
      {.key = "objects.*.shape.center",
       .label = "shape center",
       .unit = "m",
       .form = F::point,
       .range = kAnyReal,
       .required = true,
       .types = "ball annulus torus",
       .help = "center of the disk, sphere, ring, cylinder or torus; rotations turn about it",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.center = v.x; },
       .get = [](const S& s, int i) { return V{object(s, i).shape.center}; }},
      {.key = "objects.*.shape.radius",
       .label = "ball radius",
       .unit = "m",
       .range = kPositive,
       .required = true,
       .types = "ball",
       .help = "radius of the disk (2D) or sphere (3D)",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.radius = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(object(s, i).shape.radius); }},
      {.key = "objects.*.shape.inner",
       .label = "inner radius",
       .unit = "m",
       .range = kPositive,
       .required = true,
       .types = "annulus torus",
       .help = "annulus: the hole's radius; torus: the tube's radius",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.inner = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(object(s, i).shape.inner); }},
      {.key = "objects.*.shape.outer",
       .label = "outer radius",
       .unit = "m",
       .range = kPositive,
       .required = true,
       .types = "annulus torus",
       .help = "annulus: the outer radius; torus: the distance from the center to the tube's "
               "far side; must exceed inner",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.outer = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(object(s, i).shape.outer); }},
      {.key = "objects.*.shape.axis",
       .label = "shape axis",
       .unit = "1",
       .form = F::axis,
       .range = kAnyReal,
       .default_value = {0, 0, 1},
       .types = "annulus torus",
       .only_3d = true,
       .direction = true,
       .help = "3D: the cylinder's axis, the torus's axis of symmetry",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.axis = v.x; },
       .get = [](const S& s, int i) { return V{object(s, i).shape.axis}; }},
      {.key = "objects.*.shape.length",
       .label = "cylinder length",
       .unit = "m",
       .range = kPositive,
       .required = true,
       .types = "annulus",
       .only_3d = true,
       .help = "3D annulus: the hollow cylinder's length along its axis",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.length = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(object(s, i).shape.length); }},
      {.key = "objects.*.shape.scale",
       .label = "mesh scale",
       .unit = "1",
       .range = kPositive,
       .default_value = {1, 0, 0},
       .types = "mesh",
       .help = "factor on the OBJ's coordinates (placed as R (scale v) + translate)",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.scale = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(object(s, i).shape.scale); }},
      {.key = "objects.*.shape.translate",
       .label = "mesh translation",
       .unit = "m",
       .form = F::point,
       .range = kAnyReal,
       .types = "mesh",
       .help = "shift of the scaled and rotated mesh",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.translate = v.x; },
       .get = [](const S& s, int i) { return V{object(s, i).shape.translate}; }},
      {.key = "objects.*.shape.rotation.axis",
       .label = "rotation axis",
       .unit = "1",
       .form = F::axis,
       .range = kAnyReal,
       .default_value = {0, 0, 1},
       .direction = true,
       .help = "axis the shape turns about, through its center (a mesh: the origin)",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.rotation_axis = v.x; },
       .get = [](const S& s, int i) { return V{object(s, i).shape.rotation_axis}; }},
      {.key = "objects.*.shape.rotation.degrees",
       .label = "rotation angle",
       .unit = "degree",
       .range = kAnyReal,
       .required = true,
       .unless = "random_seed",
       .help = "angle of the rotation (required unless random_seed draws it)",
       .set = [](S& s, int i, const V& v) { object(s, i).shape.rotation_degrees = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(object(s, i).shape.rotation_degrees); }},
      {.key = "objects.*.shape.rotation.random_seed",
       .label = "rotation seed",
       .unit = "1",
       .form = F::seed,
       .range = kSeed,
       .unset_default = "degrees gives the angle",
       .help = "draws the angle uniformly from [0, 360) by std::mt19937_64(seed), the same on "
               "every platform; not with degrees",
       .set =
           [](S& s, int i, const V& v) {
             ShapeDesc& sh = object(s, i).shape;
             sh.rotation_seed = v.seed;
             sh.rotation_degrees = random_rotation_degrees(std::uint64_t(v.seed));
           },
       .get =
           [](const S& s, int i) {
             return V{{}, object(s, i).shape.rotation_seed};
           }},
      {.key = "objects.*.material",
       .label = "material",
       .unit = "1",
       .form = F::material,
       .range = Range{0, kInf, false, true},
       .required = true,
       .help = "the object's material: a name of materials[], or its index",
       .set = [](S& s, int i, const V& v) { object(s, i).material = int(v.x[0]); },
       .get = [](const S& s, int i) { return scalar(object(s, i).material); }},
      // Sampling (sim/geometry/sampling.hpp).
      {.key = "objects.*.sampling.spacing",
       .label = "sample spacing",
       .unit = "m",
       .range = kPositive,
       .required = true,
       .types = "lattice triangulated",
       .help = "distance between neighbouring lattice sites or triangle vertices",
       .set = [](S& s, int i, const V& v) { object(s, i).sampling.spacing = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(object(s, i).sampling.spacing); }},
      {.key = "objects.*.sampling.ppc",
       .label = "particles per cell",
       .unit = "1",
       .form = F::count,
       .range = Range{1, 1e6, false, false},
       .default_value = {4, 0, 0},
       .types = "ppc",
       .help = "particles per full cell; the lattice spacing is dx / ppc^(1/d)",
       .set = [](S& s, int i, const V& v) { object(s, i).sampling.ppc = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(object(s, i).sampling.ppc); }},
      {.key = "objects.*.sampling.radius",
       .label = "Poisson disk radius",
       .unit = "m",
       .range = kPositive,
       .required = true,
       .types = "poisson",
       .help = "minimum distance between samples (Bridson 2007)",
       .set = [](S& s, int i, const V& v) { object(s, i).sampling.radius = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(object(s, i).sampling.radius); }},
      {.key = "objects.*.sampling.seed",
       .label = "Poisson disk seed",
       .unit = "1",
       .form = F::seed,
       .range = kSeed,
       .default_value = {1, 0, 0},
       .types = "poisson",
       .help = "seed of the Poisson disk sampler's random numbers",
       .set = [](S& s, int i, const V& v) { object(s, i).sampling.seed = std::uint64_t(v.seed); },
       .get =
           [](const S& s, int i) {
             return V{{}, std::int64_t(object(s, i).sampling.seed)};
           }},
      // Motion and anchors.
      {.key = "objects.*.velocity",
       .label = "velocity",
       .unit = "m/s",
       .form = F::point,
       .range = kAnyReal,
       .help = "initial velocity of every particle of the object",
       .set = [](S& s, int i, const V& v) { object(s, i).velocity = v.x; },
       .get = [](const S& s, int i) { return V{object(s, i).velocity}; }},
      {.key = "objects.*.angular_velocity",
       .label = "angular velocity",
       .unit = "rad/s",
       .form = F::spin,
       .range = kAnyReal,
       .help = "spin about the shape's center (a mesh: its bounding box's center): a number "
               "(about z) in 2D, a vector in 3D; v_p += omega x (x_p - center)",
       .set = [](S& s, int i, const V& v) { object(s, i).angular_velocity = v.x; },
       .get = [](const S& s, int i) { return V{object(s, i).angular_velocity}; }},
      {.key = "objects.*.anchors.stiffness",
       .label = "anchor stiffness",
       .unit = "N/m",
       .range = kPositive,
       .default_value = {1e5, 0, 0},
       .help = "c of the zero-length springs f = -c (x - x0) on the anchored rows (Sec 6.7)",
       .set = [](S& s, int i, const V& v) { object(s, i).anchor_stiffness = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(object(s, i).anchor_stiffness); }},
      // Colliders (sim/geometry/collider_body.hpp).
      {.key = "colliders.*.point",
       .label = "collider point",
       .unit = "m",
       .form = F::point,
       .range = kAnyReal,
       .required = true,
       .types = "plane",
       .unless = "path",
       .help = "a point on the plane (its start, which velocity and angular_velocity move)",
       .set = [](S& s, int i, const V& v) { collider(s, i).point = v.x; },
       .get = [](const S& s, int i) { return V{collider(s, i).point}; }},
      {.key = "colliders.*.center",
       .label = "collider center",
       .unit = "m",
       .form = F::point,
       .range = kAnyReal,
       .required = true,
       .types = "box rod",
       .unless = "path",
       .help = "the body's center at t = 0, which it turns about",
       .set = [](S& s, int i, const V& v) { collider(s, i).point = v.x; },
       .get = [](const S& s, int i) { return V{collider(s, i).point}; }},
      {.key = "colliders.*.normal",
       .label = "collider normal",
       .unit = "1",
       .form = F::point,
       .range = kAnyReal,
       .required = true,
       .types = "plane",
       .direction = true,
       .help = "the plane's normal, pointing into the free side; normalised",
       .set =
           [](S& s, int i, const V& v) {
             const double n = norm(v.x);
             for (int a = 0; a < 3; ++a) collider(s, i).normal[size_t(a)] = v.x[a] / n;
           },
       .get = [](const S& s, int i) { return V{collider(s, i).normal}; }},
      {.key = "colliders.*.size",
       .label = "collider box size",
       .unit = "m",
       .form = F::point,
       .range = kPositive,
       .default_value = {0.2, 0.2, 0.2},
       .types = "box",
       .help = "the box's edge lengths along its own axes",
       .set = [](S& s, int i, const V& v) { collider(s, i).size = v.x; },
       .get = [](const S& s, int i) { return V{collider(s, i).size}; }},
      {.key = "colliders.*.radius",
       .label = "rod radius",
       .unit = "m",
       .range = kPositive,
       .default_value = {0.05, 0, 0},
       .types = "rod",
       .help = "the rod's radius: it is every point within radius of its segment (a capsule)",
       .set = [](S& s, int i, const V& v) { collider(s, i).radius = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(collider(s, i).radius); }},
      {.key = "colliders.*.length",
       .label = "rod length",
       .unit = "m",
       .range = Range{0, kInf, false, true},
       .default_value = {0.4, 0, 0},
       .types = "rod",
       .help = "the length of the rod's segment, along its own x axis (0: a ball)",
       .set = [](S& s, int i, const V& v) { collider(s, i).length = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(collider(s, i).length); }},
      {.key = "colliders.*.degrees",
       .label = "collider turn",
       .unit = "deg",
       .range = kAnyReal,
       .types = "box rod",
       .help = "the body's turn at t = 0 from the world axes, about z (2D) or axis (3D)",
       .set = [](S& s, int i, const V& v) { collider(s, i).degrees = v.x[0]; },
       .get = [](const S& s, int i) { return scalar(collider(s, i).degrees); }},
      {.key = "colliders.*.axis",
       .label = "collider axis",
       .unit = "1",
       .form = F::axis,
       .range = kAnyReal,
       .default_value = {0, 0, 1},
       .only_3d = true,
       .direction = true,
       .help = "the axis that degrees and the path's turns are about; normalised",
       .set =
           [](S& s, int i, const V& v) {
             const double n = norm(v.x);
             for (int a = 0; a < 3; ++a) collider(s, i).axis[size_t(a)] = v.x[a] / n;
           },
       .get = [](const S& s, int i) { return V{collider(s, i).axis}; }},
      {.key = "colliders.*.velocity",
       .label = "collider velocity",
       .unit = "m/s",
       .form = F::point,
       .range = kAnyReal,
       .help = "constant velocity: the body's point at time t is point + t velocity; the "
               "condition holds on the velocity relative to the body's",
       .set = [](S& s, int i, const V& v) { collider(s, i).velocity = v.x; },
       .get = [](const S& s, int i) { return V{collider(s, i).velocity}; }},
      {.key = "colliders.*.angular_velocity",
       .label = "collider angular velocity",
       .unit = "rad/s",
       .form = F::spin,
       .range = kAnyReal,
       .help = "constant spin about the body's point (a number about z in 2D, a vector in 3D); "
               "the body's velocity at x is velocity + omega x (x - point)",
       .set = [](S& s, int i, const V& v) { collider(s, i).angular_velocity = v.x; },
       .get = [](const S& s, int i) { return V{collider(s, i).angular_velocity}; }},
      {.key = "colliders.*.path",
       .label = "collider path",
       .unit = "s, m, deg",
       .form = F::keys,
       .range = kAnyReal,
       .unset_default = "none",
       .help = "keys [t, x, y(, z)(, degrees)], times increasing: the body's point and turn "
               "from its start at each t, linear between keys, held before the first and after "
               "the last; replaces point, velocity and angular_velocity",
       .set = [](S& s, int i, const V& v) { collider(s, i).path = v.keys; },
       .get = [](const S& s, int i) { return V{.keys = collider(s, i).path}; }},
  };
}

// Numbers of a value of form `f` in a scene of dimension `dim`.
int components(LayoutForm f, int dim) {
  switch (f) {
    case LayoutForm::point:
      return dim;
    case LayoutForm::axis:
      return 3;
    case LayoutForm::spin:
      return dim == 2 ? 1 : 3;
    default:
      return 1;
  }
}

// A path's keys: finite, at increasing times.
std::optional<std::string> keys_problem(const std::vector<ColliderKey>& keys) {
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const ColliderKey& key = keys[k];
    const bool finite = std::isfinite(key.t) && std::isfinite(key.degrees) &&
                        std::isfinite(key.point[0]) && std::isfinite(key.point[1]) &&
                        std::isfinite(key.point[2]);
    if (!finite) return "path key " + std::to_string(k) + " has a number that is not finite";
    if (k > 0 && !(key.t > keys[k - 1].t))
      return "path key " + std::to_string(k) + " is at t = " + format_value(key.t) +
             ", not after the key before it (t = " + format_value(keys[k - 1].t) + ")";
  }
  return std::nullopt;
}

}  // namespace

std::string LayoutParameter::key_at(int index) const {
  std::string k(key);
  if (const auto star = k.find('*'); star != std::string::npos)
    k.replace(star, 1, std::to_string(index));
  return k;
}

bool LayoutParameter::read_by(int dim, std::string_view type) const {
  return (!only_3d || dim == 3) && method_listed(types, type);
}

std::string LayoutParameter::form_text() const {
  switch (form) {
    case LayoutForm::number:
      return "a number";
    case LayoutForm::count:
      return "a whole number";
    case LayoutForm::seed:
      return "a non-negative integer";
    case LayoutForm::point:
      return "one number per axis";
    case LayoutForm::axis:
      return "3 numbers";
    case LayoutForm::spin:
      return "a number (2D), 3 numbers (3D)";
    case LayoutForm::material:
      return "a name or an index";
    case LayoutForm::keys:
      return "a list of [t, x, y(, z)(, degrees)]";
  }
  return "";
}

std::string LayoutParameter::default_text() const {
  if (required) return unless.empty() ? "required" : "required unless " + std::string(unless);
  if (!unset_default.empty()) return std::string(unset_default);
  const int n = components(form, 3);
  if (n == 1) return format_value(default_value[0]);
  if (default_value == Vec3d{0, 0, 0}) return "zero";
  std::string out = "[";
  for (int a = 0; a < n; ++a) out += (a ? ", " : "") + format_value(default_value[size_t(a)]);
  return out + "]";
}

std::string LayoutParameter::allowed_text() const {
  if (direction) return "not all zero";
  if (form == LayoutForm::seed) return "[0, 2^63)";
  if (form == LayoutForm::material) return "a material of the scene";
  if (form == LayoutForm::keys) return "finite numbers, times strictly increasing";
  return range.text() + (form == LayoutForm::count ? ", integer" : "");
}

std::string LayoutParameter::describe() const {
  const std::string u = unit == "1" ? "dimensionless" : "unit: " + std::string(unit);
  return std::string(help) + " [" + form_text() + "; " + u + "; allowed: " + allowed_text() +
         "; default: " + default_text() + (types.empty() ? "" : "; type " + std::string(types)) +
         (only_3d ? ", 3D" : "") + "]";
}

const std::vector<LayoutParameter>& layout_parameters() {
  static const std::vector<LayoutParameter> all = declare();
  return all;
}

const LayoutParameter* find_layout(std::string_view key, int* index) {
  for (const LayoutParameter& p : layout_parameters())
    if (key_matches(p.key, key, index)) return &p;
  return nullptr;
}

std::optional<std::string> layout_problem(const LayoutParameter& p, const LayoutValue& v, int dim) {
  const int n = components(p.form, dim);
  const int first = p.form == LayoutForm::spin && n == 1 ? 2 : 0;  // 2D spin: about z
  if (p.form == LayoutForm::seed) {
    if (p.range.contains(double(v.seed))) return std::nullopt;
    return std::string(p.label) + " " + std::to_string(v.seed) + " is outside the allowed range " +
           p.range.text();
  }
  if (p.form == LayoutForm::keys) return keys_problem(v.keys);
  for (int a = first; a < first + n; ++a) {
    const double x = v.x[size_t(a)];
    const bool whole = p.form != LayoutForm::count || x == std::floor(x);
    if (!p.range.contains(x) || !whole)
      return std::string(p.label) + " " + format_value(x) + " is outside the allowed range " +
             p.range.text() + (p.form == LayoutForm::count ? " (integers)" : "");
  }
  if (p.direction && !(norm(v.x) > 0))
    return std::string(p.label) + " has zero length; give a direction";
  return std::nullopt;
}

// mt19937_64's output is fixed by the standard (std::uniform_real_distribution's is not).
double random_rotation_degrees(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return 360.0 * double(rng() >> 11) * 0x1.0p-53;
}

}  // namespace apiclab
