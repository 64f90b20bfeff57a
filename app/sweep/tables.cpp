#include "app/sweep/tables.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>

#include "sim/measure/metrics.hpp"

namespace apiclab::sweep {
namespace {

// The axes that vary (more than one value), in spec order.
std::vector<std::string> varying_axes(const Spec& spec) {
  std::vector<std::string> keys;
  for (const AxisGroup& g : spec.groups)
    for (const Axis& a : g.axes)
      if (a.values.size() > 1) keys.push_back(a.key);
  return keys;
}

std::string join_values(const PlannedRun& run, const std::vector<std::string>& keys) {
  std::string s;
  for (const std::string& k : keys) s += (s.empty() ? "" : " ") + run.value_text(k);
  return s;
}

std::string short_key(const std::string& key) {
  const auto dot = key.rfind('.');
  return dot == std::string::npos ? key : key.substr(dot + 1);
}

}  // namespace

std::string cell_text(const RunResult& r) {
  char buf[64];
  if (r.outcome == "blew_up") {
    std::snprintf(buf, sizeof buf, "blew up t=%.2g", r.rec.fail_t);
  } else if (r.outcome == "not_converged") {
    std::snprintf(buf, sizeof buf, "no conv. %ld", r.rec.unconverged_steps);
  } else if (r.outcome == "noisy") {
    std::snprintf(buf, sizeof buf, "noisy %.2g", r.rec.noise);
  } else if (r.outcome == "completed") {
    if (r.rec.conservation.energy_relative)
      std::snprintf(buf, sizeof buf, "dE %.3g%%", 100 * r.rec.conservation.final_energy);
    else  // E₀ is round-off (sim/measure/run_summary.hpp): the change itself
      std::snprintf(buf, sizeof buf, "dE %.2g J", r.rec.conservation.final_energy);
  } else if (r.outcome == "refused") {  // fail_message: "exit N: CAUSE"
    std::snprintf(buf, sizeof buf, "refused, %s",
                  r.rec.fail_message.substr(0, r.rec.fail_message.find(':')).c_str());
  } else {
    std::snprintf(buf, sizeof buf, "no result");
  }
  return buf;
}

std::vector<StabilityMap> stability_maps(const Spec& spec, const std::vector<RunResult>& results) {
  std::vector<StabilityMap> maps;
  const Axis* columns = spec.axis(spec.columns);
  std::vector<std::string> row_keys;
  for (const std::string& k : varying_axes(spec))
    if (!spec.follows_scene(k) && k != spec.columns) row_keys.push_back(k);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const PlannedRun& run = *results[i].run;
    const std::string scene = run.value_text("scene");
    auto map = std::find_if(maps.begin(), maps.end(), [&](auto& m) { return m.scene == scene; });
    if (map == maps.end()) {
      StabilityMap m;
      m.scene = scene;
      m.column_key = columns ? spec.columns : "";
      if (columns) {
        for (const Value& v : columns->values)  // zipped axes may repeat a value
          if (std::find(m.column_labels.begin(), m.column_labels.end(), v.text) ==
              m.column_labels.end())
            m.column_labels.push_back(v.text);
      } else {
        m.column_labels.push_back("");
      }
      maps.push_back(m);
      map = maps.end() - 1;
    }
    const std::string row = join_values(run, row_keys);
    auto r = std::find(map->row_labels.begin(), map->row_labels.end(), row);
    if (r == map->row_labels.end()) {
      map->row_labels.push_back(row);
      map->cells.push_back(std::vector<long>(map->column_labels.size(), -1));
      r = map->row_labels.end() - 1;
    }
    std::size_t c = 0;
    if (columns)
      c = std::size_t(std::find(map->column_labels.begin(), map->column_labels.end(),
                                run.value_text(spec.columns)) -
                      map->column_labels.begin());
    map->cells[std::size_t(r - map->row_labels.begin())][c] = long(i);
  }
  return maps;
}

std::vector<std::string> scenes(const Spec& spec) {
  std::vector<std::string> out;
  for (const Value& v : spec.axis("scene")->values)
    if (std::find(out.begin(), out.end(), v.text) == out.end()) out.push_back(v.text);
  return out;
}

namespace {

// The series of that label, appended empty when it is new.
Series& series_named(std::vector<Series>& out, const std::string& label) {
  auto s = std::find_if(out.begin(), out.end(), [&](auto& x) { return x.label == label; });
  if (s != out.end()) return *s;
  out.push_back({label, {}, {}, {}, 0});
  return out.back();
}

}  // namespace

std::string config_text(const Spec& spec, const PlannedRun& run) {
  std::string s;
  for (const std::string& k : varying_axes(spec))
    if (!spec.follows_scene(k))
      s += (s.empty() ? "" : ", ") + short_key(k) + "=" + run.value_text(k);
  return s.empty() ? "(the one configuration)" : s;
}

std::vector<Series> cost_series(const Spec& spec, const std::vector<RunResult>& results,
                                const std::string& error, const std::string& scene) {
  std::vector<Series> out;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const RunResult& r = results[i];
    if (r.run->value_text("scene") != scene) continue;
    if (is_reference(results, i)) continue;
    if (r.outcome != "completed" && r.outcome != "noisy" && r.outcome != "not_converged") continue;
    const double e = r.error(error);
    if (!(e > 0) || !(r.cost() > 0)) continue;
    std::string label = r.run->value_text(spec.series);
    if (label.empty()) label = "all";
    series_named(out, label).runs.push_back(i);
  }
  for (Series& s : out) {
    std::sort(s.runs.begin(), s.runs.end(),
              [&](auto a, auto b) { return results[a].cost() < results[b].cost(); });
    for (std::size_t i : s.runs) {
      s.x.push_back(results[i].cost());
      s.y.push_back(results[i].error(error));
    }
  }
  return out;
}

std::vector<std::string> distinguishing_axes(const Spec& spec,
                                             const std::vector<std::string>& without) {
  std::vector<std::string> keys;
  for (const AxisGroup& g : spec.groups) {
    std::vector<const Axis*> kept;
    for (const Axis& a : g.axes) {
      if (spec.follows_scene(a.key) ||
          std::find(without.begin(), without.end(), a.key) != without.end())
        continue;
      // Kept when it varies and the kept partners do not already fix its value.
      std::map<std::string, std::string> seen;
      bool varies = false, determined = true;
      for (std::size_t i = 0; i < g.size(); ++i) {
        std::string k;
        for (const Axis* b : kept) k += b->values[i].text + '\x1f';
        const auto [it, fresh] = seen.emplace(k, a.values[i].text);
        determined = determined && (fresh || it->second == a.values[i].text);
        varies = varies || a.values[i].text != a.values.front().text;
      }
      if (varies && !determined) kept.push_back(&a), keys.push_back(a.key);
    }
  }
  return keys;
}

std::string axes_text(const PlannedRun& run, const std::vector<std::string>& keys) {
  std::string s;
  for (const std::string& k : keys) {
    const Value* v = run.value(k);
    if (!v) continue;
    s += (s.empty() ? "" : " ") + (v->is_number ? short_key(k) + "=" + v->text : v->text);
  }
  return s;
}

std::size_t Marking::shape(const PlannedRun& run) const {
  std::string t;
  for (const std::string& k : shape_keys)
    t += (t.empty() ? "" : ", ") + short_key(k) + "=" + run.value_text(k);
  const auto it = std::find(shapes.begin(), shapes.end(), t);
  return it == shapes.end() ? 0 : std::size_t(it - shapes.begin());
}

std::string Marking::label(const PlannedRun& run) const {
  std::string t;
  for (const std::string& k : label_keys) t += (t.empty() ? "" : "/") + run.value_text(k);
  return t;
}

Marking marking(const Spec& spec, const std::vector<RunResult>& results, const std::string& scene,
                const std::vector<std::string>& without, std::size_t max_shapes) {
  std::vector<std::string> keys = distinguishing_axes(spec, without);
  auto distinct = [&](const std::string& k) {
    std::vector<std::string> seen;
    for (const RunResult& r : results)
      if (r.run->value_text("scene") == scene &&
          std::find(seen.begin(), seen.end(), r.run->value_text(k)) == seen.end())
        seen.push_back(r.run->value_text(k));
    return seen.size();
  };
  std::stable_sort(keys.begin(), keys.end(),
                   [&](const auto& a, const auto& b) { return distinct(a) < distinct(b); });
  Marking m;
  std::size_t combos = 1;
  for (const std::string& k : keys) {
    const std::size_t n = distinct(k);
    if (n > 1 && combos * n <= max_shapes && m.label_keys.empty())
      combos *= n, m.shape_keys.push_back(k);
    else if (n > 1)
      m.label_keys.push_back(k);
  }
  for (const RunResult& r : results) {
    if (r.run->value_text("scene") != scene) continue;
    std::string t;
    for (const std::string& k : m.shape_keys)
      t += (t.empty() ? "" : ", ") + short_key(k) + "=" + r.run->value_text(k);
    if (std::find(m.shapes.begin(), m.shapes.end(), t) == m.shapes.end()) m.shapes.push_back(t);
  }
  if (m.shapes.empty()) m.shapes.push_back("");
  return m;
}

std::vector<Series> convergence_series(const Spec& spec, const std::vector<RunResult>& results,
                                       const std::string& error, const std::string& scene) {
  std::vector<Series> out;
  const Axis* res = spec.axis("resolution");
  if (!res || res->values.size() < 2 || spec.follows_scene("resolution")) return out;
  const std::vector<std::string> keys = distinguishing_axes(spec, {"resolution"});
  for (std::size_t i = 0; i < results.size(); ++i) {
    const RunResult& r = results[i];
    if (r.run->value_text("scene") != scene) continue;
    if (is_reference(results, i) || !(r.error(error) > 0)) continue;
    if (r.outcome != "completed" && r.outcome != "noisy" && r.outcome != "not_converged") continue;
    std::string label = axes_text(*r.run, keys);
    if (label.empty()) label = "all";
    series_named(out, label).runs.push_back(i);
  }
  for (Series& s : out) {
    std::sort(s.runs.begin(), s.runs.end(),
              [&](auto a, auto b) { return results[a].run->dx < results[b].run->dx; });
    for (std::size_t i : s.runs) {
      s.x.push_back(results[i].run->dx);
      s.y.push_back(results[i].error(error));
    }
    s.slope = metrics::log_log_slope(s.x, s.y);
  }
  return out;
}

std::optional<std::size_t> cheapest_meeting(const Spec& spec, const std::vector<RunResult>& results,
                                            double target, const std::string& scene) {
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < results.size(); ++i) {
    if (results[i].run->value_text("scene") != scene) continue;
    const RunResult& r = results[i];
    // The reference meets any target trivially (its error against itself is 0).
    if (r.outcome != "completed" || is_reference(results, i)) continue;
    const bool meets = std::all_of(spec.errors.begin(), spec.errors.end(), [&](auto& e) {
      return r.error(e) <= target;  // NaN never meets
    });
    if (meets && (!best || r.cost() < results[*best].cost())) best = i;
  }
  return best;
}

}  // namespace apiclab::sweep
