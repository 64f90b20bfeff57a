// The numbers that lay a scene out: its dimension, each object's material, shape, sampling,
// motion and anchors, each collider's shape and motion. Each key is declared once with its label,
// form, range, default, help and the types that read it; the scene reader walks this table as it
// walks the numeric registry (sim/scene/parameters.hpp), and `run --help` and docs/scene-keys.md
// print it. They build the scene's bodies once: `--set` reaches them through the file, but they are
// no viewer widget, sweep axis or run setting.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/scene/parameters.hpp"

namespace apiclab {

// How a key's value is written in the file.
enum class LayoutForm {
  number,    // one number
  count,     // one whole number (4.0 counts as 4)
  seed,      // a non-negative JSON integer, kept exactly
  point,     // one number per axis of the scene
  axis,      // three numbers (2D scenes too: a rotation is about any axis)
  spin,      // 2D: one number, the rate about z; 3D: three numbers
  material,  // a material's name or index, kept as the index
  keys,      // a list of keys [t, x, y(, z)(, degrees)] (a collider's path)
};

// A value as read: its numbers (a scalar in x[0]) and a seed's exact integer.
struct LayoutValue {
  Vec3d x{};
  std::int64_t seed = 0;
  std::vector<ColliderKey> keys = {};  // form keys
};

struct LayoutParameter {
  std::string_view key;    // scene JSON path; '*' stands for an object's or collider's index
  std::string_view label;  // what a message calls the value
  std::string_view unit;   // SI; "1" for dimensionless
  LayoutForm form = LayoutForm::number;
  Range range;  // each number given must lie in it
  // The one statement of the default, kept for a key the file leaves out (a scalar's in x); a
  // material, object or collider built in code starts from the same (a test holds them equal).
  Vec3d default_value{};
  bool required = false;  // the section must give it (or `unless`)
  // The words of the section's `type` that read the key ("ball", "annulus torus"); empty: every.
  std::string_view types = {};
  bool only_3d = false;    // read in 3D scenes only
  bool direction = false;  // a vector of non-zero length
  // A required key the section may replace by this one (rotation: degrees or random_seed).
  std::string_view unless = {};
  // What leaving out a key without a default means; empty: the key has default_value.
  std::string_view unset_default = {};
  std::string_view help;
  void (*set)(SceneDesc&, int index, const LayoutValue&);
  LayoutValue (*get)(const SceneDesc&, int index);

  std::string key_at(int index) const;  // "objects.*.shape.radius", 0 -> "objects.0.shape.radius"
  // Whether a section of that `type` word in a scene of dimension `dim` reads the key.
  bool read_by(int dim, std::string_view type) const;
  std::string form_text() const;     // "a number", "3 numbers", ...
  std::string allowed_text() const;  // "(0, inf)", "[1, 1e+06], integer", "not all zero"
  std::string default_text() const;  // "4", "[0, 0, 1]", "required"
  std::string describe() const;      // help, unit, form, range and default in one line
};

// In the order a scene file reads: dim, objects (shape, rotation, material, sampling, motion,
// anchors), colliders.
const std::vector<LayoutParameter>& layout_parameters();

// A key like "objects.0.shape.radius" (or its pattern): its entry and the index its '*' stands
// for; null when the key is not in the table.
const LayoutParameter* find_layout(std::string_view key, int* index = nullptr);

// Why `v` is not allowed for `p` in a scene of dimension `dim`, or nothing: the one message for a
// bad value, "ball radius -1 is outside the allowed range (0, inf)", "rotation axis has zero
// length; give a direction". The reader prefixes the file and the key.
std::optional<std::string> layout_problem(const LayoutParameter& p, const LayoutValue& v, int dim);

// rotation.random_seed: an angle uniform in [0, 360), the same on every platform.
double random_rotation_degrees(std::uint64_t seed);

}  // namespace apiclab
