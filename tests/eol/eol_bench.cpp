// Per-stage timing of the EoL step in the form of Fan et al. 2013, Table II: two spheres on
// 2 × 32³ grids (no object–object contact: part 2), ms per step for forces, assembly (the
// impulse update and the node–plane rows, in one pass with the split's sums), the least-squares
// split (its solve and remainder, with the Δt choice's two projections, eq 32), the rest
// (advection, extrapolation, mass) and the whole step; then one surface placement
// (Algorithm 2), which runs once a frame; then the forces' time per Gauss point and a hash of
// the state (the same for any thread count).
//   build/tests/eol_bench [steps]
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <utility>

#include "sim/eol/eol_simulation.hpp"

int main(int argc, char** argv) {
  using namespace apiclab;
  using json = nlohmann::json;
  const int steps = argc > 1 ? std::atoi(argv[1]) : 100;
  // Radius 0.25 at dx 0.02 with 3 cells of padding: 25 + 1 + 6 = 32 nodes per axis.
  const json ball = {{"type", "ball"}, {"radius", 0.25}};
  json a = ball, b = ball;
  a["center"] = {0.5, 0.6, 0.5};
  b["center"] = {1.3, 0.6, 0.5};
  const json scene = {
      {"name", "table-ii-two-spheres"},
      {"dim", 3},
      {"domain", {{"min", {0, 0, 0}}, {"max", {1.8, 1.2, 1}}, {"dx", 0.02}, {"boundary", "slip"}}},
      {"gravity", {0, -9.8, 0}},
      {"time", {{"end", 10}, {"fps", 24}, {"dt", {{"rule", "elastic"}, {"nu", 0.3}}}}},
      {"solver", {{"method", "eol"}}},
      {"materials",
       {{{"name", "jelly"}, {"model", "neo-hookean"}, {"E", 2000}, {"nu", 0.3}, {"rho", 1}}}},
      {"objects",
       {{{"shape", a}, {"material", 0}, {"velocity", {1, 0, 0}}},
        {{"shape", b},
         {"material", 0},
         {"velocity", {-1, 0, 0}},
         {"angular_velocity", {0, 0, 2}}}}}};
  SceneDesc desc = parse_scene_text(scene.dump(), "table-ii");
  auto sim = make_simulation(desc);
  auto* eol = dynamic_cast<eol::EolSimulation<double, 3>*>(sim.get());
  DiagnosticsRow row;
  for (int s = 0; s < 3; ++s) sim->step(1e9, &row);  // warm up
  const auto before = eol->stage_seconds();
  const auto start = std::chrono::steady_clock::now();
  for (int s = 0; s < steps; ++s) sim->step(1e9, &row);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto after = eol->stage_seconds();
  const auto& g = eol->objects()[0].grid;
  const double ms = 1e3 / steps;
  // Algorithm 2 runs only at frame times (step() places the surface when a step lands on
  // one): one placement of both surfaces, warm-started from their positions `steps` steps ago.
  const auto placement_start = std::chrono::steady_clock::now();
  eol->place_surfaces();
  const double placement =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - placement_start).count();
  const double steps_per_frame = 1.0 / (desc.time.fps * row.dt);
  std::printf("EoL Table II form: 2 spheres, %zu x %dx%dx%d nodes, %d steps, dt %.3g s (%s)\n",
              eol->objects().size(), g.n[0], g.n[1], g.n[2], steps, row.dt, row.dt_limit.c_str());
  std::printf(
      "| Forces | Assembly | LS | Forces+Assembly+LS | Advection etc. | Step (with diagnostics) | "
      "Surface, per frame |\n|---|---|---|---|---|---|---|\n");
  const double f = (after.forces - before.forces) * ms,
               as = (after.assembly - before.assembly) * ms, ls = (after.split - before.split) * ms,
               adv = (after.advection - before.advection) * ms;
  std::printf("| %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", f, as, ls, f + as + ls, adv,
              wall * ms, placement * 1e3);
  std::printf(
      "surface: %zu + %zu vertices, placed once a frame (1/%g s = %.0f steps here: %.3f ms a "
      "step)\n",
      eol->objects()[0].surface.size(), eol->objects()[1].surface.size(), desc.time.fps,
      steps_per_frame, placement * 1e3 / steps_per_frame);
  // Forces per Gauss point: 2^d points in every cell holding material (the forces skip the rest).
  std::size_t cells = 0;
  for (const auto& o : std::as_const(*eol).objects())
    for (std::size_t base = 0; base < o.grid.size(); ++base)
      if (eol::is_cell_base(o.grid, base) && eol::cell_material(o.grid, base) >= 0) ++cells;
  std::printf("forces: %zu cells with material, %zu Gauss points: %.1f ns a point\n", cells,
              8 * cells, f * 1e6 / double(8 * cells));
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
  return 0;
}
