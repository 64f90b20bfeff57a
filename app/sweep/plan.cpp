#include "app/sweep/plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <unordered_map>

#include "app/assets.hpp"
#include "app/cli.hpp"
#include "app/run_length.hpp"
#include "sim/scene/input_file.hpp"
#include "sim/scene/parameters.hpp"
#include "sim/simulation.hpp"

namespace apiclab::sweep {
namespace {

using cli::UsageError;

std::string exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// FNV-1a, 64 bits: a stable key for a configuration (not a security hash).
std::string hash_hex(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

// Each base scene's text, read once: a plan parses it a few times per run.
class SceneTexts {
 public:
  const std::string& of(const std::string& path) {
    auto it = texts_.find(path);
    if (it == texts_.end()) it = texts_.emplace(path, read_input_file(path, "scene file")).first;
    return it->second;
  }

 private:
  std::map<std::string, std::string> texts_;
};

SceneDesc parse_for(const Spec& spec, const PlannedRun& run,
                    const std::vector<std::string>& overrides, SceneTexts& texts) {
  try {
    return parse_scene_text(texts.of(run.scene_path), run.scene_path, overrides);
  } catch (const SceneError& e) {
    throw UsageError(spec.source + ": run " + run.label() + ": " + e.what());
  }
}

// A configuration as one string: the key of the map that finds a run by its configuration.
std::string config_key(const std::vector<std::pair<std::string, Value>>& config) {
  std::string key;
  for (const auto& [k, v] : config) key += k + '=' + v.text + '\n';
  return key;
}

// Calls fn(config) for each configuration of the Cartesian product over the groups (the first
// group slowest) that no exclusion matches.
template <class Fn>
void for_each_config(const Spec& spec, Fn fn) {
  std::vector<std::size_t> at(spec.groups.size(), 0);
  std::vector<std::pair<std::string, Value>> config;
  for (bool more = true; more;) {
    config.clear();
    for (std::size_t g = 0; g < spec.groups.size(); ++g)
      for (const Axis& a : spec.groups[g].axes) config.push_back({a.key, a.values[at[g]]});
    more = false;  // next index (odometer)
    for (std::size_t g = spec.groups.size(); g-- > 0;) {
      if (++at[g] < spec.groups[g].size()) {
        more = true;
        break;
      }
      at[g] = 0;
    }
    const auto value = [&](const std::string& key) -> const Value* {
      for (auto& [k, v] : config)
        if (k == key) return &v;
      return nullptr;
    };
    const bool excluded = std::any_of(spec.exclude.begin(), spec.exclude.end(), [&](auto& m) {
      return std::all_of(m.begin(), m.end(), [&](auto& kv) {
        const Value* v = value(kv.first);
        return v && std::find(kv.second.begin(), kv.second.end(), *v) != kv.second.end();
      });
    });
    if (!excluded) fn(config);
  }
}

// The base scene's own value of an axis key (choice or numeric), as the spec would write it.
std::string scene_value(const SceneDesc& s, const std::string& key) {
  if (key == "solver.method") return s.solver.method;
  if (key == "solver.scheme") return std::string(key_of(s.solver.scheme));
  if (key == "solver.kernel") return std::string(key_of(s.solver.kernel));
  if (key == "solver.integrator") return std::string(key_of(s.solver.integrator));
  if (key == "solver.apic_linear_form") return std::string(key_of(s.solver.apic_linear_form));
  if (key == "solver.preconditioner") return std::string(key_of(s.solver.preconditioner));
  if (key == "time.dt.rule") return std::string(key_of(s.time.rule));
  if (key == "precision") return "double";
  int index = 0;
  if (const NumericParameter* p = find_parameter(key, &index)) {
    if (p->is_set && !p->is_set(s, index)) return "";
    Value v;
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.15g", p->get(s, index));
    return buf;
  }
  return "";
}

// Largest initial particle speed of a scene (rigid rotations included), for dt_factor.
double max_initial_speed(SceneDesc scene) {
  scene.asset_dirs.push_back(assets_directory());
  auto sim = make_simulation(scene);
  const auto snap = sim->snapshot();
  double vmax = 0;
  for (std::size_t q = 0; q < snap->count(); ++q) {
    double v2 = 0;
    for (int a = 0; a < snap->dim; ++a) {
      const double v = snap->velocities[q * std::size_t(snap->dim) + std::size_t(a)];
      v2 += v * v;
    }
    vmax = std::max(vmax, std::sqrt(v2));
  }
  return vmax;
}

}  // namespace

const Value* PlannedRun::value(const std::string& key) const {
  for (auto& [k, v] : config)
    if (k == key) return &v;
  return nullptr;
}
std::string PlannedRun::value_text(const std::string& key) const {
  const Value* v = value(key);
  return v ? v->text : "";
}

std::string PlannedRun::label() const {
  std::string s;
  for (auto& [k, v] : config) s += (s.empty() ? "" : ", ") + k + "=" + v.text;
  return s;
}

std::string shell_quote(const std::string& w) {
  if (!w.empty() && w.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                        "0123456789_-+=.,/:@%") == std::string::npos)
    return w;
  std::string q = "'";
  for (char c : w) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string run_dir(const std::string& out_dir, const PlannedRun& run) {
  return (std::filesystem::path(out_dir) / "runs" / run.id).string();
}

std::string run_checkpoint_dir(const std::string& out_dir, const PlannedRun& run,
                               const SweepCheckpoints& checkpoints) {
  if (!checkpoints.dir.empty()) return (std::filesystem::path(checkpoints.dir) / run.id).string();
  return run_dir(out_dir, run) + ".partial/checkpoint";
}

cli::RunOptions PlannedRun::options() const {
  cli::RunOptions o;
  o.scene = scene_path;
  o.precision = precision;
  o.threads = threads;
  o.sets = overrides;
  o.quiet = true;
  return o;
}

std::vector<std::string> PlannedRun::command(const std::string& exe, const std::string& out_dir,
                                             const std::string& dump_formats,
                                             const SweepCheckpoints& checkpoints) const {
  const cli::RunOptions o = options();
  std::vector<std::string> args = {
      exe,           "run",       o.scene,     "--quiet",
      "--precision", o.precision, "--threads", std::to_string(o.threads)};
  for (const std::string& s : o.sets) {
    args.push_back("--set");
    args.push_back(s);
  }
  if (!dump_formats.empty())  // with --record, --dump names a folder inside the record
    for (const char* a : {"--dump", "dump", "--dump-format"}) args.push_back(a);
  if (!dump_formats.empty()) args.push_back(dump_formats);
  if (checkpoints.every_frames > 0)
    for (const std::string& a :
         {std::string("--checkpoint-every"), std::to_string(checkpoints.every_frames)})
      args.push_back(a);
  if (checkpoints.every_seconds > 0) {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.17g", checkpoints.every_seconds);
    for (const std::string& a : {std::string("--checkpoint-seconds"), std::string(seconds)})
      args.push_back(a);
  }
  if (checkpoints.on() && !checkpoints.dir.empty())
    for (const std::string& a :
         {std::string("--checkpoint-dir"), (std::filesystem::path(checkpoints.dir) / id).string()})
      args.push_back(a);
  args.push_back("--record");
  args.push_back(run_dir(out_dir, *this));
  return args;
}

SceneDesc scene_of(const PlannedRun& run) { return cli::load_scene_with_options(run.options()); }

std::size_t count_runs(const Spec& spec) {
  std::size_t n = 0;
  for_each_config(spec, [&](const auto&) { ++n; });
  return n;
}

Plan make_plan(const Spec& spec) {
  Plan plan;
  std::vector<double> frame_interval;             // per planned run: 1 / its scene's time.fps
  std::map<std::string, double> speed_cache;      // max |v0| per scene and resolution
  std::map<std::string, std::string> own_method;  // each base scene's solver.method
  SceneTexts texts;
  for_each_config(spec, [&](const std::vector<std::pair<std::string, Value>>& config) {
    PlannedRun run;
    run.config = config;
    run.scene_path = resolve_scene_path(run.value_text("scene"));
    if (const Value* p = run.value("precision")) run.precision = p->text;
    if (const Value* t = run.value("threads")) run.threads = int(t->number);
    // Another solver method replaces the whole solver section first (its keys then take their
    // defaults, and the base scene's keys for its own family go), before `set` and the axes.
    run.overrides.clear();
    if (const Value* m = run.value("solver.method")) {
      auto own = own_method.find(run.scene_path);
      if (own == own_method.end())
        own =
            own_method.emplace(run.scene_path, parse_for(spec, run, {}, texts).solver.method).first;
      if (m->text != own->second)
        run.overrides.push_back("solver={\"method\":\"" + m->text + "\"}");
    }
    run.overrides.insert(run.overrides.end(), spec.set.begin(), spec.set.end());
    for (auto& [k, v] : run.config)
      if (!is_derived_key(k) && k != "solver.method") run.overrides.push_back(k + "=" + v.text);
    // A fixed step from dt_factor replaces the scene's rule (the cfl rule refuses some kernels);
    // its value is set below, once Δx and the speeds are known.
    const Value* dt_factor = run.value("dt_factor");
    auto with_fixed_rule = [&] {
      std::vector<std::string> o = run.overrides;
      if (dt_factor) o.insert(o.end(), {"time.dt.rule=fixed", "time.dt.value=1"});
      return o;
    };
    SceneDesc scene = parse_for(spec, run, with_fixed_rule(), texts);
    run.dx = scene.domain.dx;
    if (const Value* r = run.value("resolution")) {
      // dx / r, and the sampling follows, so particles per cell stay fixed (ppc sampling needs
      // nothing: its count is per cell).
      run.dx = scene.domain.dx / r->number;
      run.overrides.push_back("domain.dx=" + exact(run.dx));
      for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const SamplingDesc& s = scene.objects[i].sampling;
        const std::string key = "objects." + std::to_string(i) + ".sampling.";
        if (s.type == SamplingType::lattice || s.type == SamplingType::triangulated)
          run.overrides.push_back(key + "spacing=" + exact(s.spacing / r->number));
        else if (s.type == SamplingType::poisson)
          run.overrides.push_back(key + "radius=" + exact(s.radius / r->number));
      }
      scene = parse_for(spec, run, with_fixed_rule(), texts);
    }
    if (const Value* f = dt_factor) {
      // Fixed Δt = factor · Δx / (c + max|v₀|), c of the stiffest material.
      double c = 0;
      for (const MaterialDesc& m : scene.materials) c = std::max(c, m.wave_speed());
      std::string cache_key = run.scene_path;
      for (auto& o : run.overrides) cache_key += "\n" + o;
      auto it = speed_cache.find(cache_key);
      if (it == speed_cache.end()) {
        try {
          it = speed_cache.emplace(cache_key, max_initial_speed(scene)).first;
        } catch (const SceneError& e) {
          throw UsageError(spec.source + ": run " + run.label() + ": " + e.what());
        }
      }
      run.dt = f->number * run.dx / (c + it->second);
      run.overrides.push_back("time.dt.rule=fixed");
      run.overrides.push_back("time.dt.value=" + exact(run.dt));
      // Steps that would pass a frame time are shortened to land on it, so every run records
      // its frames at the reference's times and the errors against it are defined.
      run.overrides.push_back("time.dt.land_on_frames=true");
      scene = parse_for(spec, run, run.overrides, texts);
    }
    try {  // the run's own `apiclab run` would refuse it: refused here, before any run starts
      check_run_length(scene, kDefaultMaxSteps, kDefaultMaxFrames);
    } catch (const SceneError& e) {
      throw UsageError(spec.source + ": run " + run.label() + ": " + e.what());
    }
    frame_interval.push_back(1 / scene.time.fps);
    plan.runs.push_back(std::move(run));
  });
  if (plan.runs.empty())
    throw UsageError(spec.source + ": key 'exclude': every configuration is excluded");

  // Landing caps a step at the frame interval, so a dt_factor step longer than it would not be
  // the step asked for: such a scene's runs all record their frames at its longest step's
  // interval instead (the same times for every run and its reference; docs/sweeps.md).
  std::map<std::string, double> longest_dt;
  for (const PlannedRun& run : plan.runs)
    longest_dt[run.scene_path] = std::max(longest_dt[run.scene_path], run.dt);
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    PlannedRun& run = plan.runs[i];
    const double longest = longest_dt[run.scene_path];
    if (longest > frame_interval[i]) {  // replaces a time.fps of `set`, which it overrides
      std::erase_if(run.overrides,
                    [](const std::string& o) { return o.rfind("time.fps=", 0) == 0; });
      run.overrides.push_back("time.fps=" + exact(1 / longest));
    }
    std::string canonical = "scene=" + run.value_text("scene") + "\nprecision=" + run.precision +
                            "\nthreads=" + std::to_string(run.threads);
    for (const std::string& o : run.overrides) canonical += "\n" + o;
    run.id = hash_hex(canonical);
  }

  // References: the named values; otherwise the finest resolution, the smallest dt_factor, the
  // run's own scene and, for other axes, the base scene's own value where the axis has it.
  std::map<std::string, SceneDesc> base;               // per scene, with the fixed overrides only
  std::unordered_map<std::string, std::size_t> index;  // configuration -> run
  for (std::size_t i = 0; i < plan.runs.size(); ++i)
    index.emplace(config_key(plan.runs[i].config), i);
  for (PlannedRun& run : plan.runs) {
    if (!base.count(run.scene_path)) {
      std::vector<std::string> fixed = spec.set;
      if (spec.axis("dt_factor"))
        fixed.insert(fixed.end(), {"time.dt.rule=fixed", "time.dt.value=1"});
      base.emplace(run.scene_path, parse_for(spec, run, fixed, texts));
    }
    const SceneDesc& scene = base.at(run.scene_path);
    std::vector<std::pair<std::string, Value>> want;
    for (const AxisGroup& g : spec.groups)
      for (const Axis& a : g.axes) {
        Value v = a.values.front();
        if (auto named = spec.reference.find(a.key); named != spec.reference.end()) {
          v = named->second;
        } else if (spec.follows_scene(a.key)) {
          v = *run.value(a.key);
        } else if (a.key == "resolution") {
          v = *std::max_element(a.values.begin(), a.values.end(),
                                [](auto& x, auto& y) { return x.number < y.number; });
        } else if (a.key == "dt_factor") {
          v = *std::min_element(a.values.begin(), a.values.end(),
                                [](auto& x, auto& y) { return x.number < y.number; });
        } else {
          const std::string own = scene_value(scene, a.key);
          for (const Value& c : a.values)
            if (c.text == own || (c.is_number && !own.empty() && c.number == std::stod(own))) v = c;
        }
        want.push_back({a.key, v});
      }
    const auto match = index.find(config_key(want));
    if (match == index.end()) {
      std::string text;
      for (auto& [k, v] : want) text += (text.empty() ? "" : ", ") + k + "=" + v.text;
      throw UsageError(spec.source + ": key 'reference': the reference configuration (" + text +
                       ") is not in the sweep (excluded, or not a zipped combination)");
    }
    run.reference = match->second;
  }
  return plan;
}

}  // namespace apiclab::sweep
