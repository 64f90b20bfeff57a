#include "sim/scene/scene.hpp"

#include <algorithm>
#include <climits>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "sim/method_registry.hpp"
#include "sim/scene/choice_parameters.hpp"
#include "sim/scene/input_file.hpp"
#include "sim/scene/layout_parameters.hpp"
#include "sim/scene/message_text.hpp"
#include "sim/scene/parameters.hpp"
#include "sim/scene/scene_json.hpp"
#include "sim/scene/scene_method.hpp"

namespace apiclab {
namespace {

using nlohmann::json;

// A value or --set as a message quotes it on one readable line (sim/scene/message_text.hpp).
std::string shown(const std::string& s) { return message_text(s); }

// Reads one JSON object strictly: every key must be consumed, so a misspelled key is an error.
class Reader {
 public:
  Reader(const json& j, std::string path, const std::string& file)
      : j_(j), path_(std::move(path)), file_(file) {
    if (!j_.is_object()) fail("", "expected an object");
  }
  ~Reader() noexcept(false) {
    if (std::uncaught_exceptions()) return;
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!used_.count(it.key())) fail(it.key(), unknown_key(join(it.key())));
  }
  // A key of another solver family names the families that read it.
  static std::string unknown_key(const std::string& key) {
    std::string_view methods;
    if (const ChoiceParameter* c = find_choice(key)) methods = c->method;
    if (const NumericParameter* p = find_parameter(key)) methods = p->method;
    if (methods.empty()) return "unknown key";
    std::string words(methods);
    for (std::size_t s = words.find(' '); s != std::string::npos; s = words.find(' ', s + 5))
      words.replace(s, 1, " or ");
    return "unknown key for this solver.method (read by solver.method " + words + " only)";
  }
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(file_ + ": key '" + shown(join(key)) + "': " + what);
  }
  std::string join(const std::string& key) const {
    if (path_.empty()) return key;
    return key.empty() ? path_ : path_ + "." + key;
  }
  bool has(const std::string& key) const { return j_.contains(key); }
  // A key left unread on purpose (not an unknown key).
  void accept(const std::string& key) { used_.insert(key); }
  const json& raw(const std::string& key) {
    if (!has(key)) fail(key, "required key is missing");
    used_.insert(key);
    return j_.at(key);
  }
  // A key the section gives (raw refuses a missing one), as a finite number.
  double number(const std::string& key) {
    const json& v = raw(key);
    if (!v.is_number()) fail(key, "expected a number, got " + shown(v.dump()));
    double d = v.get<double>();
    if (!std::isfinite(d)) fail(key, "not finite");
    return d;
  }
  int integer(const std::string& key) {
    const json& v = raw(key);
    if (!v.is_number_integer() || v < json(INT_MIN) || v > json(INT_MAX))
      fail(key, "expected an integer, got " + shown(v.dump()));
    return v.get<int>();
  }
  bool boolean(const std::string& key, bool fallback) {
    if (!has(key)) return fallback;
    const json& v = raw(key);
    if (!v.is_boolean()) fail(key, "expected true or false, got " + shown(v.dump()));
    return v.get<bool>();
  }
  std::string string(const std::string& key, const std::string& fallback, bool required = false) {
    if (!has(key)) {
      if (required) fail(key, "required key is missing");
      return fallback;
    }
    const json& v = raw(key);
    if (!v.is_string()) fail(key, "expected a string, got " + shown(v.dump()));
    return v.get<std::string>();
  }
  // A vector of `dim` numbers (the components past `dim` stay as in fallback).
  Vec3d vec(const std::string& key, Vec3d fallback, int dim) {
    const json& v = raw(key);
    if (!v.is_array() || int(v.size()) != dim)
      fail(key, "expected " + std::to_string(dim) + " numbers, got " + shown(v.dump()));
    Vec3d out = fallback;
    for (int i = 0; i < dim; ++i) {
      if (!v[i].is_number()) fail(key, "expected numbers, got " + shown(v.dump()));
      out[i] = v[i].get<double>();
      if (!std::isfinite(out[i])) fail(key, "not finite");
    }
    return out;
  }
  Reader child(const std::string& key) { return Reader(raw(key), join(key), file_); }
  const std::string& file() const { return file_; }
  std::string path() const { return path_; }

 private:
  const json& j_;
  std::string path_;
  const std::string& file_;
  std::set<std::string> used_;
};

// A Reader as the SceneSection a method's validate hook sees.
class SectionOf final : public SceneSection {
 public:
  explicit SectionOf(Reader& r) : r_(r) {}
  bool has(const std::string& key) const override { return r_.has(key); }
  bool boolean(const std::string& key, bool fallback) override { return r_.boolean(key, fallback); }
  std::string string(const std::string& key, const std::string& fallback) override {
    return r_.string(key, fallback);
  }
  std::string where(const std::string& key) const override {
    return r_.file() + ": key '" + r_.join(key) + "'";
  }

 private:
  Reader& r_;
};

// The registry's numbers of one section (`prefix` "", "domain.", "time.dt.", "solver.",
// "materials.*."), so none is read by hand: each one the section gives is a number (an integer
// where the registry says so), a vector key ("gravity.*") one per axis; one it leaves out is
// refused when required, else keeps its default. `index`: the material's.
void read_numbers(Reader& r, SceneDesc& s, std::string_view prefix, int index = 0) {
  for (const NumericParameter& p : numeric_parameters()) {
    if (!p.key.starts_with(prefix) || !p.read_by(s.solver.method)) continue;
    std::string_view name = p.key.substr(prefix.size());
    const bool vector = name.ends_with(".*");
    if (vector) name.remove_suffix(2);
    if (name.find('.') != std::string_view::npos) continue;  // a key of a child section
    const std::string key(name);
    if (!r.has(key)) {
      if (p.required || (p.required_for && p.required_for(s)))
        r.fail(key, "required key is missing");
      if (p.default_for) p.set(s, index, p.default_for(s));
      continue;
    }
    if (!vector) {
      p.set(s, index, p.integer ? r.integer(key) : r.number(key));
      continue;
    }
    const Vec3d v = r.vec(key, {0, 0, 0}, s.dim);
    for (int a = 0; a < s.dim; ++a) p.set(s, a, v[a]);
  }
}

// A list key's array, each word set in turn.
void read_word_list(Reader& r, SceneDesc& s, const ChoiceParameter& p, const std::string& key,
                    int index) {
  std::string words;
  for (const ChoiceOption& o : p.options) words += (words.empty() ? "" : "|") + o.key;
  const json& v = r.raw(key);
  if (!v.is_array()) r.fail(key, "expected an array of " + words + ", got " + shown(v.dump()));
  for (const json& w : v) {
    if (!w.is_string()) r.fail(key, "expected words of " + words + ", got " + shown(w.dump()));
    try {
      p.set(s, index, w.get<std::string>());
    } catch (const std::invalid_argument& e) {
      r.fail(key, e.what());
    }
  }
}

// The registry's words and switches of one section, as read_numbers reads its numbers: each one
// the section gives is a word of the key's list (a switch: true or false), one it leaves out is
// refused when the registry has no default, else keeps the default. A method's keys are read
// once solver.method, the solver section's first, is known.
void read_choices(Reader& r, SceneDesc& s, std::string_view prefix, int index = 0) {
  for (const ChoiceParameter& p : choice_parameters()) {
    if (!p.key.starts_with(prefix) || !p.read_by(s.solver.method)) continue;
    if (p.only_3d && s.dim != 3) continue;
    const std::string key(p.key.substr(prefix.size()));
    if (key.find('.') != std::string::npos) continue;  // a key of a child section
    if (!r.has(key)) {
      if (p.default_key.empty()) r.fail(key, "required key is missing");
      p.set(s, index, p.default_key);
      continue;
    }
    if (p.list) {
      read_word_list(r, s, p, key, index);
      continue;
    }
    const std::string word =
        p.is_switch() ? (r.boolean(key, false) ? "true" : "false") : r.string(key, "");
    try {
      p.set(s, index, word);
    } catch (const std::invalid_argument& e) {
      r.fail(key, e.what());
    }
  }
}

// domain.boundary: a word for every wall, or an object of walls (domain.boundary.x-, ...), each
// one the object leaves out at the registry's default.
void read_domain(Reader r, SceneDesc& s) {
  const DomainDesc& d = s.domain;
  read_numbers(r, s, "domain.");
  if (!r.has("boundary") || r.raw("boundary").is_string()) return read_choices(r, s, "domain.");
  Reader walls = r.child("boundary");
  read_choices(walls, s, "domain.boundary.");
  for (int a = 0; a < s.dim; ++a)
    if ((d.walls[2 * a] == BoundaryCondition::periodic) !=
        (d.walls[2 * a + 1] == BoundaryCondition::periodic))
      r.fail("boundary", "periodic must be set on both walls of an axis");
}

void read_time(Reader r, SceneDesc& s) {
  read_numbers(r, s, "time.");
  if (r.has("dt")) {
    Reader d = r.child("dt");
    read_choices(d, s, "time.dt.");
    read_numbers(d, s, "time.dt.");  // after the rule, which decides whether value is required
  }
}

// The solver section: `method` picks the solver family, whose keys the registries name; its
// validate hook checks how they combine. `left_out`: the file's keys of another method, when
// `--set solver.method` switched it.
void read_solver(Reader r, SceneDesc& s, const std::set<std::string>& left_out) {
  read_choices(r, s, "solver.");
  read_numbers(r, s, "solver.");  // the hook's checks see the scene's numbers
  SectionOf section(r);
  find_method(s.solver.method)->validate(section, s);
  for (const std::string& key : left_out) r.accept(key);
}

// The plastic model's keys: its yield stress is required, and the elastic models read neither.
void read_plastic_keys(Reader& r, const MaterialDesc& m) {
  if (m.model == MaterialModel::plastic) {
    if (!m.yield_stress) r.fail("yield_stress", "required key is missing (model plastic)");
    return;
  }
  for (const char* key : {"yield_stress", "flow_rate"})
    if (r.has(key)) r.fail(key, "only the plastic model reads it");
}

// `switched`: `--set solver.method` gave another method than the file's, whose material keys
// (materials.*.viscosity) the new method leaves out, as it leaves out the file's solver keys.
void read_material(Reader r, SceneDesc& s, int index, bool switched) {
  MaterialDesc& m = s.materials.emplace_back();
  m.name = r.string("name", "material" + std::to_string(index));
  read_choices(r, s, "materials.*.", index);
  read_numbers(r, s, "materials.*.", index);
  read_plastic_keys(r, m);
  if (!switched) return;
  for (const NumericParameter& p : numeric_parameters())
    if (p.key.starts_with("materials.*.") && !p.read_by(s.solver.method))
      r.accept(std::string(p.key.substr(12)));
}

// The index of the material a key names by name or index.
int material_index(Reader& r, const std::string& key, const SceneDesc& s) {
  const json& m = r.raw(key);
  if (m.is_number_integer()) {
    if (m < json(0) || m >= json(s.materials.size()))  // compared as JSON: no int wrap-around
      r.fail(key, "no material with index " + shown(m.dump()));
    return m.get<int>();
  }
  if (!m.is_string()) r.fail(key, "expected a material name or index");
  for (size_t i = s.materials.size(); i-- > 0;)  // of two with one name, the last
    if (s.materials[i].name == m.get<std::string>()) return int(i);
  r.fail(key, "no material named " + shown(m.dump()));
}

// A path: an array of keys [t, x, y(, z)(, degrees)], each with dim + 1 or dim + 2 numbers.
std::vector<ColliderKey> read_keys(Reader& r, const std::string& key, int dim) {
  const json& j = r.raw(key);
  const std::string shape =
      dim == 2 ? "[t, x, y] or [t, x, y, degrees]" : "[t, x, y, z] or [t, x, y, z, degrees]";
  if (!j.is_array()) r.fail(key, "expected an array of keys " + shape);
  std::vector<ColliderKey> keys;
  for (std::size_t k = 0; k < j.size(); ++k) {
    const json& row = j[k];
    const bool numbers = row.is_array() && std::all_of(row.begin(), row.end(),
                                                       [](const json& x) { return x.is_number(); });
    if (!numbers || (row.size() != std::size_t(dim + 1) && row.size() != std::size_t(dim + 2)))
      r.fail(key,
             "key " + std::to_string(k) + ": expected " + shape + ", got " + shown(row.dump()));
    ColliderKey c;
    c.t = row[0].get<double>();
    for (int a = 0; a < dim; ++a) c.point[size_t(a)] = row[size_t(a + 1)].get<double>();
    if (row.size() == std::size_t(dim + 2)) c.degrees = row[size_t(dim + 1)].get<double>();
    keys.push_back(c);
  }
  return keys;
}

// One value of the layout table's form: numbers (of the scene's dimension, or three for an axis;
// a 2D spin is one number about z) or a seed kept exactly.
LayoutValue read_layout_value(Reader& r, const std::string& key, const LayoutParameter& p,
                              const SceneDesc& s) {
  const int dim = s.dim;
  LayoutValue v{p.default_value};
  switch (p.form) {
    case LayoutForm::number:
    case LayoutForm::count:
      v.x[0] = r.number(key);
      break;
    case LayoutForm::seed: {
      const json& j = r.raw(key);
      if (!j.is_number_integer() || j.get<long long>() < 0)
        r.fail(key, "expected a non-negative integer, got " + shown(j.dump()));
      v.seed = j.get<std::int64_t>();
      break;
    }
    case LayoutForm::point:
      v.x = r.vec(key, p.default_value, dim);
      break;
    case LayoutForm::axis:
      v.x = r.vec(key, p.default_value, 3);
      break;
    case LayoutForm::spin:
      if (dim == 2)
        v.x = {0, 0, r.number(key)};
      else
        v.x = r.vec(key, p.default_value, 3);
      break;
    case LayoutForm::material:
      v.x[0] = material_index(r, key, s);
      break;
    case LayoutForm::keys:
      v.keys = read_keys(r, key, dim);
      break;
  }
  return v;
}

// The layout table's keys of one section (`prefix` "objects.*.shape.", ...), as read_numbers
// reads the registry's: each one a section of this `type` word reads is a value of the key's form
// within its range, one it leaves out is refused when required, else keeps its default.
void read_layout(Reader& r, SceneDesc& s, std::string_view prefix, int index = 0,
                 std::string_view type = {}) {
  for (const LayoutParameter& p : layout_parameters()) {
    if (!p.key.starts_with(prefix) || !p.read_by(s.dim, type)) continue;
    const std::string key(p.key.substr(prefix.size()));
    if (key.find('.') != std::string::npos) continue;  // a key of a child section
    if (!r.has(key)) {
      if (p.required && (p.unless.empty() || !r.has(std::string(p.unless))))
        r.fail(key, "required key is missing");
      if (!p.required && p.unset_default.empty())
        p.set(s, index, {p.default_value, std::int64_t(p.default_value[0])});
      continue;
    }
    const LayoutValue v = read_layout_value(r, key, p, s);
    if (const auto why = layout_problem(p, v, s.dim)) r.fail(key, *why);
    p.set(s, index, v);
  }
}

// A section the file leaves out, read as an empty one: its keys keep their defaults.
Reader empty_section(const Reader& parent, const std::string& key) {
  static const json empty = json::object();
  return Reader(empty, parent.join(key), parent.file());
}

// Object `index`'s shape: its type through the choice registry, its numbers through the layout
// table; what relates them is checked here.
void read_shape(Reader r, SceneDesc& s, int index) {
  read_choices(r, s, "objects.*.shape.", index);
  ShapeDesc& sh = s.objects[size_t(index)].shape;
  const int dim = s.dim;
  read_layout(r, s, "objects.*.shape.", index, choice_key(shape_choices(), sh.type));
  switch (sh.type) {
    case ShapeType::box:
      for (int a = 0; a < dim; ++a)
        if (!(sh.max[a] > sh.min[a])) r.fail("max", "must exceed min on every axis");
      for (int a = 0; a < dim; ++a) sh.center[a] = 0.5 * (sh.min[a] + sh.max[a]);
      break;
    case ShapeType::annulus:
    case ShapeType::torus:
      if (!(sh.outer > sh.inner)) r.fail("outer", "must exceed inner");
      if (sh.type == ShapeType::torus && dim != 3)
        r.fail("type", "torus needs dim 3 (use annulus in 2D)");
      break;
    case ShapeType::mesh:
      sh.file = r.string("file", "", true);
      if (dim != 3) r.fail("type", "mesh needs dim 3");
      break;
    default:
      break;
  }
  if (r.has("rotation")) {
    Reader rot = r.child("rotation");
    if (rot.has("random_seed") && rot.has("degrees"))
      rot.fail("random_seed", "give either degrees or random_seed, not both");
    read_layout(rot, s, "objects.*.shape.rotation.", index);
  }
}

// Object `index`'s sampling: its type through the choice registry, its numbers through the
// layout table.
void read_sampling(Reader r, SceneDesc& scene, int index) {
  read_choices(r, scene, "objects.*.sampling.", index);
  read_layout(r, scene, "objects.*.sampling.", index,
              choice_key(sampling_choices(), scene.objects[size_t(index)].sampling.type));
}

// Object `index`, added to the scene before it is read (its words are set through the registry).
void read_object(Reader r, SceneDesc& s, int index) {
  ObjectDesc& o = s.objects.emplace_back();
  o.name = r.string("name", "object" + std::to_string(index));
  read_shape(r.child("shape"), s, index);
  read_layout(r, s, "objects.*.", index);  // material, velocity, angular_velocity
  read_sampling(r.has("sampling") ? r.child("sampling") : empty_section(r, "sampling"), s, index);
  if (o.sampling.type == SamplingType::triangulated &&
      (s.dim != 2 || o.shape.type != ShapeType::box || o.shape.rotation_degrees != 0))
    r.fail("sampling", "triangulated sampling needs an unrotated box in 2D");
  if (r.has("anchors")) {
    Reader a = r.child("anchors");
    read_choices(a, s, "objects.*.anchors.", index);
    read_layout(a, s, "objects.*.anchors.", index);
    if (o.sampling.type != SamplingType::triangulated)
      r.fail("anchors", "anchors need triangulated sampling");
  }
  // The object's bounding box must lie inside the domain.
  const ShapeDesc& sh = o.shape;
  Vec3d lo = sh.min, hi = sh.max;
  double ext = sh.type == ShapeType::ball ? sh.radius : sh.outer;
  if (sh.type == ShapeType::annulus && s.dim == 3) ext = std::max(ext, 0.5 * sh.length);
  if (sh.type == ShapeType::ball || sh.type == ShapeType::annulus || sh.type == ShapeType::torus)
    for (int a = 0; a < 3; ++a) {
      lo[a] = sh.center[a] - ext;
      hi[a] = sh.center[a] + ext;
    }
  if (sh.type != ShapeType::mesh)
    for (int a = 0; a < s.dim; ++a)
      if (lo[a] < s.domain.min[a] - 1e-12 || hi[a] > s.domain.max[a] + 1e-12)
        r.fail("shape", "object lies outside the domain on axis " + std::string(1, "xyz"[a]));
}

// Collider `index`, added to the scene before it is read: its type and condition through the
// choice registry, its numbers through the layout table (those its type reads).
void read_collider(Reader r, SceneDesc& s, int index) {
  ColliderDesc& c = s.colliders.emplace_back();
  read_choices(r, s, "colliders.*.", index);
  constexpr std::string_view kTypes[] = {"plane", "box", "rod"};
  read_layout(r, s, "colliders.*.", index, kTypes[int(c.type)]);
  if (c.condition == BoundaryCondition::periodic)
    r.fail("condition", "a collider cannot be periodic");
  if (r.has("path") && (r.has("velocity") || r.has("angular_velocity")))
    r.fail("path", "give a path or velocity and angular_velocity, not both");
  if (r.has("path") && c.path.empty()) r.fail("path", "expected at least one key");
}

SceneDesc parse_json(const json& j, const std::string& file,
                     const std::set<std::string>& left_out = {}, bool switched = false) {
  SceneDesc s;
  s.source = file;
  Reader r(j, "", file);
  s.name = r.string("name", std::filesystem::path(file).stem().string());
  s.description = r.string("description", "");
  read_layout(r, s, "");  // dim, before every key whose length it sets
  if (!r.has("domain")) r.fail("domain", "missing");
  read_domain(r.child("domain"), s);
  read_numbers(r, s, "");  // gravity
  if (r.has("time")) read_time(r.child("time"), s);
  if (r.has("solver")) read_solver(r.child("solver"), s, left_out);
  if (!r.has("materials") || !r.raw("materials").is_array() || r.raw("materials").empty())
    r.fail("materials", "expected a non-empty array");
  const json& mats = r.raw("materials");
  for (size_t i = 0; i < mats.size(); ++i)
    read_material(Reader(mats[i], "materials." + std::to_string(i), file), s, int(i), switched);
  // Every numeric parameter is read by now: ranges and the relations between values are
  // checked before any object is placed in the domain.
  validate(s);
  if (!r.has("objects") || !r.raw("objects").is_array() || r.raw("objects").empty())
    r.fail("objects", "expected a non-empty array");
  const json& objs = r.raw("objects");
  for (size_t i = 0; i < objs.size(); ++i)
    read_object(Reader(objs[i], "objects." + std::to_string(i), file), s, int(i));
  if (r.has("colliders")) {
    const json& cols = r.raw("colliders");
    if (!cols.is_array()) r.fail("colliders", "expected an array");
    for (size_t i = 0; i < cols.size(); ++i)
      read_collider(Reader(cols[i], "colliders." + std::to_string(i), file), s, int(i));
  }
  return s;
}

// A `--set` value that is not JSON is taken as a string when it is a bare word
// (solver.scheme=flip); anything else (1e400, nan, [1,) is refused as invalid JSON.
bool bare_word(const std::string& text) {
  static const std::regex word("[A-Za-z_][A-Za-z0-9_+-]*");
  static const std::regex not_a_number("[+-]?(nan|inf|infinity)", std::regex::icase);
  return std::regex_match(text, word) && !std::regex_match(text, not_a_number);
}

// `--set a.b.0.c=VALUE`: walks objects and existing array elements; missing keys are added (the
// strict parser then rejects them if the scene format does not know them). Numeric keys are checked
// here to be numbers, so the message names the --set that gave the value.
void apply_override(json& j, const std::string& assignment, const std::string& file) {
  auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError(file + ": --set '" + shown(assignment) +
                     "': expected KEY=VALUE with a JSON value, e.g. materials.0.E=2000");
  std::string key = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  const std::string where = file + ": --set " + shown(assignment);
  json value;
  JsonError error;
  if (!parse_json_strict(text, value, error)) {
    // Within a one-line value the position is a column; the key path would be the value's own.
    std::string at = error.position;
    if (at.rfind("line 1, ", 0) == 0) at = at.substr(8);
    if (!bare_word(text))
      throw SceneError(where + ": the value '" + shown(text) + "' is not valid JSON (" +
                       error.cause + (at.empty() ? "" : ", at " + at) + ")");
    value = text;  // a bare word is a string
  }
  json* node = &j;
  std::string walked;
  std::stringstream ss(key);
  std::vector<std::string> parts;
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  if (parts.empty() || key.back() == '.')
    throw SceneError(where + ": '" + shown(key) + "' is not a key path like materials.0.E");
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& p = parts[i];
    bool last = i + 1 == parts.size();
    walked += (walked.empty() ? "" : ".") + p;
    if (node->is_array()) {
      char* end = nullptr;
      long idx = std::strtol(p.c_str(), &end, 10);
      if (p.empty() || *end || idx < 0 || idx >= long(node->size()))
        throw SceneError(file + ": --set key '" + shown(walked) + "' does not exist");
      node = &(*node)[size_t(idx)];
    } else if (node->is_object()) {
      // A missing section is created (the strict reader rejects it if the format has no such
      // key): --scheme works on a scene without a solver section.
      if (!node->contains(p) && !last) (*node)[p] = json::object();
      node = &(*node)[p];
    } else {
      throw SceneError(file + ": --set key '" + shown(walked) + "' does not exist");
    }
  }
  // The range is the reader's to check (one message for every path, sim/scene/parameters.hpp).
  if (const NumericParameter* p = find_parameter(key)) {
    if (!value.is_number())
      throw SceneError(where + ": " + std::string(p->label) + " must be a number, got " +
                       shown(value.dump()));
  }
  *node = value;
}

// The solver method the scene's JSON names ("mpm" when none; "" when it is no string).
std::string method_of(const json& j) {
  if (!j.is_object() || !j.contains("solver") || !j["solver"].is_object()) return "mpm";
  const json& solver = j["solver"];
  if (!solver.contains("method")) return "mpm";
  return solver["method"].is_string() ? solver["method"].get<std::string>() : "";
}

// The file's solver keys, when `--set solver.method` gives another method than the file's: they
// belong to the file's method, and the new one reads those it knows (docs/cli.md). A key that a
// `--set` gives is the new method's to read.
std::set<std::string> switched_method_keys(const json& file, const json& set,
                                           const std::vector<std::string>& overrides) {
  std::set<std::string> keys;
  if (method_of(file) == method_of(set) || !file.contains("solver") || !file["solver"].is_object())
    return keys;
  for (auto it = file["solver"].begin(); it != file["solver"].end(); ++it)
    if (it.key() != "method") keys.insert(it.key());
  for (const std::string& o : overrides)
    if (o.rfind("solver.", 0) == 0) keys.erase(o.substr(7, o.find_first_of(".=", 7) - 7));
  return keys;
}

SceneDesc parse_with_overrides(json j, const std::string& file,
                               const std::vector<std::string>& overrides) {
  const json before = overrides.empty() ? json() : j;
  for (auto& o : overrides) apply_override(j, o, file);
  try {
    const bool switched = !overrides.empty() && method_of(before) != method_of(j);
    return parse_json(
        j, file,
        overrides.empty() ? std::set<std::string>{} : switched_method_keys(before, j, overrides),
        switched);
  } catch (const SceneError&) {
    throw;
  } catch (const std::exception& e) {
    // Not expected (every read above checks the kind first); never shows the library's tag.
    std::string what = e.what();
    if (what.rfind("[json.exception.", 0) == 0) what = what.substr(what.find(']') + 2);
    throw SceneError(file + ": " + what);
  }
}

}  // namespace

SceneDesc parse_scene_text(const std::string& text, const std::string& source,
                           const std::vector<std::string>& overrides) {
  try {
    json j;
    JsonError error;
    if (!parse_json_strict(text, j, error)) throw SceneError(source + ": " + error.text());
    return parse_with_overrides(std::move(j), source, overrides);
  } catch (const SceneError& e) {
    // Whatever text of the input a message quotes (a key, a value, a choice, a name), it stays
    // one line: fuzz_scene found a key holding "\n" split the message in two.
    const std::string what = e.what();
    if (what.find_first_of(kControlCharacters) == std::string::npos) throw;
    throw SceneError(message_text(what, std::string::npos));
  }
}

SceneMethod scene_method(const std::string& path, const std::vector<std::string>& overrides) {
  try {
    json j;
    JsonError error;
    if (!parse_json_strict(read_input_file(path, "scene file"), j, error)) return {};
    SceneMethod m;
    m.file_method = method_of(j);
    if (j.is_object() && j.contains("solver") && j["solver"].is_object())
      for (auto it = j["solver"].begin(); it != j["solver"].end(); ++it)
        if (it.key() != "method") m.file_keys.push_back(it.key());
    for (const std::string& o : overrides) apply_override(j, o, path);
    m.method = method_of(j);
    if (j.contains("solver") && j["solver"].is_object()) {
      const json& solver = j["solver"];
      const auto text = [&](const char* key) {
        return solver.contains(key) && solver[key].is_string() ? solver[key].get<std::string>()
                                                               : std::string();
      };
      m.scheme = text("scheme");
      m.kernel = text("kernel");
      m.integrator = text("integrator");
    }
    return m;
  } catch (const std::exception&) {
    return {};  // loading the scene reports it
  }
}

SceneDesc load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  return parse_scene_text(read_input_file(path, "scene file"), path, overrides);
}

}  // namespace apiclab
