// `apiclab bench`: explicit-step throughput on a standard elastic block (one size, or a table of
// sizes), optionally against the readable reference step on the same state, or the throughput
// of a real scene over a few frames.
#include <omp.h>
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "app/cli_checks.hpp"
#include "app/frame_loop.hpp"
#include "app/perf_ledger.hpp"
#include "cli.hpp"
#include "commands.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"
#include "sim/scene/memory_estimate.hpp"

namespace apiclab::cli {
namespace {

struct BenchOptions {
  int dim = 2;
  long particles = 0;  // default: 262144 (2D), 110592 (3D)
  int steps = 0;       // default: 200 (2D), 50 (3D); with --sizes, the same work per size
  std::optional<std::string> precision;  // default: float (block), double (--scene)
  std::string scheme = "apic", kernel = "quadratic", integrator = "symplectic";
  int threads = 0;
  std::string max_memory;
  std::vector<long> sizes;
  bool reference = false;
  bool ledger = false;  // the block's rows with the conservation ledger (solver.ledger)
  std::string scene;
  int frames = 3;
  double domain_times = 1;  // --scene: the domain grown to this × its area (2D) or volume (3D)
  int polypic_modes = 0;    // solver.polypic_modes of the block (0 = all)
  std::string record;       // --record: the performance ledger to append rows to
};

// A block of fixed-corotated material, spinning and falling, filling a quarter of the domain
// along each axis at 4 (2D) or 8 (3D) particles per cell.
std::string bench_scene(const BenchOptions& o, long particles, double& dx) {
  using json = nlohmann::json;
  const int ppc = o.dim == 2 ? 4 : 8;
  double cells_in_block = double(particles) / ppc;
  double side_cells = std::pow(cells_in_block, 1.0 / o.dim);
  dx = 0.5 / side_cells;
  const bool d2 = o.dim == 2;
  const json lo = d2 ? json{0.25, 0.25} : json{0.25, 0.25, 0.25};
  const json hi = d2 ? json{0.75, 0.75} : json{0.75, 0.75, 0.75};
  const json zero = d2 ? json{0, 0} : json{0, 0, 0};
  const json ones = d2 ? json{1, 1} : json{1, 1, 1};
  const json omega = d2 ? json(1.0) : json{0, 0, 1.0};
  const json scene = {
      {"name", "bench-block"},
      {"dim", o.dim},
      {"domain", {{"min", zero}, {"max", ones}, {"dx", dx}, {"boundary", "sticky"}}},
      {"gravity", d2 ? json{0, -9.8} : json{0, -9.8, 0}},
      {"time", {{"end", 1}, {"fps", 24}, {"dt", {{"rule", "fixed"}, {"value", 0.3 * dx / 3.7}}}}},
      {"solver",
       {{"scheme", o.scheme},
        {"kernel", o.kernel},
        {"integrator", o.integrator},
        {"polypic_modes", o.polypic_modes}}},
      {"materials", json::array({{{"name", "jelly"},
                                  {"model", "fixed-corotated"},
                                  {"E", 10000},
                                  {"nu", 0.3},
                                  {"rho", 1000}}})},
      {"objects", json::array({{{"shape", {{"type", "box"}, {"min", lo}, {"max", hi}}},
                                {"material", 0},
                                {"sampling", {{"type", "ppc"}, {"ppc", ppc}}},
                                {"velocity", zero},
                                {"angular_velocity", omega}}})},
  };
  return scene.dump();
}

bool finite_state(const Simulation& sim) {
  const DiagnosticsRow end = sim.measure();
  return std::isfinite(end.total + end.kinetic);
}

// The readable reference step (sim/reference/reference_step.hpp) from sim's current particles,
// `steps` fixed steps of dt in the same precision; particle-steps/s, or nullopt if it blew up.
std::optional<double> reference_rate(const Simulation& sim, double dt, int steps) {
  const std::unique_ptr<ReferenceRun> run = sim.transfers()->reference_run();
  const double start = now_seconds();
  for (int s = 0; s < steps; ++s) run->step(dt);
  const double wall = now_seconds() - start;
  if (!run->finite()) return std::nullopt;
  return double(run->particle_count()) * steps / wall;
}

struct BlockResult {
  std::size_t particles = 0;
  int steps = 0;
  double dx = 0, wall = 0, rate = 0;
  // The diagnostics row as step() pays for it, as a share of a step: the CPU time of a step with
  // its row (Simulation::step_fixed_measured) over that of the same step without, less 1, the
  // median over pairs (row_cost); and in seconds per row at the timed step's wall time.
  double row_share = 0, measure_wall = 0;
  std::optional<double> reference;  // particle-steps/s of the reference step (--reference)
};

// Process CPU time on one thread; wall time on more, where the CPU time would count OpenMP's
// threads spinning at their barriers (measured: shares of −26 % to +51 % on 2 threads).
double row_clock_seconds() {
  timespec t{};
  clock_gettime(omp_get_max_threads() > 1 ? CLOCK_MONOTONIC : CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// The diagnostics row step() computes after each step (energies, momenta; MPM sums the
// particles' share inside G2P), as a share of a step: `rounds` times from `warm`, `steps` steps
// of one copy without rows and of another with them, alternating step by step, each timed in
// process CPU time (time the machine gives other processes falls out); the median over the
// pairs of (with / without − 1), so that a step that met a context switch or another process's
// cache traffic does not count. `sink` collects the rows' totals (the caller checks them).
double row_cost(const Simulation& warm, double dt, int steps, int rounds, double& sink) {
  std::vector<double> ratios;
  ratios.reserve(std::size_t(steps) * std::size_t(rounds));
  for (int k = 0; k < rounds; ++k) {
    auto plain = warm.clone(), rows = warm.clone();
    for (int s = 0; s < steps; ++s) {
      const double start = row_clock_seconds();
      plain->step_fixed(dt);
      const double middle = row_clock_seconds();
      sink += rows->step_fixed_measured(dt).total;
      ratios.push_back((row_clock_seconds() - middle) / std::max(middle - start, 1e-9) - 1);
    }
  }
  const auto mid = ratios.begin() + std::ptrdiff_t(ratios.size() / 2);
  std::nth_element(ratios.begin(), mid, ratios.end());
  return *mid;
}

// Times `steps` steps of the block at about `particles` particles after 3 warm-up steps (the
// first sort, page faults), `repeats` times from the same warmed-up state (small sizes: enough
// work to time, in the same stage of the motion as the large ones); then the diagnostics row's
// cost (row_cost); with --reference, then the reference step from that state. Returns nullopt,
// having said why, if the block blew up.
std::optional<BlockResult> time_block(const BenchOptions& o, Precision precision, long particles,
                                      int steps, int repeats = 1) {
  BlockResult r;
  std::vector<std::string> sets;
  if (auto gb = max_memory_gb(o.max_memory))
    sets.push_back("solver.max_memory_gb=" + std::to_string(*gb));
  if (o.ledger) sets.push_back("solver.ledger=true");
  SceneDesc scene = parse_scene_text(bench_scene(o, particles, r.dx), "bench scene", sets);
  auto warm = make_simulation(scene, precision);
  const double dt = scene.time.dt;
  for (int s = 0; s < 3; ++s) warm->step_fixed(dt);
  std::unique_ptr<Simulation> sim;
  for (int k = 0; k < repeats; ++k) {
    sim = warm->clone();
    const double start = now_seconds();
    for (int s = 0; s < steps; ++s) sim->step_fixed(dt);
    r.wall += now_seconds() - start;
  }
  r.particles = particle_count(*sim);
  r.steps = steps * repeats;
  r.rate = double(r.particles) * r.steps / r.wall;
  double sink = 0;
  r.row_share = row_cost(*warm, dt, std::max(1, (steps + 1) / 2), repeats, sink);
  r.measure_wall = r.row_share * r.wall / r.steps;
  bool finite = std::isfinite(sink) && finite_state(*sim);
  if (finite && o.reference) {
    // Fewer steps (about 10⁶ particle-steps, a few seconds): the reference is slower, and its
    // rate does not depend on the step count.
    const long affordable = 1000000L / long(std::max<std::size_t>(r.particles, 1));
    r.reference = reference_rate(*warm, dt, int(std::max(2L, std::min(affordable, long(steps)))));
    finite = r.reference.has_value();
  }
  if (!finite) {
    std::fprintf(stderr,
                 "bench: the simulation blew up (non-finite state) within %d steps; try another "
                 "kernel or fewer steps\n",
                 steps);
    return std::nullopt;
  }
  return r;
}

// The ledger row of one timing of the block (--record); the reference step's row beside it.
LedgerRow block_row(const BenchOptions& o, const BlockResult& r, const std::string& note) {
  LedgerRow row;
  row.dim = o.dim;
  row.precision = *o.precision;
  row.threads = omp_get_max_threads();
  row.scheme = o.scheme;
  row.kernel = o.kernel;
  row.integrator = o.integrator;
  row.particles = long(r.particles);
  row.steps = r.steps;
  row.rate = r.rate;
  row.wall = r.wall;
  char share[64];
  std::snprintf(share, sizeof share, "diagnostics row %.1f %%", 100 * r.row_share);
  row.note = note + (note.empty() ? "" : "; ") + share;
  if (o.polypic_modes > 0) row.note += "; polypic modes " + std::to_string(o.polypic_modes);
  return row;
}
void add_block_rows(std::vector<LedgerRow>& rows, const BenchOptions& o, const BlockResult& r,
                    const std::string& note) {
  rows.push_back(block_row(o, r, note));
  if (!r.reference) return;
  LedgerRow ref = rows.back();
  ref.build = "reference";
  ref.rate = *r.reference;
  ref.wall.reset();
  ref.steps = 0;
  char speedup[64];
  std::snprintf(speedup, sizeof speedup, "this build %.2fx the reference", r.rate / *r.reference);
  ref.note = note + (note.empty() ? "" : "; ") + speedup;
  rows.push_back(ref);
}

Precision parse_precision(const std::string& key) {
  try {
    return parse_choice(precision_choices(), key, "precision");
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

// --sizes: one row per size. Each size steps through the same simulated time as the default
// run (fewer steps when smaller: Δt ∝ Δx), repeated from the warmed-up state until it has
// about the default run's particle-steps (at most 100 times); --steps fixes the step count.
int bench_sizes(const BenchOptions& o, Precision precision) {
  const double default_size = o.dim == 2 ? 262144 : 110592, default_steps = o.dim == 2 ? 200 : 50;
  std::printf("bench: %dD %s, scheme %s, kernel %s, integrator %s, %d threads\n", o.dim,
              o.precision->c_str(), o.scheme.c_str(), o.kernel.c_str(), o.integrator.c_str(),
              omp_get_max_threads());
  std::printf("%10s %6s %10s %7s %18s", "particles", "steps", "ms/step", "diag",
              "particle-steps/s");
  if (o.reference) std::printf(" %18s %9s", "reference", "speed-up");
  std::printf("\n");
  double lo = 1e300, hi = 0;
  std::vector<BlockResult> results;
  for (long size : o.sizes) {
    const double scaled = default_steps * std::pow(double(size) / default_size, 1.0 / o.dim);
    const int steps = o.steps > 0 ? o.steps : int(std::clamp(std::lround(scaled), 5L, 200L));
    const double work = default_size * default_steps;
    const int repeats = int(std::clamp(std::lround(work / (double(size) * steps)), 1L, 100L));
    const auto r = time_block(o, precision, size, steps, repeats);
    if (!r) return 2;
    const double step_wall = r->wall / r->steps;
    std::printf("%10zu %6d %10.3f %6.1f%% %18.0f", r->particles, r->steps, 1e3 * step_wall,
                100 * r->row_share, r->rate);
    if (r->reference) std::printf(" %18.0f %8.2fx", *r->reference, r->rate / *r->reference);
    std::printf("\n");
    std::fflush(stdout);
    lo = std::min(lo, r->rate);
    hi = std::max(hi, r->rate);
    results.push_back(*r);
  }
  std::printf("flatness: slowest / fastest size = %.2f\n", lo / hi);
  if (!o.record.empty()) {
    char note[64];
    std::snprintf(note, sizeof note, "sizes run flatness %.2f", lo / hi);
    std::vector<LedgerRow> rows;
    for (const auto& r : results) add_block_rows(rows, o, r, note);
    append_ledger_rows(o.record, rows);
  }
  return 0;
}

// Bytes the MPM grid's node arrays hold (0 for a family without one).
std::size_t grid_bytes(const Simulation& sim) {
  const TransferControls* t = sim.transfers();
  return t ? t->grid_bytes() : 0;
}

// --domain-times N: the domain grown away from its minimum corner (walls there stay put) to N ×
// its area or volume; the grid stores only the box the particles reach, so memory and time
// should stay those of the tight domain.
void grow_domain(SceneDesc& scene, double times) {
  for (int a = 0; a < scene.dim; ++a)
    if (scene.domain.periodic(a))
      throw UsageError("--domain-times: " + scene.source +
                       " has a periodic axis, whose length is part of the physics");
  const double per_axis = std::pow(times, 1.0 / scene.dim);
  for (int a = 0; a < scene.dim; ++a)
    scene.domain.max[a] =
        scene.domain.min[a] + per_axis * (scene.domain.max[a] - scene.domain.min[a]);
}

// The ledger row of a --scene timing (--record): the scene's name and solver, its wall time and
// rates, and in the note the frames timed and the peak RSS.
LedgerRow scene_row(const BenchOptions& o, const SceneDesc& scene, const Simulation& sim,
                    double wall, bool partial) {
  LedgerRow row;
  row.method = scene.solver.method;
  row.scene = scene.name;
  row.dim = scene.dim;
  row.precision = o.precision.value_or("double");
  row.threads = omp_get_max_threads();
  if (row.method == "mpm") {
    row.scheme = key_of(scene.solver.scheme);
    row.kernel = key_of(scene.solver.kernel);
    row.integrator = key_of(scene.solver.integrator);
  }
  row.particles = long(particle_count(sim));
  row.steps = sim.steps();
  if (row.particles > 0) row.rate = double(row.particles) * double(sim.steps()) / wall;
  row.wall = wall;
  row.sim_rate = sim.time() / wall;
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  row.note = (partial ? "frames " + std::to_string(o.frames) : std::string("to the end")) +
             "; peak RSS " + format_bytes(1024.0 * double(usage.ru_maxrss));
  char domain[64];
  std::snprintf(domain, sizeof domain, "; domain %gx", o.domain_times);
  if (o.domain_times != 1) row.note += domain;
  return row;
}

// --scene: the scene's own time-step rule and diagnostics (what `run` does), over a few frames.
int bench_scene_frames(const BenchOptions& o, const CLI::App& cmd) {
  RunOptions ro;
  ro.scene = o.scene;
  ro.precision = o.precision.value_or("double");
  if (cmd.count("--scheme")) ro.scheme = o.scheme;
  if (cmd.count("--kernel")) ro.kernel = o.kernel;
  if (cmd.count("--integrator")) ro.integrator = o.integrator;
  SceneDesc scene = load_scene_with_options(ro);
  if (o.domain_times != 1) {
    grow_domain(scene, o.domain_times);
    check_memory(scene, precision_of(ro));
  }
  auto sim = make_simulation(scene, precision_of(ro));
  const FrameTimes times(scene);
  const int frames = std::min(o.frames, times.frames);
  const double start = now_seconds();
  for (int f = 1; f <= frames; ++f)
    if (sim->advance_to(times.time_of(f))) break;
  const double wall = now_seconds() - start;
  if (const auto& failure = sim->failure()) {
    std::fprintf(stderr, "bench: %s\n", failure->message.c_str());
    return 2;
  }
  std::printf(
      "bench: scene %s, %dD %s, scheme %s, integrator %s, %zu particles, %d frames, %d "
      "threads\n",
      scene.name.c_str(), scene.dim, ro.precision.c_str(),
      std::string(key_of(scene.solver.scheme)).c_str(), integrator_label(scene.solver).c_str(),
      particle_count(*sim), frames, omp_get_max_threads());
  std::printf("wall: %.3f s for %ld steps to t = %.4g s, %.3f ms/step\n", wall, sim->steps(),
              sim->time(), 1e3 * wall / double(std::max(1L, sim->steps())));
  std::printf("simulated s per wall s: %.4g\n", sim->time() / wall);
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("domain: %g x the scene's; grid arrays: %s; peak RSS: %s\n", o.domain_times,
              format_bytes(double(grid_bytes(*sim))).c_str(),
              format_bytes(1024.0 * double(usage.ru_maxrss)).c_str());
  std::printf("particle-steps/s: %.0f\n",
              double(particle_count(*sim)) * double(sim->steps()) / wall);
  if (!o.record.empty())
    append_ledger_rows(o.record, {scene_row(o, scene, *sim, wall, frames < times.frames)});
  return 0;
}

int bench(BenchOptions o, const CLI::App& cmd) {
  if (o.dim != 2 && o.dim != 3) throw UsageError("--dim must be 2 or 3");
  if (o.frames < 1) throw UsageError("--frames must be at least 1");
  apply_threads(o.threads);
  if (!o.record.empty()) check_ledger(o.record);  // refuse before the minutes of timing
  if (!o.scene.empty()) {
    for (const char* flag : {"--dim", "--particles", "--steps", "--sizes", "--reference"})
      if (cmd.count(flag))
        throw UsageError(std::string(flag) +
                         " is for the bench block; --scene times the scene "
                         "as it is (use --frames)");
    return bench_scene_frames(o, cmd);
  }
  if (cmd.count("--frames")) throw UsageError("--frames goes with --scene");
  if (cmd.count("--domain-times")) throw UsageError("--domain-times goes with --scene");
  if (!o.precision) o.precision = "float";
  const Precision precision = parse_precision(*o.precision);
  if (o.reference && o.integrator != "symplectic")
    throw UsageError("--reference: the reference step is symplectic Euler only");
  for (long size : o.sizes)
    if (size < 16) throw UsageError("--sizes: every size must be at least 16 particles");
  if (!o.sizes.empty()) {
    if (cmd.count("--particles")) throw UsageError("give --particles or --sizes, not both");
    if (cmd.count("--steps") && o.steps < 1) throw UsageError("--steps must be at least 1");
    return bench_sizes(o, precision);
  }
  if (o.particles == 0) o.particles = o.dim == 2 ? 262144 : 110592;
  if (o.steps == 0) o.steps = o.dim == 2 ? 200 : 50;
  if (o.particles < 16 || o.steps < 1)
    throw UsageError("--particles must be at least 16 and --steps at least 1");
  const auto r = time_block(o, precision, o.particles, o.steps);
  if (!r) return 2;
  std::printf(
      "bench: %dD %s, scheme %s, kernel %s, integrator %s, %zu particles, dx %.4g, %d steps, %d "
      "threads\n",
      o.dim, o.precision->c_str(), o.scheme.c_str(), o.kernel.c_str(), o.integrator.c_str(),
      r->particles, r->dx, o.steps, omp_get_max_threads());
  std::printf("wall: %.3f s, %.3f ms/step\n", r->wall, 1e3 * r->wall / o.steps);
  std::printf("diagnostics row: %.3f ms, %.1f%% of a step (%s, steps with rows against without)\n",
              1e3 * r->measure_wall, 100 * r->row_share,
              omp_get_max_threads() > 1 ? "wall time" : "CPU time");
  if (r->reference)
    std::printf("reference step (same state and precision): %.0f particle-steps/s; speed-up %.2f\n",
                *r->reference, r->rate / *r->reference);
  std::printf("particle-steps/s: %.0f\n", r->rate);
  if (!o.record.empty()) {
    std::vector<LedgerRow> rows;
    add_block_rows(rows, o, *r, "");
    append_ledger_rows(o.record, rows);
  }
  return 0;
}

}  // namespace

void register_bench(CLI::App& root, CommandTable& table) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* cmd =
      root.add_subcommand("bench", "explicit-step throughput; last line 'particle-steps/s: N'");
  cmd->add_option("--dim", o->dim, "dimension [allowed: 2, 3; default: 2]")
      ->check(whole_number(2, 3));
  cmd->add_option("--particles", o->particles,
                  "particle count, approximate [allowed: 16 or more; default: 262144 (2D), "
                  "110592 (3D)]")
      ->check(whole_number(16, 2000000000));
  cmd->add_option("--steps", o->steps,
                  "timed steps [allowed: 1 or more; default: 200 (2D), 50 (3D); with --sizes, "
                  "the same work per size]")
      ->check(whole_number(1, 100000000));
  cmd->add_option("--precision", o->precision,
                  "float|double [default: float; double with --scene]");
  cmd->add_option("--threads", o->threads, "OpenMP threads [allowed: 1-4096; default: all cores]")
      ->check(whole_number(1, 4096));
  cmd->add_option("--scheme", o->scheme,
                  "transfer scheme: " + choice_keys(scheme_choices()) + " [default: apic]");
  cmd->add_option("--kernel", o->kernel,
                  "kernel: " + choice_keys(kernel_choices()) + " [default: quadratic]");
  cmd->add_option("--integrator", o->integrator,
                  "integrator: " + choice_keys(integrator_choices()) + " [default: symplectic]");
  cmd->add_option("--polypic-modes", o->polypic_modes,
                  "PolyPIC's modes kept per component (solver.polypic_modes) [allowed: 0-27; "
                  "default: 0 = all]")
      ->check(whole_number(0, 27));
  cmd->add_option("--max-memory", o->max_memory,
                  "refuse a block whose estimated memory exceeds this: BYTES (e.g. 8G), auto or "
                  "none [default: auto = the available memory]");
  cmd->add_option("--sizes", o->sizes,
                  "a table over particle counts, e.g. 3000,30000,300000 [default: one block]")
      ->delimiter(',');
  cmd->add_flag("--reference", o->reference,
                "also time the readable reference step on the same state; print the speed-up "
                "[default: off]");
  cmd->add_flag("--ledger", o->ledger,
                "rows with the conservation ledger (solver.ledger): the row's share includes it "
                "[default: off]");
  cmd->add_option("--scene", o->scene,
                  "time a real scene (name or path) instead of the block [default: the block]");
  cmd->add_option("--frames", o->frames, "frames of --scene to time [default: 3]");
  cmd->add_option("--domain-times", o->domain_times,
                  "with --scene: grow the domain away from its minimum corner to N x its area "
                  "(2D) or volume (3D) [allowed: 1-1e12; default: 1]")
      ->check(number_at_least(1, 1e12));
  cmd->add_option("--record", o->record,
                  "append one row per measurement to this performance ledger (CSV, "
                  "docs/data/performance-ledger.csv; created with its header if absent) "
                  "[default: none]");
  table.push_back({cmd, [o, cmd] { return bench(*o, *cmd); }});
}

}  // namespace apiclab::cli
