#include "app/gui/pane_checkpoint.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>

#include "app/assets.hpp"
#include "app/checkpoint.hpp"
#include "app/output_file.hpp"
#include "app/output_owner.hpp"
#include "app/run_outputs.hpp"
#include "sim/scene/choice_parameters.hpp"
#include "sim/scene/parameters.hpp"
#include "sim/state_io.hpp"

namespace apiclab::gui {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// How many entries a word key with '*' has in the scene (materials, objects, colliders).
int choice_count(const ChoiceParameter& c, const SceneDesc& s) {
  const std::string_view k = c.key;
  if (k.find('*') == std::string_view::npos) return 1;
  if (k.starts_with("materials.")) return int(s.materials.size());
  if (k.starts_with("objects.")) return int(s.objects.size());
  if (k.starts_with("colliders.")) return int(s.colliders.size());
  return 0;
}

// The --set overrides that take `base` to `pane`: every word key, then every number, that
// differs (solver.method first, so that the rest read with that method's defaults).
std::vector<std::string> overrides_between(const SceneDesc& base, const SceneDesc& pane) {
  std::vector<std::string> sets;
  const std::string& method = pane.solver.method;
  for (const ChoiceParameter& c : choice_parameters()) {
    if (!c.read_by(method) || c.list || (c.only_3d && pane.dim != 3) ||
        choice_count(c, base) != choice_count(c, pane))
      continue;
    for (int i = 0; i < choice_count(c, pane); ++i)
      if (c.get(base, i) != c.get(pane, i)) sets.push_back(c.key_at(i) + "=" + c.get(pane, i));
  }
  for (const NumericParameter& p : numeric_parameters()) {
    if (!p.read_by(method) || (p.count && p.count(base) != p.count(pane))) continue;
    for (int i = 0; i < (p.count ? p.count(pane) : 1); ++i)
      if ((!p.is_set || p.is_set(pane, i)) && p.get(base, i) != p.get(pane, i))
        sets.push_back(p.key_at(i) + "=" + format_value(p.get(pane, i)));
  }
  return sets;
}

// The `run` options that load the pane's scene: its scene file and the overrides that make it.
cli::RunOptions run_options_of(const SceneDesc& pane, Precision precision) {
  cli::RunOptions o;
  o.scene = pane.source;
  o.precision = std::string(key_of(precision));
  o.quiet = true;
  SceneDesc base = load_scene(pane.source, {});
  if (base.solver.method != pane.solver.method)
    base = load_scene(pane.source, {"solver.method=" + pane.solver.method});
  o.sets = overrides_between(base, pane);
  return o;
}

// The pane's state as `run` writes it: its output indexes, the running diagnostics, the dump
// series (none), then the solver's state.
std::string run_state(const PaneView& v, const cli::RunProgress& p, const RunSummary& summary) {
  std::string bytes;
  StateWriter w(bytes);
  cli::save_run_state(w, p, summary, {});
  v.sim.save_state(w);
  return bytes;
}

// Writes the pane as a run's checkpoint into dir; returns the line the viewer shows.
std::string write_pane(const PaneView& v, const std::string& dir) {
  const SceneDesc& scene = v.sim.scene();
  const Precision precision = v.sim.precision();
  if (!v.sim.checkpoints())
    throw std::runtime_error("checkpoint: solver method '" + scene.solver.method +
                             "' has no checkpoints");
  if (v.sim.failure()) throw std::runtime_error("checkpoint: the pane failed; nothing to resume");
  if (v.origin && v.origin->csv_text.empty())
    throw std::runtime_error(
        "checkpoint: the CSV of the run this pane was opened from is gone "
        "or shorter than its checkpoint counted; Reset starts a new run");
  // The run whose options load this scene: refused when they do not load it exactly.
  cli::RunOptions o = run_options_of(scene, precision);
  const json settings = run_settings(cli::load_scene_with_options(o), precision, o.sets);
  if (const std::string d = cli::settings_difference(settings, run_settings(scene, precision, {}));
      !d.empty())
    throw std::runtime_error(
        "checkpoint: the pane's scene is not a scene file with --set "
        "overrides (" +
        d + ")");
  fs::create_directories(dir);
  o.csv = (fs::path(dir) / "diagnostics.csv").string();
  cli::CheckpointOptions c;
  c.dir = dir;
  // Its rows: the run's up to where the pane was opened, or the pane's own from t = 0.
  std::size_t from = 1;
  std::string csv;
  std::optional<RunSummary> summary;
  long unconverged = 0;
  if (v.origin) {
    csv = v.origin->csv_text, summary = v.origin->summary, unconverged = v.origin->unconverged;
  } else {
    DiagnosticsRow first = v.history[0];
    first.dt = 0;  // as run's first row
    csv = diagnostics_header(scene.solver.ledger) + '\n' + diagnostics_row_text(first);
    summary.emplace(DriftRule::of(v.sim, first));
  }
  for (std::size_t i = from; i < v.history.size(); ++i) {
    csv += diagnostics_row_text(v.history[i]);
    summary->add(v.history[i]);
    unconverged += v.history[i].converged ? 0 : 1;
  }
  write_file_whole(o.csv, csv);
  write_csv_sidecar(o.csv, settings);
  const json header = cli::run_header(v.sim, settings, o.csv, fs::current_path().string(),
                                      int(v.frame), cli::options_json(o, "", c));
  const cli::RunProgress p{std::int32_t(v.frame), csv.size(), 0, unconverged};
  cli::write_checkpoint(dir, header, run_state(v, p, *summary));
  std::ostringstream s;
  s << "checkpoint at t = " << v.sim.time() << " s (frame " << v.frame << ", step " << v.sim.steps()
    << ") in " << dir << "; apiclab run --resume " << dir << " continues it";
  return s.str();
}

// A relative path of the run's, as seen from the folder it started in.
std::string from_run_folder(const std::string& cwd, const std::string& path) {
  if (path.empty() || fs::path(path).is_absolute() || cwd.empty()) return path;
  const fs::path p = fs::path(cwd) / path;
  return fs::exists(p) ? p.string() : path;
}

// The run's CSV up to the checkpoint; empty when it is gone or shorter.
std::string csv_prefix(const std::string& path, std::uint64_t bytes) {
  std::ifstream in(path, std::ios::binary);
  std::string text(std::size_t(bytes), '\0');
  if (!in.read(text.data(), std::streamsize(bytes))) return "";
  return text;
}

}  // namespace

std::string default_checkpoint_dir(const ViewerState& st) {
  return "apiclab-out/" + cli::safe_file_name(st.scene.name) + ".checkpoint";
}

void save_pane_checkpoints(const ViewerState& st, SimWorker& worker, const std::string& dir) {
  const std::size_t n = st.panes.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::string to =
        n == 1 ? dir : (fs::path(dir) / ("pane-" + std::to_string(k + 1))).string();
    worker.with_pane(k, [to](const PaneView& v) { return write_pane(v, to); });
  }
}

void open_checkpoint(ViewerState& st, SimWorker& worker, const std::string& dir) {
  try {
    auto file = std::make_shared<const cli::CheckpointFile>(cli::read_checkpoint(dir));
    const json& h = file->header;
    cli::RunOptions o;
    std::string summary_file;
    cli::CheckpointOptions c;
    cli::options_from_json(h.value("options", json()), o, summary_file, c);
    const std::string cwd = h.value("cwd", "");
    o.scene = from_run_folder(cwd, o.scene);
    o.quiet = true;
    SceneDesc scene = cli::load_scene_with_options(o);
    const Precision precision = cli::precision_of(o);
    if (const std::string d = cli::settings_difference(h.value("settings", json()),
                                                       run_settings(scene, precision, o.sets));
        !d.empty())
      throw cli::UsageError("checkpoint " + dir + " was written with other settings: " + d);
    // The run's part of the state, then the solver's (read on the worker).
    auto state =
        std::make_shared<StateReader>(file->bytes.data() + file->state_at, file->state_size);
    auto origin =
        std::make_shared<PaneOrigin>(PaneOrigin{"", RunSummary(DiagnosticsRow{}, 0, 0), 0});
    std::vector<PvdSeries::Entry> series;
    const cli::RunProgress p = cli::load_run_state(*state, origin->summary, series);
    const int frame = p.last_frame;
    origin->unconverged = long(p.unconverged);
    origin->csv_text = csv_prefix(from_run_folder(cwd, h.value("csv", "")), p.csv_bytes);
    PaneConfig pane;
    pane.scheme = scene.solver.scheme, pane.flip_alpha = scene.solver.flip_alpha;
    pane.method = scene.solver.method;
    st.scene = scene;
    st.scene_path = scene.source;
    st.scene_loaded = true;
    st.panes = {pane};
    st.precision = precision;
    st.sweep.reset(), st.sweep_run = -1;
    st.load_error.clear();
    st.notice = "checkpoint " + dir + ": the run at t = " + std::to_string(h.value("t", 0.0)) +
                " s, paused; Play continues it";
    worker.load_restored(std::move(scene), pane, precision,
                         [file, state, origin, frame](Simulation& sim) {
                           sim.load_state(*state);
                           Restored r;
                           r.frame = frame;
                           r.drift = origin->summary.drift();
                           r.last = origin->summary.last();
                           r.origin = origin;
                           return r;
                         });
    worker.set_noise(st.color == render::ColorMode::noise);
  } catch (const StateError& e) {
    st.load_error = "checkpoint " + dir + ": " + e.what();
  } catch (const std::exception& e) {
    st.load_error = e.what();
  }
}

}  // namespace apiclab::gui
