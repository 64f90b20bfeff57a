#include "cli.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace apiclab::cli {

void add_run_options(CLI::App* cmd, RunOptions& o, bool scene_required) {
  auto* scene = cmd->add_option("scene", o.scene, "scene file, or the name of a shipped scene (e.g. rotating-disk)");
  if (scene_required) scene->required();
  cmd->add_option("--scheme", o.scheme, "transfer scheme: " + choice_keys(scheme_choices()));
  cmd->add_option("--flip-alpha", o.flip_alpha, "FLIP/PIC blend of eq 3 (1 = FLIP, 0 = PIC)");
  cmd->add_option("--kernel", o.kernel, "interpolation kernel: " + choice_keys(kernel_choices()));
  cmd->add_option("--integrator", o.integrator, "grid update: " + choice_keys(integrator_choices()));
  cmd->add_option("--lambda", o.lambda, "lambda of eqs 27-30 (overrides the integrator's)");
  cmd->add_option("--t-end", o.t_end, "end time (s)");
  cmd->add_option("--frames", o.frames, "number of frames (end time = frames / fps)");
  cmd->add_option("--fps", o.fps, "frames per second");
  cmd->add_option("--dt", o.dt, "fixed time step (s)");
  cmd->add_option("--csv", o.csv, "diagnostics CSV, one row per step");
  cmd->add_option("--dump", o.dump, "directory for particle state per frame (frame_0000.csv, ...)");
  cmd->add_option("--set", o.sets, "override a scene value by JSON path, e.g. --set materials.0.E=2000")->take_all();
  cmd->add_option("--threads", o.threads, "OpenMP threads (default: all cores)");
  cmd->add_option("--precision", o.precision, "scalar type: double|float");
  cmd->add_flag("--quiet", o.quiet, "no progress line");
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

SceneDesc load_scene_with_options(const RunOptions& o) {
  std::vector<std::string> sets;
  auto check = [](const auto& choices, const std::string& key, const char* what) {
    try {
      parse_choice(choices, key, what);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  };
  if (!o.scheme.empty()) { check(scheme_choices(), o.scheme, "scheme"); sets.push_back("solver.scheme=" + o.scheme); }
  if (!o.kernel.empty()) { check(kernel_choices(), o.kernel, "kernel"); sets.push_back("solver.kernel=" + o.kernel); }
  if (!o.integrator.empty()) {
    check(integrator_choices(), o.integrator, "integrator");
    sets.push_back("solver.integrator=" + o.integrator);
  }
  if (o.flip_alpha) sets.push_back("solver.flip_alpha=" + number(*o.flip_alpha));
  if (o.lambda) sets.push_back("solver.lambda=" + number(*o.lambda));
  if (o.fps) sets.push_back("time.fps=" + number(*o.fps));
  if (o.t_end) sets.push_back("time.end=" + number(*o.t_end));
  if (o.dt) sets.push_back("time.dt={\"rule\":\"fixed\",\"value\":" + number(*o.dt) + "}");
  if (o.frames && *o.frames < 1) throw UsageError("--frames must be at least 1");
  if (o.threads < 0) throw UsageError("--threads must be positive");
  precision_of(o);
  for (auto& s : o.sets) sets.push_back(s);
  SceneDesc scene = load_scene(resolve_scene_path(o.scene), sets);
  if (o.frames) scene.time.end = *o.frames / scene.time.fps;
  return scene;
}


void apply_threads(int threads) {
  if (threads > 0) omp_set_num_threads(threads);
}

void ensure_writable_dir(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw UsageError("cannot create output directory '" + dir + "'" + (ec ? ": " + ec.message() : ""));
  fs::path probe = fs::path(dir) / ".apiclab-write-test";
  {
    std::ofstream f(probe);
    if (!f) throw UsageError("output directory '" + dir + "' is not writable");
  }
  fs::remove(probe, ec);
}

void ensure_writable_file(const std::string& file) {
  namespace fs = std::filesystem;
  fs::path p(file);
  if (p.has_parent_path()) ensure_writable_dir(p.parent_path().string());
  if (fs::is_directory(p)) throw UsageError("output file '" + file + "' is a directory");
  std::ofstream f(file, std::ios::app);
  if (!f) throw UsageError("cannot write output file '" + file + "'");
}

Progress::Progress(std::string label, double total, bool quiet)
    : label_(std::move(label)), total_(total), quiet_(quiet), start_(now_seconds()) {}

void Progress::update(double done, const std::string& extra) {
  if (quiet_) return;
  double t = now_seconds();
  if (t - last_ < 0.25 && done < total_) return;
  last_ = t;
  double elapsed = t - start_, frac = total_ > 0 ? done / total_ : 1;
  double eta = frac > 0 ? elapsed * (1 - frac) / frac : 0;
  std::fprintf(stderr, "\r%s %5.1f%% %s elapsed %.1fs ETA %.1fs   ", label_.c_str(), 100 * frac, extra.c_str(), elapsed, eta);
  std::fflush(stderr);
}

void Progress::finish(const std::string& summary) {
  if (!quiet_) std::fprintf(stderr, "\r\033[K");
  std::fprintf(stderr, "%s\n", summary.c_str());
}

}  // namespace apiclab::cli
