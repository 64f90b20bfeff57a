#include "app/run_outputs.hpp"

#include <cmath>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "sim/mpm/schemes/scheme_label.hpp"
#include "sim/scene/choice_parameters.hpp"
#include "sim/scene/parameters.hpp"

namespace apiclab {

namespace {

// Whether a scene of its method reads the key (the registry's method list, as the reader).
bool method_reads(const NumericParameter& p, const SceneDesc& scene) {
  return p.read_by(scene.solver.method);
}

// A value as the sidecar writes it: a count as an integer, "no bound" (infinite, or the 1e30 that
// stands for none) as null.
nlohmann::json parameter_value(const NumericParameter& p, double v) {
  if (!std::isfinite(v) || std::abs(v) >= 1e30) return nullptr;
  if (p.integer) return static_cast<long long>(v);
  return v;
}

// The solver as it ran: MPM's scheme, kernel and integrator; the EoL family's contact.
nlohmann::json family_settings(const SceneDesc& scene) {
  const SolverDesc& v = scene.solver;
  if (v.method != "mpm")
    return {{"method", v.method},
            {"label", run_label(scene)},
            {"contact", choice_key(eol_contact_choices(), v.eol.contact)},
            {"elasticity", choice_key(eol_elasticity_choices(), v.eol.elasticity)}};
  return {{"method", v.method},
          {"scheme", key_of(v.scheme)},
          {"label", run_label(scene)},  // the scheme with its parameter: "xpic(3)"
          {"kernel", key_of(v.kernel)},
          {"integrator", key_of(v.integrator)},
          {"preconditioner", key_of(v.preconditioner)}};
}

// With the ledger's columns, "ledger": true; absent without them.
nlohmann::json solver_settings(const SceneDesc& scene) {
  nlohmann::json s = family_settings(scene);
  if (scene.solver.ledger) s["ledger"] = true;
  return s;
}

}  // namespace

nlohmann::json run_settings(const SceneDesc& scene, Precision precision,
                            const std::vector<std::string>& overrides) {
  nlohmann::json parameters = nlohmann::json::object();
  for (const NumericParameter& p : numeric_parameters()) {
    if (!method_reads(p, scene)) continue;
    const int n = p.count ? p.count(scene) : 1;
    for (int i = 0; i < n; ++i)
      if (!p.is_set || p.is_set(scene, i))
        parameters[p.key_at(i)] = parameter_value(p, p.get(scene, i));
  }
  // The EoL family runs in double whatever --precision says (it warns).
  if (scene.solver.method != "mpm") precision = Precision::dbl;
  return {
      {"scene", scene.name},
      {"scene_file", scene.source},
      {"dim", scene.dim},
      {"precision", key_of(precision)},
      {"solver", solver_settings(scene)},
      {"time",
       {{"dt_rule", key_of(scene.time.rule)}, {"lands_on_frames", scene.time.lands_on_frames()}}},
      {"overrides", overrides},
      {"parameters", parameters}};
}

std::string diagnostics_row_text(const DiagnosticsRow& r) {
  std::ostringstream row;
  write_diagnostics_row(row, r);
  return row.str();
}

void write_csv_sidecar(const std::string& csv_path, const nlohmann::json& settings) {
  // The version beside the settings, not in them: a rebuild does not make a run another's.
  const nlohmann::json sidecar{{"csv", std::filesystem::path(csv_path).filename().string()},
                               {"apiclab_version", apiclab_version()},
                               {"settings", settings}};
  write_file_whole(csv_path + ".json", sidecar.dump(2) + '\n');
}

FrameIndex::FrameIndex(const std::string& dir, const std::vector<std::string>& panes)
    : out_((std::filesystem::path(dir) / "frames.csv").string()) {
  std::string head = "frame,t";
  if (panes.empty()) head += ",step";
  for (const std::string& p : panes) head += ",step_" + p;
  out_.write_row(head + '\n');
}

FrameIndex::FrameIndex(const std::string& dir, std::size_t keep)
    : out_((std::filesystem::path(dir) / "frames.csv").string(), keep) {}

void FrameIndex::add(int frame, double t, const std::vector<long>& steps) {
  if (!out_.is_open()) return;
  std::ostringstream row;
  row.precision(17);
  row << frame << ',' << t;
  for (long s : steps) row << ',' << s;
  row << '\n';
  out_.write_row(row.str());
}

std::string time_step_note(const SceneDesc& scene) {
  const TimeDesc& tm = scene.time;
  if (tm.lands_on_frames()) return "";
  const double frame = 1 / tm.fps, steps_per_frame = frame / tm.dt;
  std::ostringstream s;
  s << "fixed dt = " << tm.dt << " s is taken exactly; ";
  if (tm.dt > frame * (1 + 1e-9))
    s << "it is longer than a frame (1/fps = " << frame
      << " s), so frames repeat the step at or just past their time";
  else if (std::abs(steps_per_frame - std::round(steps_per_frame)) > 1e-6 * steps_per_frame)
    s << "frames are the step at or just past their time (1/fps = " << frame
      << " s is not a whole number of steps)";
  else
    return "";
  if (std::abs(tm.end / tm.dt - std::round(tm.end / tm.dt)) > 1e-6 * (tm.end / tm.dt))
    s << ", and the run ends at the first step past time.end = " << tm.end << " s";
  return s.str();
}

std::string dt_stats_text(const RunSummary::DtStats& dt) {
  std::ostringstream s;
  s.precision(4);
  s << "dt min/median/max = " << dt.min << " / " << dt.median << " / " << dt.max << " s";
  return s.str();
}

nlohmann::json run_summary_json(const SceneDesc& scene, const nlohmann::json& settings,
                                const RunSummary& summary, double final_time, const RunCosts& c,
                                const std::optional<Failure>& failure) {
  const RunSummary::DtStats dt = summary.dt();
  const bool relative = summary.angular_momentum_relative();
  const bool energy_relative = summary.energy_relative();
  const double wall = std::max(c.wall_seconds, 1e-9);
  nlohmann::json j = {
      {"apiclab_version", apiclab_version()},
      {"settings", settings},
      {"steps", summary.steps()},
      {"t_final", final_time},
      {"t_end", scene.time.end},
      {"dt", {{"min", dt.min}, {"median", dt.median}, {"max", dt.max}, {"unit", "s"}}},
      {"wall_seconds", c.wall_seconds},
      {"cpu_seconds", c.cpu_seconds},
      {"step_wall_seconds", summary.step_wall_seconds()},
      {"particles", c.particles},
      // A grid method (eol, eulerian) has no particles: no particle rate, its steps per second.
      {"particle_steps_per_second",
       c.particles ? nlohmann::json(double(c.particles) * double(c.steps_timed) / wall)
                   : nlohmann::json()},
      {"steps_per_second", double(c.steps_timed) / wall},
      {"energy_drift",
       {{"kind", energy_relative ? "relative" : "absolute"},
        {"quantity", energy_relative ? "(E - E0) / |E0|" : "E - E0 (E0 below round-off)"},
        {"unit", energy_relative ? "1" : "J"},
        {"final", summary.energy_drift()},
        {"max_abs", summary.max_energy_drift()}}},
      {"angular_momentum_drift",
       {{"kind", relative ? "relative" : "absolute"},
        {"quantity", relative ? "|L - L0| / |L0|" : "|L - L0| (L0 below round-off)"},
        {"unit", relative ? "1" : "kg m^2/s"},
        {"final", summary.angular_momentum_drift()},
        {"max", summary.max_angular_momentum_drift()}}},
      {"unconverged_implicit_steps", summary.unconverged_steps()},
      {"failure", nullptr}};
  if (failure)
    j["failure"] = {{"step", failure->step},
                    {"t", failure->t},
                    {"quantity", failure->quantity},
                    {"message", failure->message}};
  return j;
}

double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

}  // namespace apiclab
