#include "cli.hpp"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "app/cli_checks.hpp"
#include "app/set_conflicts.hpp"
#include "sim/method_registry.hpp"
#include "sim/scene/choice_parameters.hpp"
#include "sim/scene/input_file.hpp"
#include "sim/scene/layout_parameters.hpp"
#include "sim/scene/memory_estimate.hpp"
#include "sim/scene/message_text.hpp"
#include "sim/scene/parameters.hpp"
#include "sim/scene/scene_method.hpp"

namespace apiclab::cli {

namespace {

// "--flip-alpha": the registry's label and help, unit, range and default (the scene's value
// when the scene gives one).
template <class T>
CLI::Option* add_parameter_option(CLI::App* cmd, const std::string& flag, T& target,
                                  std::string_view key, const std::string& note = "") {
  const NumericParameter* p = find_parameter(key);
  if (!p) throw std::logic_error("no numeric parameter " + std::string(key));
  return cmd->add_option(
      flag, target,
      std::string(p->label) + note + " (--set " + std::string(key) + "): " + p->describe());
}

template <class E>
std::string choice_help(const char* what, const std::vector<Choice<E>>& choices) {
  return std::string(what) + ": " + choice_keys(choices) +
         " [default: the scene's; solver.method mpm only]";
}

// Each scheme's help (registry.hpp: source and equations), so --help names what a key runs.
std::string scheme_table() {
  std::string out = "Transfer schemes (the values of solver.scheme):\n";
  for (const auto& c : scheme_choices())
    out += "  " + std::string(c.key) + "  " + std::string(c.help) + "\n";
  return out + "\n";
}

std::string parameter_table() {
  std::string out = "Numeric scene keys (--set KEY=VALUE; * is a material index or an axis):\n";
  for (const auto& p : numeric_parameters())
    out += "  " + std::string(p.key) + "  " + std::string(p.label) + ": " + p.describe() + "\n";
  return out;
}

// "eol eulerian" -> "eol or eulerian".
std::string method_list(std::string_view methods) {
  std::string out(methods);
  for (std::size_t at = out.find(' '); at != std::string::npos; at = out.find(' ', at + 4))
    out.replace(at, 1, " or ");
  return out;
}

std::string choice_table() {
  std::string out = "\nWord and switch scene keys (--set KEY=WORD; * is an index):\n";
  for (const ChoiceParameter& c : choice_parameters()) {
    std::string words;
    for (const ChoiceOption& o : c.options) words += (words.empty() ? "" : ", ") + o.key;
    out += "  " + std::string(c.key) + "  " + std::string(c.what) + ": " + words +
           " [default: " + (c.default_key.empty() ? "required" : c.default_key) +
           (c.method.empty() ? "" : "; solver.method " + method_list(c.method)) + "]\n";
  }
  return out;
}

std::string layout_table() {
  std::string out = "\nLayout scene keys (--set KEY=VALUE; * is an object or collider index):\n";
  for (const LayoutParameter& l : layout_parameters())
    out += "  " + std::string(l.key) + "  " + std::string(l.label) + ": " + l.describe() + "\n";
  return out;
}

}  // namespace

void add_run_options(CLI::App* cmd, RunOptions& o, RunOptionSet which) {
  auto* scene = cmd->add_option("scene", o.scene,
                                "scene file, or the name of a shipped scene (apiclab list shows "
                                "them)");
  if (which.scene_required) scene->required();
  cmd->add_option("--scheme", o.scheme, choice_help("transfer scheme", scheme_choices()));
  add_parameter_option(cmd, "--flip-alpha", o.flip_alpha, "solver.flip_alpha",
                       ", FLIP and ASFLIP (mpm)");
  cmd->add_option("--kernel", o.kernel, choice_help("interpolation kernel", kernel_choices()));
  cmd->add_option("--integrator", o.integrator, choice_help("grid update", integrator_choices()));
  add_parameter_option(cmd, "--lambda", o.lambda, "solver.lambda",
                       ", runs --integrator lambda (the one integrator that reads it)");
  add_parameter_option(cmd, "--t-end", o.t_end, "time.end");
  if (which.frames)
    cmd->add_option("--frames", o.frames,
                    "number of frames (end time = frames / fps; not with --t-end) [allowed: "
                    "integer >= 1; default: the scene's time.end]")
        ->check(whole_number(1, std::numeric_limits<int>::max()));
  add_parameter_option(cmd, "--fps", o.fps, "time.fps");
  add_parameter_option(cmd, "--dt", o.dt, "time.dt.value", ", with the fixed rule");
  if (which.outputs) {
    cmd->add_option("--csv", o.csv,
                    "diagnostics CSV, one row per step [default: apiclab-out/SCENE-SCHEME.csv]");
    cmd->add_option("--dump", o.dump,
                    "directory for particle state per frame (frame_0000.csv, ...) [default: none]");
    cmd->add_option("--dump-format", o.dump_format,
                    "formats of --dump, several allowed: csv (the contract), vtk (.vtp + "
                    "series.pvd for ParaView, zlib-compressed; vtk-raw uncompressed), ply (binary, "
                    "Houdini/Blender), obj (vertices) "
                    "[default: csv; vtk for eol and eulerian, which have no particles]");
    cmd->add_flag("--overwrite", o.overwrite,
                  "replace outputs that another run or no apiclab run wrote (without it they are "
                  "refused; a run's own earlier outputs are always replaced) [default: off]");
  }
  cmd->add_option(
         "--set", o.sets,
         "override a scene value by JSON path, e.g. --set materials.0.E=2000; the value is JSON "
         "(a bare word is a string); numeric keys are checked against their allowed range "
         "(listed below)")
      ->take_all();
  cmd->add_option("--threads", o.threads, "OpenMP threads [allowed: 1-4096; default: all cores]")
      ->check(whole_number(1, 4096));
  cmd->add_option("--precision", o.precision,
                  "scalar type: " + choice_keys(precision_choices()) + " [default: double]");
  cmd->add_option("--max-memory", o.max_memory,
                  "refuse a scene whose estimated memory exceeds this: BYTES (e.g. 8G, 512M), "
                  "auto or none [default: the scene's solver.max_memory_gb, else auto = the "
                  "available memory]");
  cmd->add_option("--max-steps", o.max_steps,
                  "refuse a run whose time-step rule must take more steps than this, or whose "
                  "first steps predict more; a run that passes it stops [allowed: > 0; default: "
                  "1e8]")
      ->check(number_above(0));
  cmd->add_option("--max-frames", o.max_frames,
                  "refuse a run of more frames than this (time.end x fps) [allowed: > 0; "
                  "default: 1e6]")
      ->check(number_above(0));
  if (which.quiet) cmd->add_flag("--quiet", o.quiet, "no progress line [default: off]");
  cmd->footer(scheme_table() + parameter_table() + choice_table() + layout_table());
}

std::vector<DumpFormat> dump_formats_of(const RunOptions& o, bool particles) {
  if (o.dump.empty() && !o.dump_format.empty())
    throw UsageError("--dump-format " + o.dump_format + " needs --dump DIR");
  try {
    return parse_dump_formats(o.dump_format.empty() ? (particles ? "csv" : "vtk") : o.dump_format);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--dump-format: ") + e.what());
  }
}

Precision precision_of(const RunOptions& o) {
  try {
    return parse_choice(precision_choices(), o.precision, "precision");
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

static std::string number(double d) {
  std::ostringstream s;
  s.precision(17);
  s << d;
  return s.str();
}

std::vector<std::string> option_overrides(const RunOptions& o) {
  check_run_options(o);
  std::vector<Assignment> given;  // options first, then the --sets, in the order applied
  auto add = [&](const std::string& option, const std::string& shown, const std::string& text) {
    given.push_back({option + " " + shown, text});
  };
  auto check = [](const auto& choices, const std::string& key, const char* what) {
    try {
      parse_choice(choices, key, what);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  };
  if (!o.scheme.empty()) {
    if (find_method(o.scheme))
      throw UsageError("--scheme " + o.scheme + ": " + o.scheme +
                       " is a solver method, not an MPM transfer scheme; a scene chooses it with "
                       "solver.method, the command line with --set solver.method=" +
                       o.scheme + " (--scheme takes " + choice_keys(scheme_choices()) + ")");
    check(scheme_choices(), o.scheme, "scheme");
    add("--scheme", o.scheme, "solver.scheme=" + o.scheme);
  }
  if (!o.kernel.empty()) {
    check(kernel_choices(), o.kernel, "kernel");
    add("--kernel", o.kernel, "solver.kernel=" + o.kernel);
  }
  if (!o.integrator.empty()) {
    check(integrator_choices(), o.integrator, "integrator");
    add("--integrator", o.integrator, "solver.integrator=" + o.integrator);
  }
  auto add_number = [&](const std::string& option, const std::string& key, double v) {
    add(option, format_value(v), key + "=" + number(v));
  };
  if (o.flip_alpha) add_number("--flip-alpha", "solver.flip_alpha", *o.flip_alpha);
  if (o.lambda) {  // check_run_options refused it beside another integrator
    if (o.integrator.empty()) add("--lambda", format_value(*o.lambda), "solver.integrator=lambda");
    add_number("--lambda", "solver.lambda", *o.lambda);
  }
  if (o.fps) add_number("--fps", "time.fps", *o.fps);
  if (o.t_end) add_number("--t-end", "time.end", *o.t_end);
  if (o.frames)  // applied once the scene's fps is known (load_scene_with_options)
    given.push_back({"--frames " + std::to_string(*o.frames), "time.end=0", true});
  if (o.dt)
    add("--dt", format_value(*o.dt),
        "time.dt={\"rule\":\"fixed\",\"value\":" + number(*o.dt) + "}");
  if (auto gb = max_memory_gb(o.max_memory))
    add("--max-memory", o.max_memory, "solver.max_memory_gb=" + number(*gb));
  precision_of(o);
  for (const std::string& s : o.sets) given.push_back({"--set " + s, s});
  check_assignments(given);
  std::vector<std::string> sets;
  for (const Assignment& a : given)
    if (!a.any_other_disagrees) sets.push_back(a.text);
  return sets;
}

// --scheme, --kernel or --integrator that cannot run with the rest of the scene's solver (mls
// with an implicit integrator): an error naming the option and the fix, not the file's key.
static void check_scheme_options(const RunOptions& o, const SceneMethod& m) {
  if (o.scheme.empty() && o.kernel.empty() && o.integrator.empty()) return;
  SolverDesc v = SceneDesc().solver;  // the registry's defaults
  try {
    if (!m.scheme.empty()) v.scheme = parse_choice(scheme_choices(), m.scheme, "scheme");
    if (!m.kernel.empty()) v.kernel = parse_choice(kernel_choices(), m.kernel, "kernel");
    if (!m.integrator.empty())
      v.integrator = parse_choice(integrator_choices(), m.integrator, "integrator");
  } catch (const std::invalid_argument&) {
    return;  // the scene's own choice is wrong: its load names the key
  }
  const std::string why = scheme_conflict(v);
  if (why.empty()) return;
  std::string given;
  for (const auto& [flag, value] :
       {std::pair<const char*, const std::string&>{"--scheme", o.scheme},
        {"--kernel", o.kernel},
        {"--integrator", o.integrator}})
    if (!value.empty()) given += (given.empty() ? "" : " ") + std::string(flag) + " " + value;
  throw UsageError(given + " on " + message_text(o.scene) + ": " + why);
}

// The MPM options on a scene of another method: an error naming the method, not the file's key.
static void check_method_options(const RunOptions& o, const SceneMethod& m) {
  if (m.method.empty()) return;  // the scene does not load: its load says why
  if (m.method != "mpm") {
    std::string given;
    if (!o.scheme.empty())
      given = "--scheme " + o.scheme;
    else if (!o.kernel.empty())
      given = "--kernel " + o.kernel;
    else if (!o.integrator.empty())
      given = "--integrator " + o.integrator;
    else if (o.flip_alpha)
      given = "--flip-alpha " + format_value(*o.flip_alpha);
    else if (o.lambda)
      given = "--lambda " + format_value(*o.lambda);
    if (!given.empty())
      throw UsageError(given + ": " + message_text(o.scene) + " runs solver.method " + m.method +
                       ", and --scheme, --kernel, --integrator, --flip-alpha and --lambda choose "
                       "how MPM runs (solver.method mpm); leave it out, or run the scene with "
                       "MPM: --set solver.method=mpm");
    return;
  }
  check_scheme_options(o, m);
}

// A method switched by --set, once the scene loaded: the file's keys of its method left out.
static void note_method_switch(const RunOptions& o, const SceneMethod& m) {
  if (m.method.empty() || m.file_method == m.method || m.file_keys.empty() || o.quiet) return;
  std::string keys;
  for (const std::string& k : m.file_keys) keys += (keys.empty() ? "" : ", ") + k;
  std::fprintf(stderr,
               "apiclab: note: %s: --set solver.method=%s: of the scene's %s keys (solver: %s), "
               "those %s does not read are left out\n",
               message_text(o.scene).c_str(), m.method.c_str(), m.file_method.c_str(),
               message_text(keys).c_str(), m.method.c_str());
}

SceneDesc load_scene_with_options(const RunOptions& o) {
  const std::vector<std::string> sets = option_overrides(o);
  const std::string path = resolve_scene_path(o.scene);
  std::error_code ec;
  if (!o.scene.empty() && o.scene.find('/') == std::string::npos &&
      !std::filesystem::exists(path, ec) && ec != std::errc::filename_too_long)
    throw UsageError(
        "'" + message_text(o.scene) +
        "': no such scene file or shipped scene (apiclab list shows the shipped ones)");
  const SceneMethod method = scene_method(path, sets);
  check_method_options(o, method);
  SceneDesc scene = load_scene(path, sets);
  note_method_switch(o, method);
  scene.asset_dirs.push_back(assets_directory());
  if (scene.solver.method != "mpm" && precision_of(o) == Precision::single)
    std::fprintf(stderr,
                 "apiclab: warning: %s: --precision float: the %s solver runs in double "
                 "precision only; this run is double\n",
                 scene.source.c_str(), scene.solver.method.c_str());
  if (o.frames) {
    const double end = *o.frames / scene.time.fps;
    if (end > scene.time.end * (1 + 1e-9) && !o.quiet)
      std::fprintf(stderr,
                   "apiclab: note: --frames %d runs to t = %g s, past the scene's end "
                   "(time.end = %g s)\n",
                   *o.frames, end, scene.time.end);
    apply_parameter(scene, "time.end", end);
  }
  check_run_length(scene, o.max_steps, o.max_frames);  // before anything is sampled or written
  check_memory(scene, precision_of(o));                // before the overlap check samples anything
  warn_about_overlaps(scene);
  warn_about_scheme(scene);
  warn_about_integrator(scene);
  return scene;
}

void apply_threads(int threads) {
  if (threads > 0) omp_set_num_threads(threads);
}

void ensure_writable_dir(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir, ec))
    throw UsageError("cannot create output directory '" + message_text(dir) + "'" +
                     (ec ? ": " + path_error_text(ec, dir) : ""));
  fs::path probe = fs::path(dir) / ".apiclab-write-test";
  {
    std::ofstream f(probe);
    if (!f) throw UsageError("output directory '" + message_text(dir) + "' is not writable");
  }
  fs::remove(probe, ec);
}

void ensure_writable_file(const std::string& file) {
  namespace fs = std::filesystem;
  fs::path p(file);
  std::error_code ec;
  const fs::file_status st = fs::status(p, ec);
  if (ec == std::errc::filename_too_long)
    throw UsageError("cannot write output file '" + message_text(file) +
                     "': " + path_error_text(ec, file));
  ensure_writable_dir(p.has_parent_path() ? p.parent_path().string() : ".");
  if (fs::is_directory(st))
    throw UsageError("output file '" + message_text(file) + "' is a directory");
  if (fs::exists(st) && !std::ofstream(file, std::ios::app))
    throw UsageError("cannot write output file '" + message_text(file) + "'");
}

std::string format_duration(double seconds) {
  char text[64];
  // The bounds are where the rounded value would roll over into the next unit.
  if (!(seconds < 1e300)) return "unbounded";
  if (seconds < 59.95) {
    std::snprintf(text, sizeof text, "%.1fs", std::max(seconds, 0.0));
  } else if (seconds < 3599.5) {
    const long s = std::lround(seconds);
    std::snprintf(text, sizeof text, "%ldm%02lds", s / 60, s % 60);
  } else if (seconds < 48 * 3600 - 30) {
    const long m = std::lround(seconds / 60);
    std::snprintf(text, sizeof text, "%ldh%02ldm", m / 60, m % 60);
  } else if (seconds < 365.25 * 86400) {
    std::snprintf(text, sizeof text, "%.1f days", seconds / 86400);
  } else {
    std::snprintf(text, sizeof text, "%.3g years", seconds / (365.25 * 86400));
  }
  return text;
}

Progress::Progress(std::string label, double total, bool quiet)
    : label_(std::move(label)),
      total_(total),
      quiet_(quiet),
      terminal_(isatty(fileno(stderr))),
      start_(now_seconds()) {}

void Progress::update(double done, const std::string& extra) {
  if (quiet_) return;
  double t = now_seconds();
  // A terminal gets one line rewritten in place; a log file or pipe gets plain lines, fewer.
  if (t - last_ < (terminal_ ? 0.25 : 2.0) && done < total_) return;
  last_ = t;
  // A fixed step may end past the total (the step at or just past time.end): 100 % at most.
  double elapsed = t - start_, frac = total_ > 0 ? std::min(done / total_, 1.0) : 1;
  double eta = frac > 0 ? elapsed * (1 - frac) / frac : 0;
  std::fprintf(
      stderr,
      terminal_ ? "\r%s %5.1f%% %s elapsed %s ETA %s   " : "%s %5.1f%% %s elapsed %s ETA %s\n",
      label_.c_str(), 100 * frac, extra.c_str(), format_duration(elapsed).c_str(),
      frac > 0 ? format_duration(eta).c_str() : "unknown");
  std::fflush(stderr);
}

void Progress::finish(const std::string& summary) {
  if (!quiet_ && terminal_) std::fprintf(stderr, "\r\033[K");
  std::fprintf(stderr, "%s\n", summary.c_str());
}

}  // namespace apiclab::cli
