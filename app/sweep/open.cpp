#include "app/sweep/open.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "app/cli.hpp"
#include "app/output_file.hpp"
#include "app/sweep/record.hpp"

namespace apiclab::sweep {
namespace {

namespace fs = std::filesystem;
using cli::UsageError;

std::optional<std::string> read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The files a sweep writes at the top of its folder (docs/sweeps.md, Outputs).
bool is_sweep_file_name(const std::string& name) {
  const std::string base = name.size() > 5 && name.compare(name.size() - 5, 5, ".part") == 0
                               ? name.substr(0, name.size() - 5)
                               : name;
  if (base == kSpecCopy || base == "runs.csv" || base == "summary.md") return true;
  const bool chart_file = base.size() > 4 && (base.compare(base.size() - 4, 4, ".png") == 0 ||
                                              base.compare(base.size() - 4, 4, ".csv") == 0);
  for (const char* prefix : {"error_vs_cost_", "stability_", "convergence_"})
    if (chart_file && base.rfind(prefix, 0) == 0) return true;
  return false;
}

// A message cut to its first line: the viewer and the command line show one line.
std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

// "scheme=flip, dt_factor=2": the axis values where a run differs from its reference (the pane
// title; the whole configuration is in the control column and the tooltips).
std::string differences(const PlannedRun& run, const PlannedRun& reference) {
  std::string s;
  for (const auto& [key, value] : run.config)
    if (reference.value_text(key) != value.text)
      s += (s.empty() ? "" : ", ") + key.substr(key.rfind('.') + 1) + "=" + value.text;
  return s;
}

}  // namespace

void write_spec_copy(const std::string& spec_path, const std::string& out_dir) {
  const fs::path copy = fs::path(out_dir) / kSpecCopy;
  std::error_code ec;
  if (fs::exists(copy, ec) && fs::equivalent(spec_path, copy, ec)) return;  // --collect DIR/spec
  const std::optional<std::string> text = read_text(spec_path);
  if (!text) throw UsageError("sweep: cannot read '" + spec_path + "'");
  write_file_whole(copy.string(), *text);
}

void claim_sweep_folder(const std::string& spec_path, const std::string& out_dir, bool overwrite) {
  const fs::path copy = fs::path(out_dir) / kSpecCopy;
  std::error_code ec;
  if (!fs::exists(copy, ec) || fs::equivalent(spec_path, copy, ec)) return;
  const std::optional<std::string> ours = read_text(spec_path), theirs = read_text(copy);
  const nlohmann::json a = nlohmann::json::parse(ours.value_or(""), nullptr, false),
                       b = nlohmann::json::parse(theirs.value_or(""), nullptr, false);
  if (!a.is_discarded() && a == b) return;  // the same spec: a rerun resumes
  if (!overwrite) {
    const std::string name = b.is_object() && b.contains("name") && b["name"].is_string()
                                 ? b["name"].get<std::string>()
                                 : std::string();
    const std::string owner =
        name.empty() ? copy.string() + " is no spec of this sweep"
                     : "sweep '" + name + "': " + copy.string() + " differs from " + spec_path;
    throw UsageError("sweep: " + out_dir + " holds another sweep (" + owner +
                     "); give another folder, or --overwrite to replace its spec, runs.csv, "
                     "summary and charts (run records stay: each is named by its "
                     "configuration)");
  }
  for (const auto& e : fs::directory_iterator(out_dir, ec)) {
    const std::string f = e.path().filename().string();
    if (is_sweep_file_name(f) && e.is_regular_file(ec)) fs::remove(e.path(), ec);
  }
}

std::shared_ptr<const OpenedSweep> open_sweep(const std::string& dir) {
  const std::string where = "sweep folder '" + dir + "'";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw UsageError(where + ": no such folder");
  const fs::path spec_file = fs::path(dir) / kSpecCopy;
  if (!fs::is_regular_file(spec_file, ec))
    throw UsageError(where + ": not a sweep (no " + std::string(kSpecCopy) +
                     "; `apiclab sweep SPEC --out DIR` writes one, and `--collect DIR` adds it "
                     "to an older folder)");
  auto out = std::make_shared<OpenedSweep>();
  out->dir = dir;
  out->spec = load_spec(spec_file.string());  // UsageError names the file and the key
  out->plan = make_plan(out->spec);
  std::size_t complete = 0;
  for (const PlannedRun& r : out->plan.runs) complete += record_complete(run_dir(dir, r));
  if (complete == 0)
    throw UsageError(where + ": no run of its " + std::to_string(out->plan.runs.size()) +
                     " has finished yet (runs/ID/result.json)");
  try {  // the sweep's own reading (results.cpp); a damaged record throws, naming its file
    out->results = collect(out->spec, out->plan, dir);
  } catch (const OldFramesError& e) {
    throw UsageError(where + ": " + first_line(e.what()) + "; `apiclab sweep SPEC --out " + dir +
                     "` records those runs again");
  } catch (const std::exception& e) {
    throw UsageError(where + ": a run record is half-written or damaged: " + first_line(e.what()));
  }
  for (const RunResult& r : out->results) out->missing += r.outcome == "no_result";
  if (out->spec.axis(out->spec.columns) || out->spec.columns == "dt_factor")
    out->maps = stability_maps(out->spec, out->results);
  const std::string& error = out->spec.errors.front();
  for (const std::string& scene : scenes(out->spec)) {
    SceneCharts c;
    c.scene = scene;
    c.cost = cost_series(out->spec, out->results, error, scene);
    c.front = pareto_front(out->results, error, scene);
    c.convergence = convergence_series(out->spec, out->results, error, scene);
    for (const StabilityMap& m : out->maps)
      if (m.scene == scene) c.stability = &m;
    out->charts.push_back(std::move(c));
  }
  return out;
}

SweepLaunch launch_run(const OpenedSweep& sweep, std::size_t run) {
  if (run >= sweep.plan.runs.size())
    throw UsageError("sweep: no run " + std::to_string(run) + " (the sweep has " +
                     std::to_string(sweep.plan.runs.size()) + ")");
  SweepLaunch l;
  l.run = run;
  l.reference = sweep.plan.runs[run].reference;
  std::vector<std::size_t> shown = {l.reference};
  if (run != l.reference) shown.push_back(run);
  for (std::size_t i : shown) {
    const PlannedRun& p = sweep.plan.runs[i];
    auto scene = std::make_shared<const SceneDesc>(scene_of(p));
    gui::PaneConfig c;
    c.scene = scene;
    c.precision = cli::precision_of(p.options());
    c.method = scene->solver.method;
    c.scheme = scene->solver.scheme;
    c.flip_alpha = scene->solver.flip_alpha;
    c.label =
        i == l.reference ? "reference" : "run " + differences(p, sweep.plan.runs[l.reference]);
    if (l.panes.empty()) {
      l.scene = *scene;
      l.precision = *c.precision;
    }
    l.panes.push_back(std::move(c));
  }
  return l;
}

std::size_t run_with_id(const OpenedSweep& sweep, const std::string& id) {
  for (std::size_t i = 0; i < sweep.plan.runs.size(); ++i)
    if (sweep.plan.runs[i].id == id) return i;
  throw UsageError("sweep folder '" + sweep.dir + "': no run with id '" + id +
                   "' (the first column of runs.csv)");
}

std::string run_summary(const OpenedSweep& sweep, std::size_t i) {
  const RunResult& r = sweep.results[i];
  std::string s = config_text(sweep.spec, *r.run) + "\n" + r.outcome;
  if (r.outcome == "blew_up")
    s += " at t = " + number_text(r.rec.fail_t) + " s (" + r.rec.fail_quantity + ")";
  if (r.outcome == "refused") s += ": " + r.rec.fail_message;
  if (r.present) {
    s += "\ncost " + number_text(r.cost()) + " s in " + std::to_string(r.rec.steps) + " steps, " +
         std::to_string(r.rec.particles) + " particles";
    s += "\ndx " + number_text(r.run->dx) + (r.run->dt > 0 ? ", dt " + number_text(r.run->dt) : "");
    for (const char* e : {"displacement", "com", "energy", "angular"}) {
      const double v = r.error(e);
      if (std::isfinite(v)) s += std::string("\n") + e + " error " + number_text(v);
    }
  }
  s += is_reference(sweep.results, i) ? "\n(the reference run)" : "\nid " + r.run->id;
  return s;
}

}  // namespace apiclab::sweep
