#include "app/sweep/summary.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "app/output_file.hpp"
#include "app/sweep/tables.hpp"

namespace apiclab::sweep {
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
      for (long i : m.cells[r]) md << (i < 0 ? "" : cell_text(results[std::size_t(i)])) << " | ";
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
    for (const std::string& scene : scenes(spec)) {
      md << "- " << scene << ": ";
      if (auto best = cheapest_meeting(spec, results, *target_error, scene)) {
        const RunResult& r = results[*best];
        md << config_text(spec, *r.run) << ", " << number_text(r.cost(), 3) << " s in the steps ("
           << r.rec.steps << " steps)";
        for (const std::string& e : spec.errors)
          md << ", " << e << " " << number_text(r.error(e), 3);
        md << " (run " << r.run->id << ")\n";
      } else {
        md << "no completed run but the reference meets it\n";
      }
    }
  }
  const std::string text = md.str();
  write_file_whole((std::filesystem::path(out_dir) / "summary.md").string(), text);
  return text;
}

}  // namespace apiclab::sweep
