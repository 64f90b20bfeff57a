// DIR/summary.md: outcome counts, the Pareto front of error against cost, the stability maps,
// the convergence slopes and, with --target-error, the cheapest configuration meeting it.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "app/sweep/results.hpp"

namespace apiclab::sweep {

// Writes out_dir/summary.md and returns its text.
std::string write_summary(const Spec& spec, const std::vector<RunResult>& results,
                          const std::string& out_dir, std::optional<double> target_error,
                          const std::vector<std::string>& charts);

}  // namespace apiclab::sweep
