#include "app/sweep/summary.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "app/output_file.hpp"
#include "app/sweep/tables.hpp"

namespace apiclab::sweep {
namespace {

// The run a scene's runs are compared with: its configuration, cost and its own errors.
void reference_section(std::ostringstream& md, const Spec& spec,
                       const std::vector<RunResult>& results, const std::string& scene) {
  std::vector<std::size_t> refs;
  for (std::size_t i = 0; i < results.size(); ++i)
    if (results[i].run->value_text("scene") == scene &&
        std::find(refs.begin(), refs.end(), results[i].run->reference) == refs.end())
      refs.push_back(results[i].run->reference);
  md << "\n## Reference: " << scene << "\n\n";
  for (std::size_t i : refs) {
    const RunResult& r = results[i];
    md << "- " << config_text(spec, *r.run) << " (run " << r.run->id << "): " << r.outcome;
    if (r.outcome == "blew_up") md << " at t = " << number_text(r.rec.fail_t, 3) << " s";
    if (r.outcome == "refused") md << " (" << r.rec.fail_message << ")";
    if (r.present) {
      md << ", " << number_text(r.cost(), 3) << " s in the steps (" << r.rec.steps << " steps, "
         << r.rec.particles << " particles); its own errors: "
         << (r.rec.conservation.energy_relative ? "max |dE|/E0 " : "max |dE| [J] (E0 round-off) ")
         << number_text(r.error("energy"), 3)
         << (r.rec.conservation.angular_relative ? ", max |dL|/|L0| "
                                                 : ", max |dL| [kg m^2/s] (L0 round-off) ")
         << number_text(r.error("angular"), 3);
      if (std::isfinite(r.rigid)) md << ", rigid " << number_text(r.rigid, 3);
      md << ". Its distances to itself are 0 by definition";
    }
    if (r.outcome == "blew_up" || !r.present) md << ". No run of " << scene << " has a distance";
    md << ".\n";
  }
}

// The target error's answer for one scene: the cheapest completed run meeting it, or plainly
// none, with the smallest error reached.
void target_line(std::ostringstream& md, const Spec& spec, const std::vector<RunResult>& results,
                 double target, const std::string& scene) {
  md << "- " << scene << ": ";
  if (auto best = cheapest_meeting(spec, results, target, scene)) {
    const RunResult& r = results[*best];
    md << config_text(spec, *r.run) << ", " << number_text(r.cost(), 3) << " s in the steps ("
       << r.rec.steps << " steps)";
    for (const std::string& e : spec.errors) md << ", " << e << " " << number_text(r.error(e), 3);
    md << " (run " << r.run->id << ")\n";
    return;
  }
  md << "no run meets it";
  // The completed run closest to it: the smallest of its largest selected error.
  std::optional<std::size_t> closest;
  double closest_worst = 0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const RunResult& r = results[i];
    if (r.run->value_text("scene") != scene || r.outcome != "completed" || is_reference(results, i))
      continue;
    double worst = 0;
    for (const std::string& e : spec.errors)
      worst = std::isnan(r.error(e)) ? r.error(e) : std::max(worst, r.error(e));
    if (std::isfinite(worst) && (!closest || worst < closest_worst))
      closest = i, closest_worst = worst;
  }
  if (closest)
    md << "; the closest completed run, " << config_text(spec, *results[*closest].run) << " (run "
       << results[*closest].run->id << "), reaches " << number_text(closest_worst, 3);
  else
    md << "; no completed run has every selected error";
  md << " (the reference is what the errors are measured against, not a candidate)\n";
}

}  // namespace

std::string write_summary(const Spec& spec, const std::vector<RunResult>& results,
                          const std::string& out_dir, std::optional<double> target_error,
                          const std::vector<std::string>& charts) {
  std::ostringstream md;
  const std::string& error = spec.errors.front();
  md << "# Sweep " << spec.name << "\n\nSpec: `" << spec.source << "`, " << results.size()
     << " runs.";
  std::map<std::string, int> counts;
  for (const RunResult& r : results) counts[r.outcome]++;
  for (auto& [k, n] : counts) md << " " << k << ": " << n << ".";
  double total = 0;
  for (const RunResult& r : results) total += r.present ? r.rec.total_wall_s : 0;
  md << " Run time, summed over runs: " << number_text(total, 3) << " s.\n\n";
  md << "Errors are relative L2 errors over the frames against each run's reference run "
        "(docs/sweeps.md); cost is the wall time inside the steps.\n";
  for (const std::string& c : charts) md << "\n![" << c << "](" << c << ")\n";

  for (const std::string& scene : scenes(spec)) reference_section(md, spec, results, scene);

  std::vector<std::size_t> refused;
  for (std::size_t i = 0; i < results.size(); ++i)
    if (results[i].outcome == "refused") refused.push_back(i);
  if (!refused.empty()) {
    md << "\n## Refused runs\n\nTheir processes ended without a record (runs/ID/refused.txt, "
          "logs/ID.log):\n\n";
    for (std::size_t i : refused)
      md << "- " << config_text(spec, *results[i].run) << " (run " << results[i].run->id
         << "): " << results[i].rec.fail_message << "\n";
  }

  for (const std::string& scene : scenes(spec)) {
    md << "\n## Pareto front: " << scene << ", " << error << " error against cost\n\n"
       << "| configuration | cost [s] | " << error << " error | outcome |\n|---|---|---|---|\n";
    for (std::size_t i : pareto_front(results, error, scene))
      md << "| " << config_text(spec, *results[i].run) << " | " << number_text(results[i].cost(), 3)
         << " | " << number_text(results[i].error(error), 3) << " | " << results[i].outcome
         << " |\n";
  }

  for (const StabilityMap& m : stability_maps(spec, results)) {
    md << "\n## Stability map: " << m.scene << "\n\n| | ";
    for (const std::string& c : m.column_labels)
      md << (m.column_key.empty() ? "outcome" : m.column_key + "=" + c) << " | ";
    md << "\n|---|";
    for (std::size_t c = 0; c < m.column_labels.size(); ++c) md << "---|";
    md << "\n";
    for (std::size_t r = 0; r < m.row_labels.size(); ++r) {
      md << "| " << m.row_labels[r] << " | ";
      for (long i : m.cells[r])
        md << (i < 0 ? "excluded" : cell_text(results[std::size_t(i)])) << " | ";
      md << "\n";
    }
  }

  for (const std::string& scene : scenes(spec)) {
    const auto conv = convergence_series(spec, results, error, scene);
    if (conv.empty()) continue;
    md << "\n## Convergence: " << scene << ", " << error
       << " error against dx\n\n| series | dx | error | fitted slope |\n|---|---|---|---|\n";
    for (const Series& s : conv) {
      std::string dx, err;
      for (std::size_t k = 0; k < s.x.size(); ++k) {
        dx += (k ? " " : "") + number_text(s.x[k], 3);
        err += (k ? " " : "") + number_text(s.y[k], 3);
      }
      md << "| " << s.label << " | " << dx << " | " << err << " | " << number_text(s.slope, 3)
         << " |\n";
    }
  }

  if (target_error) {
    md << "\n## Cheapest configuration with every selected error (";
    for (std::size_t k = 0; k < spec.errors.size(); ++k) md << (k ? ", " : "") << spec.errors[k];
    md << ") at most " << number_text(*target_error, 3) << "\n\n";
    for (const std::string& scene : scenes(spec))
      target_line(md, spec, results, *target_error, scene);
  }
  const std::string text = md.str();
  write_file_whole((std::filesystem::path(out_dir) / "summary.md").string(), text);
  return text;
}

}  // namespace apiclab::sweep
