// A sweep specification (docs/sweeps.md): a base scene, fixed overrides and axes. Every check
// that can fail runs here, before any run starts: an unknown key, an empty axis, a value the
// parameter or choice registry rejects, an exclusion or reference that names no run.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace apiclab::sweep {

// One axis value as the spec writes it: a JSON number or string.
struct Value {
  std::string text;  // "0.5", "apic"
  double number = 0;
  bool is_number = false;
  bool operator==(const Value& o) const { return text == o.text; }
};

struct Axis {
  std::string key;
  std::vector<Value> values;
};

// Axes that vary together (a zipped group): member k takes values[i] of every axis at step i.
// A plain axis is a group of one.
struct AxisGroup {
  std::vector<Axis> axes;
  std::size_t size() const { return axes.front().values.size(); }
};

// A partial configuration: axis key -> allowed values (exclusions) or the value (reference).
using Match = std::map<std::string, std::vector<Value>>;

struct Spec {
  std::string name, source;                // source: the spec file, for messages
  std::vector<std::string> set;            // fixed `--set` overrides KEY=VALUE
  std::vector<AxisGroup> groups;           // includes the single-valued scene/precision/threads
  std::vector<Match> exclude;              // a run matching every key of one entry is left out
  std::map<std::string, Value> reference;  // named reference values (others: the default rule)
  // "rigid_rotation": every object in free rigid motion is the known answer (error "rigid").
  std::string known_answer;
  double noise_threshold = 0.1;          // RMS |v_p - v_PIC| / RMS |v_p(0)| above it: noisy
  std::string series = "solver.scheme";  // error-against-cost series
  std::string columns = "dt_factor";     // stability map columns
  std::vector<std::string> errors = {"displacement"};  // what --target-error must meet

  // The axis with this key, or null.
  const Axis* axis(const std::string& key) const;
  std::vector<std::string> axis_keys() const;
  // Whether the axis steps with the scene (the scene axis, or zipped with it, like a per-scene
  // time.end): it follows each run's scene in references, map rows and series.
  bool follows_scene(const std::string& key) const;
};

// Axis keys besides the registry's: "scene", "resolution", "dt_factor", "precision", "threads".
bool is_derived_key(const std::string& key);

// Reads and checks a spec; throws cli::UsageError with one line naming the spec and the key.
Spec load_spec(const std::string& path);
Spec parse_spec(const std::string& json_text, const std::string& source);

// The error columns a spec may select (errors, --target-error): "displacement", "com", ...
const std::vector<std::string>& error_names();

}  // namespace apiclab::sweep
