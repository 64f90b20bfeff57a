// The numeric-parameter registry: every number a user can set in a scene, declared once with
// its scene key, label, unit, allowed range, default and help. The scene reader, `--set`, the
// CLI help, the GUI widgets and sweep axes all come from here, and one function validates a
// SceneDesc against it, so no path can build a solver from an out-of-range value.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sim/scene/scene.hpp"

namespace apiclab {

// An interval of allowed values; an infinite bound is written as ±inf.
struct Range {
  double lo, hi;
  bool lo_open, hi_open;
  bool contains(double v) const;
  std::string text() const;  // "(0, inf)", "[0, 1]", "(-1, 0.5)"
};

struct NumericParameter {
  // Scene JSON path; '*' stands for an index (a material, or a vector component).
  std::string_view key;
  std::string_view label;
  std::string_view unit;          // SI; "1" for dimensionless
  std::string_view unit_3d = {};  // when it differs in 3D (density); empty: same as unit
  Range range;
  // The one statement of the default: SceneDesc() starts from it and the reader keeps it for a key
  // the file leaves out (unused when required).
  double default_value = 0;
  bool required = false;  // the scene must give it
  bool integer = false;
  std::string_view help;  // cites the paper where there is a source
  double (*get)(const SceneDesc&, int index);
  void (*set)(SceneDesc&, int index, double value);
  // How many indices '*' takes in this scene; null for keys without '*'.
  int (*count)(const SceneDesc&) = nullptr;
  // Whether the scene gives a value at all (solver.lambda is optional); null: always.
  bool (*is_set)(const SceneDesc&, int index) = nullptr;
  // What the default is when is_set says the key is unset; empty: "from the integrator".
  std::string_view unset_default = {};
  // The solver methods whose `solver` section holds the key, space-separated ("mpm", "eol
  // eulerian"); empty: every method's scenes take it.
  std::string_view method = {};
  // Whether the scene must give it, where that depends on other keys (the fixed rule's step).
  bool (*required_for)(const SceneDesc&) = nullptr;
  // The default where it depends on other keys (the two-step rule's dt_max); null: default_value.
  double (*default_for)(const SceneDesc&) = nullptr;

  std::string key_at(int index) const;                 // "materials.*.E", 0 -> "materials.0.E"
  std::string unit_for(int dim) const;                 // unit in a scene of this dimension
  std::string default_text() const;                    // "1", "required", ...
  std::string describe() const;                        // help, unit, range and default in one line
  bool read_by(std::string_view solver_method) const;  // whether that method's scenes take it
};

const std::vector<NumericParameter>& numeric_parameters();

// Whether a key's method list ("mpm", "eol eulerian"; "" every method) names `solver_method`.
bool method_listed(std::string_view methods, std::string_view solver_method);

// Whether `key` ("materials.0.E", "materials.*.E") is the registry key `pattern`
// ("materials.*.E"), and the index its '*' stands for (0 when none).
bool key_matches(std::string_view pattern, std::string_view key, int* index = nullptr);

// A key like "materials.0.E" or "solver.flip_alpha" (or a pattern "materials.*.E"): the
// parameter and the index its '*' stands for (0 when none). Null when the key is not numeric.
const NumericParameter* find_parameter(std::string_view key, int* index = nullptr);

// Why `value` is not allowed for `p`, or nothing. The one message format the reader, the
// CLI and the GUI show: "<file>: key '<key>': <label> <value> is outside the allowed range
// <range>".
std::optional<std::string> parameter_error(const NumericParameter& p, int index, double value,
                                           const std::string& file);

// Throws SceneError (the message above) for the first out-of-range value, then checks what
// relates values (domain max > min, cell counts, periodic axes). The reader calls it on every
// scene it returns; the GUI calls it (through apply_parameter) before any restart.
void validate(const SceneDesc& scene);

// Sets a numeric key ("materials.0.nu", "time.dt.value") on a scene and validates it; on a
// bad key or value throws SceneError and leaves `scene` unchanged. The GUI's edit path and the
// sweep's axis setter.
void apply_parameter(SceneDesc& scene, std::string_view key, double value);

// A value as the messages and help texts print it (shortest round-trip form).
std::string format_value(double v);

}  // namespace apiclab
