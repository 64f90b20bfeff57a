// Per-stage timing of the EoL step in the form of Fan et al. 2013, Table II, "2 Spheres": two
// balls on 2 × 32³ grids, ms per step for the paper's five stages (Forces; Collision: the box
// test and the contact rows of eq 28; Assembly: the impulse, in one pass with the split's sums;
// LS: the least-squares split with the Δt choice's two projections, eq 32; QP: eq 29) and for the
// stages the paper leaves out (advection, extrapolation with the mass passes, the surface
// placements of Algorithm 2), and the whole step. Two windows: the balls in flight (no contact),
// then from the moment they touch (every step holds pair rows). Then one surface placement (once
// a frame), the forces' time per Gauss point and a hash of the state (the same for any thread
// count). With a second argument, the cost per simulated second of that many simulated seconds
// of the collision under explicit and implicit elasticity.
//   build/tests/eol_bench [steps] [simulated seconds]
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "sim/eol/eol_simulation.hpp"

namespace {

using namespace apiclab;
using json = nlohmann::json;
using Eol = eol::EolSimulation<double, 3>;

// Radius 0.25 at dx 0.02 with 3 cells of padding: 25 + 1 + 6 = 32 nodes per axis; the balls'
// centres `apart` metres apart (0.5: their surfaces touch).
std::unique_ptr<Simulation> two_spheres(double apart, const std::string& elasticity) {
  const json ball = {{"type", "ball"}, {"radius", 0.25}};
  json a = ball, b = ball;
  a["center"] = {0.5, 0.6, 0.5};
  b["center"] = {0.5 + apart, 0.6, 0.5};
  const json scene = {
      {"name", "table-ii-two-spheres"},
      {"dim", 3},
      {"domain", {{"min", {0, 0, 0}}, {"max", {1.8, 1.2, 1}}, {"dx", 0.02}, {"boundary", "slip"}}},
      {"gravity", {0, -9.8, 0}},
      {"time", {{"end", 10}, {"fps", 24}, {"dt", {{"rule", "elastic"}, {"nu", 0.3}}}}},
      {"solver", {{"method", "eol"}, {"elasticity", elasticity}}},
      {"materials",
       {{{"name", "jelly"}, {"model", "neo-hookean"}, {"E", 2000}, {"nu", 0.3}, {"rho", 1}}}},
      {"objects",
       {{{"shape", a}, {"material", 0}, {"velocity", {1, 0, 0}}},
        {{"shape", b},
         {"material", 0},
         {"velocity", {-1, 0, 0}},
         {"angular_velocity", {0, 0, 2}}}}}};
  return make_simulation(parse_scene_text(scene.dump(), "table-ii"));
}

double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

// `steps` steps after 3 warm-up steps: ms per step of each stage and of the whole step. Returns
// the last step's Δt and the forces' ms per step.
std::pair<double, double> time_window(Simulation& sim, Eol& eol, int steps, const char* what) {
  DiagnosticsRow row;
  for (int s = 0; s < 3; ++s) sim.step(1e9, &row);
  const auto before = eol.stage_seconds();
  const double cpu0 = cpu_seconds();
  const auto start = std::chrono::steady_clock::now();
  int touching = 0, rows = 0;
  for (int s = 0; s < steps; ++s) {
    sim.step(1e9, &row);
    touching += eol.last_object_pairs().empty() ? 0 : 1;
    rows = std::max(rows, eol.last_contact_solve().rows);
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cpu = cpu_seconds() - cpu0;
  const auto after = eol.stage_seconds();
  const auto& g = eol.objects()[0].grid;
  const double ms = 1e3 / steps;
  std::printf(
      "%s: %zu x %dx%dx%d nodes, %d steps (%d with pair rows, QP up to %d rows), dt %.3g s "
      "(%s), t = %.4f s\n",
      what, eol.objects().size(), g.n[0], g.n[1], g.n[2], steps, touching, rows, row.dt,
      row.dt_limit.c_str(), sim.time());
  const auto d = [&](double eol::EolSimulation<double, 3>::StageSeconds::*f) {
    return (after.*f - before.*f) * ms;
  };
  using S = Eol::StageSeconds;
  const double paper =
      d(&S::forces) + d(&S::collision) + d(&S::assembly) + d(&S::split) + d(&S::qp);
  std::printf(
      "| Forces | Collision | Assembly | LS | QP | the five | Advection | Extrapolation | "
      "Surface | Step (with diagnostics) |\n|---|---|---|---|---|---|---|---|---|---|\n");
  std::printf("| %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n",
              d(&S::forces), d(&S::collision), d(&S::assembly), d(&S::split), d(&S::qp), paper,
              d(&S::advection), d(&S::extrapolation), d(&S::surface), wall * ms);
  // On a loaded machine the stages' wall times stretch alike: scaled to the window's CPU time
  // (meaningful with one thread, where CPU time is the work itself).
  const double k = cpu / wall;
  std::printf(
      "| %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | (scaled to "
      "CPU time, %.2f CPU-s / %.2f s)\n",
      k * d(&S::forces), k * d(&S::collision), k * d(&S::assembly), k * d(&S::split), k * d(&S::qp),
      k * paper, k * d(&S::advection), k * d(&S::extrapolation), k * d(&S::surface), cpu * ms, cpu,
      wall);
  return {row.dt, d(&S::forces)};
}

// CPU seconds per simulated second of the collision from first touch, explicit and implicit.
void cost_per_second(double seconds) {
  for (const char* mode : {"explicit", "implicit"}) {
    auto sim = two_spheres(0.5, mode);
    long steps = 0;
    const double c0 = cpu_seconds();
    DiagnosticsRow row;
    while (sim->time() < seconds - 1e-12) {
      if (sim->step(seconds, &row)) break;
      ++steps;
    }
    const double cpu = cpu_seconds() - c0;
    std::printf(
        "%s elasticity: %.3f s simulated in %ld steps, %.1f CPU-s: %.1f CPU-s per "
        "simulated second%s\n",
        mode, sim->time(), steps, cpu, cpu / sim->time(), sim->failure() ? " (failed)" : "");
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 100;
  // In flight: 0.8 m apart, the balls never touch within the window.
  auto sim = two_spheres(0.8, "explicit");
  auto* eol = dynamic_cast<Eol*>(sim.get());
  const auto [dt, forces_ms] =
      time_window(*sim, *eol, steps, "EoL Table II form, 2 spheres in flight");
  // In contact: touching at the start.
  auto hit = two_spheres(0.5, "explicit");
  time_window(*hit, *dynamic_cast<Eol*>(hit.get()), steps, "2 spheres colliding");
  const SceneDesc& desc = sim->scene();
  // Algorithm 2 runs only at frame times (step() places the surface when a step lands on
  // one): one placement of both surfaces, warm-started from their positions `steps` steps ago.
  const auto placement_start = std::chrono::steady_clock::now();
  eol->place_surfaces();
  const double placement =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - placement_start).count();
  const double steps_per_frame = 1.0 / (desc.time.fps * dt);
  std::printf(
      "surface: %zu + %zu vertices, %.2f ms a placement, once a frame (1/%g s = %.0f steps in "
      "flight: %.3f ms a step)\n",
      eol->objects()[0].surface.size(), eol->objects()[1].surface.size(), placement * 1e3,
      desc.time.fps, steps_per_frame, placement * 1e3 / steps_per_frame);
  // Forces per Gauss point: 2^d points in every cell holding material (the forces skip the rest).
  std::size_t cells = 0;
  for (const auto& o : std::as_const(*eol).objects())
    for (std::size_t base = 0; base < o.grid.size(); ++base)
      if (eol::is_cell_base(o.grid, base) && eol::cell_material(o.grid, base) >= 0) ++cells;
  std::printf("forces: %zu cells with material, %zu Gauss points: %.1f ns a point\n", cells,
              8 * cells, forces_ms * 1e6 / double(8 * cells));
  // The state after the run, bit for bit (FNV-1a over X, v, u and the forces of both
  // objects): equal across builds and thread counts when the arithmetic is.
  std::uint64_t hash = 1469598103934665603ull;
  auto mix = [&](const auto& field) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(field.data());
    for (std::size_t i = 0; i < field.size() * sizeof(field[0]); ++i)
      hash = (hash ^ bytes[i]) * 1099511628211ull;
  };
  for (const auto& o : eol->objects()) {
    mix(o.grid.X);
    mix(o.grid.v);
    mix(o.u);
    mix(o.force);
  }
  std::printf("state after %d steps: hash %016llx, t = %.17g\n", steps + 3,
              (unsigned long long)hash, sim->time());
  if (argc > 2) cost_per_second(std::atof(argv[2]));
  return 0;
}
