#include "app/jobs.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <exception>
#include <mutex>
#include <thread>

#include "app/assets.hpp"
#include "app/clock.hpp"
#include "app/lockstep.hpp"

namespace apiclab::jobs {

void execute(Run& r) {
  const double t0 = now_seconds();
  std::vector<std::string> overrides = r.overrides;
  overrides.push_back(r.method.empty() ? "solver.scheme=" + r.scheme : "solver.method=" + r.method);
  SceneDesc scene = load_scene(resolve_scene_path(r.scene), overrides);
  scene.asset_dirs.push_back(assets_directory());
  if (r.t_end <= 0) r.t_end = scene.time.end;
  r.scheme_parameters = scheme_parameters_of(scene);
  r.flip_alpha = scene.solver.flip_alpha;
  auto sim = make_simulation(scene);
  r.rows.push_back(sim->measure());
  Lockstep pane({sim.get()});
  const auto on_row = [&](std::size_t, const DiagnosticsRow& row) { r.rows.push_back(row); };
  std::vector<double> stops = r.snapshot_times;
  stops.push_back(r.t_end);
  std::sort(stops.begin(), stops.end());
  stops.erase(std::unique(stops.begin(), stops.end()), stops.end());  // one snapshot per time
  for (double t : stops) {
    if (t > r.t_end + 1e-12) break;
    pane.advance_to(t, on_row);
    if (const auto& failure = sim->failure()) {
      char at[64];
      std::snprintf(at, sizeof at, " (at t = %.4g)", sim->time());
      r.failure = failure->message + at;
      break;
    }
    if (std::find(r.snapshot_times.begin(), r.snapshot_times.end(), t) != r.snapshot_times.end())
      r.snapshots.push_back(sim->snapshot());
  }
  r.seconds = now_seconds() - t0;
}

void execute_all(const std::vector<Run*>& runs, int threads) {
  std::vector<Run*> shared, alone;
  for (Run* r : runs) (r->timed ? alone : shared).push_back(r);
  std::stable_sort(shared.begin(), shared.end(), [](Run* a, Run* b) { return a->cost > b->cost; });
  auto job = [](Run& r) {
    try {
      execute(r);
    } catch (const std::exception& e) {
      throw JobError(r.scene + " (" + r.scheme + "): " + e.what());
    }
  };
  run_pool(shared.size(), threads, [&](std::size_t i) { job(*shared[i]); });
  for (Run* r : alone) job(*r);
}

}  // namespace apiclab::jobs
