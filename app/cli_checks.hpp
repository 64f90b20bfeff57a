// Option values and combinations, checked before a scene is loaded or a run starts. The rule
// (docs/cli.md): an option that contradicts another or cannot do anything is an error
// (exit 2, one line naming the option); a scene that runs but is probably not what was meant
// (overlapping objects) is a warning on stderr.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "app/cli.hpp"

namespace apiclab::cli {

// Option values checked before CLI11 converts them, each refusal in the project's words
// ("--threads: expected a whole number from 1 to 4096, got 'abc'"), with no text in --help.
CLI::Validator whole_number(long long lo, long long hi);
CLI::Validator number_above(double lo);                        // > lo
CLI::Validator number_at_least(double lo, double hi = 1e300);  // in [lo, hi]
CLI::Validator one_of(const std::vector<std::string>& keys);
// Gives every numeric option of `app` and its subcommands the check of its kind (a whole
// number, a number), so that CLI11's "Could not convert" never reaches the user.
void check_option_kinds(CLI::App& app);

// The candidate nearest to `word` by edit distance, if near enough to be a typo; else "".
std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

// A numeric option against its scene key's range in the parameter registry, with the message
// --set KEY=VALUE and the GUI give, naming the option where they name the file: "--t-end nan: key
// 'time.end': end time nan is outside the allowed range (0, inf)".
void check_numeric_option(const std::string& flag, std::string_view key, double value);

// Each numeric option of `o`, and --frames with --t-end.
void check_run_options(const RunOptions& o);

// --lambda: in range, at most 1/2 (sim/scene/parameters.hpp), and only with --integrator lambda or
// none (it then implies lambda); beside another integrator an error naming both options.
void check_lambda_option(const RunOptions& o);

// A lambda integrator whose steps may pass its stability limit Δx / (c |1 − 2λ|): a warning.
void warn_about_integrator(const SceneDesc& scene);

// --flip-alpha when none of the schemes that will run is FLIP: an error.
void check_flip_alpha(const RunOptions& o, const std::vector<Scheme>& schemes);

// --max-memory BYTES|auto|none as a solver.max_memory_gb value; empty for auto. BYTES takes
// an optional k, M, G, T suffix (powers of 1000) or Ki, Mi, Gi, Ti (powers of 1024).
std::optional<double> max_memory_gb(const std::string& text);

// The memory guard for `copies` simulations of the scene held at once (compare's panes; the
// GUI also keeps each pane's initial state): one line with the estimate, exit 2.
void check_memory_for(const SceneDesc& scene, Precision precision, int copies);

// Prints "apiclab: warning: ..." for each pair of objects that overlap
// (sim/geometry/object_overlap.hpp).
void warn_about_overlaps(const SceneDesc& scene);

// Prints one "apiclab: warning: ..." line when the scene runs PolyPIC with its G modes, which
// blow up where stressed material meets nearly empty grid nodes (impacts).
void warn_about_scheme(const SceneDesc& scene);

}  // namespace apiclab::cli
