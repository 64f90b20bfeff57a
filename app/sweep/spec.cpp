#include "app/sweep/spec.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/assets.hpp"
#include "app/cli.hpp"
#include "sim/method_registry.hpp"
#include "sim/scene/parameters.hpp"
#include "sim/scene/registry.hpp"
#include "sim/scene/scene_json.hpp"

namespace apiclab::sweep {
namespace {

using json = nlohmann::ordered_json;
using cli::UsageError;

// The choice keys an axis may take, each checked against its registry.
void check_choice(const std::string& key, const std::string& value) {
  if (key == "solver.scheme")
    parse_choice(scheme_choices(), value, "scheme");
  else if (key == "solver.kernel")
    parse_choice(kernel_choices(), value, "kernel");
  else if (key == "solver.integrator")
    parse_choice(integrator_choices(), value, "integrator");
  else if (key == "solver.apic_linear_form")
    parse_choice(apic_linear_form_choices(), value, "APIC linear form");
  else if (key == "solver.preconditioner")
    parse_choice(cg_preconditioner_choices(), value, "CG preconditioner");
  else if (key == "time.dt.rule")
    parse_choice(dt_rule_choices(), value, "time-step rule");
  else if (key == "precision")
    parse_choice(precision_choices(), value, "precision");
  else if (key == "solver.method" && !find_method(value)) {
    std::string names;
    for (const std::string& n : method_names()) names += (names.empty() ? "" : "|") + n;
    throw std::invalid_argument("unknown solver method '" + value + "' (expected " + names + ")");
  }
}
bool is_choice_key(const std::string& key) {
  return key == "solver.scheme" || key == "solver.kernel" || key == "solver.integrator" ||
         key == "solver.apic_linear_form" || key == "solver.preconditioner" ||
         key == "time.dt.rule" || key == "precision" || key == "solver.method";
}

class Checker {
 public:
  explicit Checker(std::string source) : source_(std::move(source)) {}
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw UsageError(source_ + ": key '" + key + "': " + what);
  }

  Value value(const std::string& key, const json& j) const {
    Value v;
    if (j.is_number()) {
      v.number = j.get<double>();
      v.is_number = true;
      std::ostringstream s;
      s.precision(15);
      s << v.number;
      v.text = s.str();
    } else if (j.is_string()) {
      v.text = j.get<std::string>();
    } else {
      fail(key, "expected a number or a string, got " + j.dump());
    }
    check(key, v);
    return v;
  }

  // An axis value: the key must be known and the registry must accept the value.
  void check(const std::string& key, const Value& v) const {
    if (key == "scene") {
      if (v.is_number) fail(key, "expected a scene name or path");
      std::ifstream in(resolve_scene_path(v.text));
      if (!in) fail(key, "cannot open scene '" + v.text + "'");
      return;
    }
    if (key == "resolution" || key == "dt_factor") {
      if (!v.is_number || !(v.number > 0) || !std::isfinite(v.number))
        fail(key, "expected a positive number, got '" + v.text + "'");
      return;
    }
    if (key == "threads") {
      if (!v.is_number || v.number < 1 || v.number != std::floor(v.number))
        fail(key, "expected a whole number of threads >= 1, got '" + v.text + "'");
      return;
    }
    if (is_choice_key(key)) {
      if (v.is_number) fail(key, "expected one of its choices, got " + v.text);
      try {
        check_choice(key, v.text);
      } catch (const std::invalid_argument& e) {
        fail(key, e.what());
      }
      return;
    }
    int index = 0;
    const NumericParameter* p =
        key.find('*') == std::string::npos ? find_parameter(key, &index) : nullptr;
    if (!p)
      fail(key,
           "unknown axis key (expected a numeric registry key such as materials.0.E or "
           "solver.flip_alpha, a choice key "
           "solver.method|solver.scheme|solver.kernel|solver.integrator|"
           "solver.apic_linear_form|solver.preconditioner|time.dt.rule, or "
           "scene|resolution|dt_factor|precision|"
           "threads)");
    if (!v.is_number) fail(key, "expected a number, got '" + v.text + "'");
    if (auto e = parameter_error(*p, index, v.number, source_)) throw UsageError(*e);
  }

  Axis axis(const std::string& key, const json& j) const {
    Axis a{key, {}};
    // "solver.scheme": "all" is every scheme in the registry, in its order, so a scheme added
    // there joins the shipped sweeps without an edit.
    if (key == "solver.scheme" && j.is_string() && j.get<std::string>() == "all") {
      for (const auto& c : scheme_choices())
        a.values.push_back(value(key, json(std::string(c.key))));
      return a;
    }
    if (!j.is_array()) {
      a.values.push_back(value(key, j));
      return a;
    }
    if (j.empty()) fail(key, "empty axis (give at least one value)");
    for (const json& e : j) {
      Value v = value(key, e);
      if (std::find(a.values.begin(), a.values.end(), v) != a.values.end())
        fail(key, "value '" + v.text + "' appears twice");
      a.values.push_back(v);
    }
    return a;
  }

 private:
  std::string source_;
};

// The scene keys an axis sets: its own, or for a derived axis those it writes
// (app/sweep/plan.cpp); '*' stands for any one part of a key.
std::vector<std::string> keys_set_by(const std::string& axis) {
  if (axis == "dt_factor") return {"time.dt.rule", "time.dt.value"};
  if (axis == "resolution")
    return {"domain.dx", "objects.*.sampling.spacing", "objects.*.sampling.radius"};
  if (axis == "scene" || axis == "precision" || axis == "threads") return {};
  return {axis};
}

std::vector<std::string> parts_of(const std::string& key) {
  std::vector<std::string> parts;
  std::stringstream in(key);
  for (std::string part; std::getline(in, part, '.');) parts.push_back(part);
  return parts;
}

// A key and the section holding it ("time.dt" and "time.dt.value") name the same value.
bool overlaps(const std::string& a, const std::string& b) {
  const std::vector<std::string> x = parts_of(a), y = parts_of(b);
  for (std::size_t i = 0; i < std::min(x.size(), y.size()); ++i)
    if (x[i] != y[i] && x[i] != "*" && y[i] != "*") return false;
  return true;
}

// A key in `set` that an axis also sets: the axis would override it silently in every run.
void check_set_against_axes(const Spec& s, const Checker& check) {
  for (const std::string& assignment : s.set) {
    const std::string key = assignment.substr(0, assignment.find('='));
    for (const std::string& axis : s.axis_keys())
      for (const std::string& k : keys_set_by(axis))
        if (overlaps(key, k))
          check.fail(key, "in both \"set\" and the axis '" + axis +
                              "' (set fixes one value, the axis runs each of its values; "
                              "remove it from one)");
  }
}

}  // namespace

bool is_derived_key(const std::string& key) {
  return key == "scene" || key == "resolution" || key == "dt_factor" || key == "precision" ||
         key == "threads";
}

const std::vector<std::string>& error_names() {
  static const std::vector<std::string> names = {"displacement", "com",     "kinetic", "elastic",
                                                 "energy",       "angular", "rigid"};
  return names;
}

const Axis* Spec::axis(const std::string& key) const {
  for (const AxisGroup& g : groups)
    for (const Axis& a : g.axes)
      if (a.key == key) return &a;
  return nullptr;
}

std::vector<std::string> Spec::axis_keys() const {
  std::vector<std::string> keys;
  for (const AxisGroup& g : groups)
    for (const Axis& a : g.axes) keys.push_back(a.key);
  return keys;
}

bool Spec::follows_scene(const std::string& key) const {
  for (const AxisGroup& g : groups) {
    bool has_scene = false, has_key = false;
    for (const Axis& a : g.axes) {
      has_scene = has_scene || a.key == "scene";
      has_key = has_key || a.key == key;
    }
    if (has_scene && has_key) return true;
  }
  return false;
}

Spec parse_spec(const std::string& text, const std::string& source) {
  // Strict: a key written twice is refused (nlohmann would keep the last one silently).
  json j;
  JsonError error;
  if (!parse_json_strict(text, j, error)) throw UsageError(source + ": " + error.text());
  if (!j.is_object()) throw UsageError(source + ": malformed JSON (expected an object)");
  const Checker check(source);
  Spec s;
  s.source = source;
  static const std::vector<std::string> known = {
      "name",   "description", "scene",  "precision",       "threads",
      "set",    "axes",        "zip",    "exclude",         "reference",
      "series", "columns",     "errors", "noise_threshold", "known_answer"};
  for (auto& [k, v] : j.items())
    if (std::find(known.begin(), known.end(), k) == known.end())
      check.fail(
          k, "unknown spec key (expected " + [&] {
            std::string all;
            for (auto& n : known) all += (all.empty() ? "" : ", ") + n;
            return all;
          }() + ")");
  s.name = j.value("name", std::string("sweep"));

  auto add_axis = [&](const std::string& key, const json& values) {
    if (s.axis(key)) check.fail(key, "given twice (axes, zip, or a top-level key)");
    s.groups.push_back({{check.axis(key, values)}});
  };
  // scene, precision and threads: single-valued unless they are arrays (axes).
  if (j.contains("scene")) add_axis("scene", j["scene"]);  // or in "axes" or a "zip" group
  if (j.contains("precision")) add_axis("precision", j["precision"]);
  if (j.contains("threads")) add_axis("threads", j["threads"]);
  if (j.contains("set")) {
    if (!j["set"].is_object()) check.fail("set", "expected an object of KEY: VALUE overrides");
    for (auto& [k, v] : j["set"].items())
      s.set.push_back(k + "=" + (v.is_string() ? v.get<std::string>() : v.dump()));
  }
  if (j.contains("axes")) {
    if (!j["axes"].is_object()) check.fail("axes", "expected an object of KEY: [values]");
    for (auto& [k, v] : j["axes"].items()) {
      const bool all_schemes = k == "solver.scheme" && v == "all";
      if (!v.is_array() && !all_schemes)
        check.fail(k, "expected an array of values" +
                          std::string(k == "solver.scheme" ? " or \"all\"" : ""));
      add_axis(k, v);
    }
  }
  if (j.contains("zip")) {
    if (!j["zip"].is_array()) check.fail("zip", "expected an array of groups");
    for (const json& g : j["zip"]) {
      if (!g.is_object() || g.empty())
        check.fail("zip", "each group is an object of KEY: [values] of equal length");
      AxisGroup group;
      for (auto& [k, v] : g.items()) {
        if (!v.is_array()) check.fail(k, "expected an array of values");
        if (s.axis(k)) check.fail(k, "given twice (axes, zip, or a top-level key)");
        Axis a{k, {}};
        if (v.empty()) check.fail(k, "empty axis (give at least one value)");
        for (const json& e : v) a.values.push_back(check.value(k, e));
        if (!group.axes.empty() && a.values.size() != group.size())
          check.fail(k, "zipped with '" + group.axes.front().key + "' but has " +
                            std::to_string(a.values.size()) + " values, not " +
                            std::to_string(group.size()));
        group.axes.push_back(std::move(a));
      }
      s.groups.push_back(std::move(group));
    }
  }
  if (!s.axis("scene")) check.fail("scene", "missing (a shipped scene name or a path)");
  check_set_against_axes(s, check);
  // A value an exclusion or the reference names must be one of its axis's values.
  auto member = [&](const std::string& where, const std::string& key, const json& v) {
    const Axis* a = s.axis(key);
    if (!a) check.fail(key, where + " names a key that is not an axis of the sweep");
    Value value = check.value(key, v);
    if (std::find(a->values.begin(), a->values.end(), value) == a->values.end())
      check.fail(key, where + " value '" + value.text + "' is not in the sweep");
    return value;
  };
  if (j.contains("exclude")) {
    if (!j["exclude"].is_array()) check.fail("exclude", "expected an array of objects");
    for (const json& e : j["exclude"]) {
      if (!e.is_object() || e.empty()) check.fail("exclude", "each entry is a non-empty object");
      Match m;
      for (auto& [k, v] : e.items()) {
        if (v.is_array()) {
          if (v.empty()) check.fail(k, "exclude: empty list of values");
          for (const json& x : v) m[k].push_back(member("exclude", k, x));
        } else {
          m[k].push_back(member("exclude", k, v));
        }
      }
      s.exclude.push_back(std::move(m));
    }
  }
  if (j.contains("reference")) {
    if (!j["reference"].is_object()) check.fail("reference", "expected an object KEY: value");
    for (auto& [k, v] : j["reference"].items()) s.reference[k] = member("reference", k, v);
  }
  auto axis_or_none = [&](const char* key, std::string& out) {
    if (!j.contains(key)) return;
    if (!j[key].is_string()) check.fail(key, "expected an axis key");
    out = j[key].get<std::string>();
  };
  axis_or_none("series", s.series);
  axis_or_none("columns", s.columns);
  if (j.contains("series") && !s.axis(s.series))
    check.fail("series", "'" + s.series + "' is not an axis of the sweep");
  if (j.contains("columns") && !s.axis(s.columns))
    check.fail("columns", "'" + s.columns + "' is not an axis of the sweep");
  if (j.contains("errors")) {
    if (!j["errors"].is_array() || j["errors"].empty())
      check.fail("errors", "expected a non-empty array of error names");
    s.errors.clear();
    for (const json& e : j["errors"]) {
      const std::string name = e.is_string() ? e.get<std::string>() : e.dump();
      if (std::find(error_names().begin(), error_names().end(), name) == error_names().end())
        check.fail("errors",
                   "unknown error '" + name +
                       "' (expected displacement|com|kinetic|elastic|energy|angular|rigid)");
      s.errors.push_back(name);
    }
  }
  if (j.contains("known_answer")) {
    if (j["known_answer"] != "rigid_rotation")
      check.fail("known_answer", "expected \"rigid_rotation\" (the one known answer so far)");
    s.known_answer = "rigid_rotation";
  }
  if (std::find(s.errors.begin(), s.errors.end(), "rigid") != s.errors.end() &&
      s.known_answer.empty())
    check.fail("errors", "error 'rigid' needs \"known_answer\": \"rigid_rotation\"");
  if (j.contains("noise_threshold")) {
    if (!j["noise_threshold"].is_number() || !(j["noise_threshold"].get<double>() > 0))
      check.fail("noise_threshold", "expected a positive number");
    s.noise_threshold = j["noise_threshold"].get<double>();
  }
  return s;
}

Spec load_spec(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UsageError(path + ": cannot open sweep spec");
  std::stringstream buf;
  buf << in.rdbuf();
  return parse_spec(buf.str(), path);
}

}  // namespace apiclab::sweep
