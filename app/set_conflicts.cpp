#include "app/set_conflicts.hpp"

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <optional>

#include "app/cli.hpp"
#include "sim/scene/scene_json.hpp"

namespace apiclab::cli {
namespace {

using nlohmann::json;

struct Parsed {
  std::vector<std::string> path;
  json value;
};

// KEY=VALUE as a key path and a JSON value; nothing for a text apply_override refuses anyway.
std::optional<Parsed> parse(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) return std::nullopt;
  Parsed p;
  const std::string key = text.substr(0, eq);
  for (std::size_t start = 0;;) {
    const auto dot = key.find('.', start);
    p.path.push_back(key.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  JsonError error;
  if (!parse_json_strict(text.substr(eq + 1), p.value, error)) p.value = text.substr(eq + 1);
  return p;
}

// The value at `path` below `v` (object keys, array indices), or null when there is none.
const json* below(const json& v, const std::vector<std::string>& path, std::size_t from) {
  const json* node = &v;
  for (std::size_t i = from; i < path.size(); ++i) {
    if (node->is_object()) {
      auto it = node->find(path[i]);
      if (it == node->end()) return nullptr;
      node = &*it;
    } else if (node->is_array()) {
      char* end = nullptr;
      const long k = std::strtol(path[i].c_str(), &end, 10);
      if (path[i].empty() || *end || k < 0 || k >= long(node->size())) return nullptr;
      node = &(*node)[std::size_t(k)];
    } else {
      return nullptr;
    }
  }
  return node;
}

bool starts_with(const std::vector<std::string>& path, const std::vector<std::string>& prefix) {
  if (prefix.size() > path.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (path[i] != prefix[i]) return false;
  return true;
}

std::string joined(const std::vector<std::string>& path) {
  std::string s;
  for (const std::string& p : path) s += (s.empty() ? "" : ".") + p;
  return s;
}

// Whether b, applied after a, changes what a set; an assignment whose value is not known here
// disagrees with any other value of its key. Fills the key they share.
bool disagree(const Assignment& ea, const Parsed& a, const Assignment& eb, const Parsed& b,
              std::string& key) {
  if (starts_with(b.path, a.path)) {  // b sets a's key or a key inside a's value
    key = joined(b.path);
    if (ea.any_other_disagrees || eb.any_other_disagrees) return true;
    const json* was = below(a.value, b.path, a.path.size());
    return was && *was != b.value;  // a key a's value lacks is added, not changed
  }
  if (starts_with(a.path, b.path)) {  // b replaces the section holding a's key
    key = joined(a.path);
    const json* now = below(b.value, a.path, b.path.size());
    if (ea.any_other_disagrees || eb.any_other_disagrees) return now != nullptr;
    return !now || *now != a.value;
  }
  return false;
}

}  // namespace

void check_assignments(const std::vector<Assignment>& assignments) {
  std::vector<std::optional<Parsed>> parsed;
  for (const Assignment& a : assignments) parsed.push_back(parse(a.text));
  for (std::size_t j = 1; j < assignments.size(); ++j)
    for (std::size_t i = 0; i < j; ++i) {
      if (!parsed[i] || !parsed[j]) continue;
      std::string key;
      if (disagree(assignments[i], *parsed[i], assignments[j], *parsed[j], key))
        throw UsageError(assignments[i].given + " and " + assignments[j].given + " disagree on " +
                         key + " (give one of them, or the same value)");
    }
}

}  // namespace apiclab::cli
