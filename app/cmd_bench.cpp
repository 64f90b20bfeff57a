// `apiclab bench`: explicit-step throughput on a standard elastic block.
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "app/cli_checks.hpp"
#include "cli.hpp"
#include "commands.hpp"

namespace apiclab::cli {
namespace {

struct BenchOptions {
  int dim = 2;
  long particles = 0;  // default: 262144 (2D), 110592 (3D)
  int steps = 0;       // default: 200 (2D), 50 (3D)
  std::string precision = "float", scheme = "apic", kernel = "quadratic", integrator = "symplectic";
  int threads = 0;
  std::string max_memory;
};

// A block of fixed-corotated material, spinning and falling, filling a quarter of the domain
// along each axis at 4 (2D) or 8 (3D) particles per cell.
std::string bench_scene(const BenchOptions& o, double& dx) {
  using json = nlohmann::json;
  const int ppc = o.dim == 2 ? 4 : 8;
  double cells_in_block = double(o.particles) / ppc;
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
      {"solver", {{"scheme", o.scheme}, {"kernel", o.kernel}, {"integrator", o.integrator}}},
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

int bench(BenchOptions o) {
  if (o.dim != 2 && o.dim != 3) throw UsageError("--dim must be 2 or 3");
  if (o.particles == 0) o.particles = o.dim == 2 ? 262144 : 110592;
  if (o.steps == 0) o.steps = o.dim == 2 ? 200 : 50;
  Precision precision;
  try {
    precision = parse_choice(precision_choices(), o.precision, "precision");
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  apply_threads(o.threads);
  double dx = 0;
  std::vector<std::string> sets;
  if (auto gb = max_memory_gb(o.max_memory))
    sets.push_back("solver.max_memory_gb=" + std::to_string(*gb));
  SceneDesc scene = parse_scene_text(bench_scene(o, dx), "bench scene", sets);
  auto sim = make_simulation(scene, precision);
  const double dt = scene.time.dt;
  for (int s = 0; s < 3; ++s) sim->step_fixed(dt);  // warm up: first sort, page faults
  double start = now_seconds();
  for (int s = 0; s < o.steps; ++s) sim->step_fixed(dt);
  double wall = now_seconds() - start;
  const DiagnosticsRow end = sim->measure();
  if (!std::isfinite(end.total + end.kinetic)) {
    std::fprintf(stderr,
                 "bench: the simulation blew up (non-finite state) within %d steps; try another "
                 "kernel or fewer steps\n",
                 o.steps);
    return 2;
  }
  double rate = double(particle_count(*sim)) * o.steps / wall;
  std::printf(
      "bench: %dD %s, scheme %s, kernel %s, integrator %s, %zu particles, dx %.4g, %d steps, %d "
      "threads\n",
      o.dim, o.precision.c_str(), o.scheme.c_str(), o.kernel.c_str(), o.integrator.c_str(),
      particle_count(*sim), dx, o.steps, omp_get_max_threads());
  std::printf("wall: %.3f s, %.3f ms/step\n", wall, 1e3 * wall / o.steps);
  std::printf("particle-steps/s: %.0f\n", rate);
  return 0;
}

}  // namespace

void register_bench(CLI::App& root, CommandTable& table) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* cmd =
      root.add_subcommand("bench", "explicit-step throughput; last line 'particle-steps/s: N'");
  cmd->add_option("--dim", o->dim, "dimension [allowed: 2, 3; default: 2]")
      ->check(CLI::IsMember({2, 3}));
  cmd->add_option("--particles", o->particles,
                  "particle count, approximate [allowed: 16 or more; default: 262144 (2D), "
                  "110592 (3D)]")
      ->check(CLI::Range(16L, 2000000000L));
  cmd->add_option("--steps", o->steps,
                  "timed steps [allowed: 1 or more; default: 200 (2D), 50 (3D)]")
      ->check(CLI::Range(1, 100000000));
  cmd->add_option("--precision", o->precision, "float|double [default: float]");
  cmd->add_option("--threads", o->threads, "OpenMP threads [allowed: 1-4096; default: all cores]")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--scheme", o->scheme,
                  "transfer scheme: " + choice_keys(scheme_choices()) + " [default: apic]");
  cmd->add_option("--kernel", o->kernel,
                  "kernel: " + choice_keys(kernel_choices()) + " [default: quadratic]");
  cmd->add_option("--integrator", o->integrator,
                  "integrator: " + choice_keys(integrator_choices()) + " [default: symplectic]");
  cmd->add_option("--max-memory", o->max_memory,
                  "refuse a block whose estimated memory exceeds this: BYTES (e.g. 8G), auto or "
                  "none [default: auto = the available memory]");
  table.push_back({cmd, [o] { return bench(*o); }});
}

}  // namespace apiclab::cli
