#include "app/cli_checks.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <regex>

#include "sim/geometry/object_overlap.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"
#include "sim/scene/memory_estimate.hpp"
#include "sim/scene/message_text.hpp"
#include "sim/scene/parameters.hpp"

namespace apiclab::cli {

namespace {

std::string in_quotes(const std::string& text) { return "'" + message_text(text, 60) + "'"; }

// The whole text as a whole number; nullopt when it is not one (or out of long long's range).
std::optional<long long> whole_value(const std::string& text) {
  static const std::regex whole(R"([+-]?[0-9]+)");
  if (!std::regex_match(text, whole)) return std::nullopt;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), nullptr, 10);
  if (errno == ERANGE) return std::nullopt;
  return v;
}

// The whole text as a number (nan and inf included: the registry's ranges refuse them by name).
std::optional<double> number_value(const std::string& text) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (*end != '\0') return std::nullopt;
  return v;
}

// "" for any int, "of at least 1", "from 1 to 4096".
std::string range_text(long long lo, long long hi) {
  if (lo <= std::numeric_limits<int>::min() && hi >= std::numeric_limits<int>::max()) return "";
  if (hi >= std::numeric_limits<int>::max()) return " of at least " + std::to_string(lo);
  return " from " + std::to_string(lo) + " to " + std::to_string(hi);
}

}  // namespace

CLI::Validator whole_number(long long lo, long long hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        const auto v = whole_value(text);
        if (v && *v >= lo && *v <= hi) return "";
        return "expected a whole number" + range_text(lo, hi) + ", got " + in_quotes(text);
      },
      "");
}

CLI::Validator number_above(double lo) {
  return CLI::Validator(
      [lo](std::string& text) -> std::string {
        const auto v = number_value(text);
        if (v && *v > lo && std::isfinite(*v)) return "";
        return "expected a number above " + format_value(lo) + ", got " + in_quotes(text);
      },
      "");
}

CLI::Validator number_at_least(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        const auto v = number_value(text);
        if (v && *v >= lo && *v <= hi) return "";
        return "expected a number " +
               (hi < 1e300 ? "from " + format_value(lo) + " to " + format_value(hi)
                           : "of at least " + format_value(lo)) +
               ", got " + in_quotes(text);
      },
      "");
}

CLI::Validator one_of(const std::vector<std::string>& keys) {
  return CLI::Validator(
      [keys](std::string& text) -> std::string {
        std::string list;
        for (const std::string& k : keys) {
          if (k == text) return "";
          list += (list.empty() ? "" : ", ") + k;
        }
        const std::string near = nearest(text, keys);
        return "expected one of " + list + ", got " + in_quotes(text) +
               (near.empty() ? "" : " (did you mean '" + near + "'?)");
      },
      "");
}

void check_option_kinds(CLI::App& app) {
  for (CLI::Option* opt : app.get_options()) {
    // The type before any validator's description ("INT:..."): CLI11's name of the target type.
    const std::string type = opt->get_type_name().substr(0, opt->get_type_name().find(':'));
    if (type == "INT")
      opt->check(whole_number(std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
    else if (type == "UINT")
      opt->check(whole_number(0, std::numeric_limits<unsigned>::max()));
    else if (type == "FLOAT")
      opt->check(CLI::Validator(
          [](std::string& text) -> std::string {
            return number_value(text) ? "" : "expected a number, got " + in_quotes(text);
          },
          ""));
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    check_option_kinds(*sub);
}

std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const std::string& c : candidates) {
    // Levenshtein distance, one row at a time.
    std::vector<std::size_t> row(c.size() + 1);
    for (std::size_t j = 0; j <= c.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= c.size(); ++j) {
        const std::size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (word[i - 1] != c[j - 1])});
        diagonal = up;
      }
    }
    if (row[c.size()] < best_distance) {
      best_distance = row[c.size()];
      best = c;
    }
  }
  return best;
}

void check_numeric_option(const std::string& flag, std::string_view key, double value) {
  int index = 0;
  const NumericParameter* p = find_parameter(key, &index);
  if (!p) throw std::logic_error("no numeric parameter " + std::string(key));
  // The registry's message, as --set KEY=VALUE and the GUI give it, naming the flag for the file.
  if (auto e = parameter_error(*p, index, value, flag + " " + format_value(value)))
    throw UsageError(*e);
}

void check_run_options(const RunOptions& o) {
  if (o.flip_alpha) check_numeric_option("--flip-alpha", "solver.flip_alpha", *o.flip_alpha);
  if (o.lambda) check_lambda_option(o);
  if (o.t_end) check_numeric_option("--t-end", "time.end", *o.t_end);
  if (o.fps) check_numeric_option("--fps", "time.fps", *o.fps);
  if (o.dt) check_numeric_option("--dt", "time.dt.value", *o.dt);
  if (o.frames && o.t_end)
    throw UsageError("--frames and --t-end both set the end time (frames / fps); give one of them");
  if (o.frames && *o.frames < 1) throw UsageError("--frames must be at least 1");
  max_memory_gb(o.max_memory);
}

void check_lambda_option(const RunOptions& o) {
  const std::string given = "--lambda " + format_value(*o.lambda);
  // An unknown --integrator is left to its own check.
  if (o.integrator == "symplectic" || o.integrator == "midpoint" || o.integrator == "backward") {
    const std::string what = o.integrator == "backward"   ? "is not of the lambda family"
                             : o.integrator == "midpoint" ? "is lambda = 1/2"
                                                          : "is lambda = 0";
    throw UsageError(given + " and --integrator " + o.integrator +
                     ": --lambda runs the lambda integrator (eqs 27-30) and --integrator " +
                     o.integrator + " " + what + " (give one of them, or --integrator lambda)");
  }
  check_numeric_option("--lambda", "solver.lambda", *o.lambda);
}

void check_flip_alpha(const RunOptions& o, const std::vector<Scheme>& schemes) {
  if (!o.flip_alpha) return;
  std::string names;
  for (Scheme s : schemes) {
    if (blends_flip(s)) return;  // flip, asflip
    names += (names.empty() ? "" : ", ") + std::string(key_of(s));
  }
  throw UsageError(
      "--flip-alpha has no effect: it blends FLIP with PIC (flip, asflip), and the "
      "scheme is " +
      names + " (add --scheme flip, or leave --flip-alpha out)");
}

std::optional<double> max_memory_gb(const std::string& text) {
  if (text.empty() || text == "auto") return std::nullopt;
  if (text == "none") return 1e300;  // no cap: larger than any estimate
  static const std::regex bytes(R"(([0-9]*\.?[0-9]+([eE][+-]?[0-9]+)?)\s*([kKMGT]i?)?[bB]?)");
  std::smatch m;
  if (!std::regex_match(text, m, bytes))
    throw UsageError("--max-memory '" + text +
                     "': expected BYTES (e.g. 8G, 512M, 2.5e9), auto (the available memory) or "
                     "none");
  double v = std::stod(m[1].str());
  const std::string unit = m[3].str();
  if (!unit.empty()) {
    const double base = unit.size() == 2 ? 1024.0 : 1000.0;
    const int power = std::string("kMGT").find(char(unit[0] == 'K' ? 'k' : unit[0])) + 1;
    v *= std::pow(base, power);
  }
  if (!(v > 0) || !std::isfinite(v))
    throw UsageError("--max-memory '" + text + "': must be a positive number of bytes");
  return v / 1e9;
}

void check_memory_for(const SceneDesc& scene, Precision precision, int copies) {
  MemoryEstimate e = estimate_memory(scene, precision);
  e.grid_nodes *= copies;
  e.particles *= copies;
  check_memory(e, memory_cap_bytes(scene),
               scene.source + " (" + std::to_string(copies) + " simulations at once)");
}

void warn_about_overlaps(const SceneDesc& scene) {
  for (const std::string& w : object_overlaps(scene))
    std::fprintf(stderr, "apiclab: warning: %s: %s\n", scene.source.c_str(), w.c_str());
}

// Eqs 27-30 on an oscillator of frequency ω (s = (ω Δt)²) are a map of determinant 1 and trace
// (2 − s (1 − 2λ + 2λ²)) / (1 + s λ(1 − λ)), stable while the trace is at least −2, i.e. while
// ω Δt |1 − 2λ| ≤ 2: every step at λ = ½ alone; λ = 0 and λ = 1 (explicit, not backward Euler)
// only up to the explicit limit. The bound warned at is that limit at the elastic rule's
// default ν = ½, Δx / 2c, over |1 − 2λ|: on rotating-disk no member blew up below it, and
// λ = 0.25, 0 and 1 blew up at 1.7, 2 and 4 times it (the λ < ½ members sooner than the
// oscillator says). The scene's longest step is bounded by the fixed value, else by the cap
// (time.dt.value), the frame interval and, for the elastic rule, ν Δx / c.
void warn_about_integrator(const SceneDesc& scene) {
  if (scene.solver.method != "mpm" || scene.solver.integrator != Integrator::lambda_family) return;
  const double lambda = scene.solver.integrator_lambda();
  double c = 0;
  for (const MaterialDesc& m : scene.materials) c = std::max(c, m.wave_speed());
  const double dx = scene.domain.dx, limit = dx / (2 * c * std::abs(1 - 2 * lambda));
  const TimeDesc& t = scene.time;
  double longest = t.dt;
  if (t.rule != DtRule::fixed) {
    longest = std::min(longest, 1 / t.fps);
    if (t.rule == DtRule::elastic) longest = std::min(longest, t.nu * dx / c);
  }
  if (!(longest > limit)) return;
  std::fprintf(stderr,
               "apiclab: warning: %s: lambda %g is stable only for steps up to dx / (2 c |1 - 2 "
               "lambda|) = %.3g s (eqs 27-30 keep every step stable at lambda = 1/2 alone; lambda "
               "above 1/2 is no backward Euler, lambda = 1 is explicit), and this scene's steps "
               "may reach %.3g s\n",
               scene.source.c_str(), lambda, limit, longest);
}

void warn_about_scheme(const SceneDesc& scene) {
  if (scene.solver.scheme != Scheme::polypic) return;
  const int kept = polypic::kept_modes(scene.solver.polypic_modes, scene.dim);
  if (!polypic::keeps_g_modes(kept, scene.dim)) return;
  std::fprintf(stderr,
               "apiclab: warning: %s: polypic with %d modes keeps the G modes, which blow up "
               "where stressed material meets nearly empty grid nodes (impacts, contact); "
               "impacts run with solver.polypic_modes=%d or fewer (docs/transfer-schemes.md)\n",
               scene.source.c_str(), kept, 1 << scene.dim);
}

}  // namespace apiclab::cli
