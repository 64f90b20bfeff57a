// `apiclab figures --out DIR [--quick]`: the figures of Jiang et al. 2017, Sec 6, as PNG
// charts (drawn by the GUI's plot widget offscreen, app/figures/chart_canvas.hpp) and frames,
// each with the CSV behind it (the list: app/figures/catalogue.cpp):
//   fig1_ringing.png               Fig 1: ringing frames at t = 2/24, 5/24, 40/24 s (PIC, FLIP,
//   APIC) fig3_rotating_disk.png/.csv    Fig 3: angular momentum and total energy, Sec 6.1
//   fig4_cylinder_rebound.png/.csv Fig 4: Sec 6.2     fig5_skew_impact.png/.csv  Fig 5: Sec 6.3
//   fig6_ring_collision.png/.csv   Fig 6: Sec 6.4
//   fig10_ringing_energy.png/.csv  Fig 10: total and kinetic energy of the ringing test, Sec 6.7
//   fig11_roundtrip.png/.csv       Fig 11: round-trip transfer error against Δx, Sec 6.8
//   eol_fig6_translation.png/.csv  Fan et al. 2013 Fig 6: grid nodes and memory, EoL/Eulerian
//   eol_fig7_spin.png/.csv         Fan et al. 2013 Fig 7: ω(t) of a spinning disk, EoL/Eulerian
//   eol_fig8_two_balls.png/.csv    Fan et al. 2013 Fig 8: EoL's Δt through the two-ball
//                                  collision, coloured by its bound, the contact marked
//   eol_fig9_two_balls.png/.csv    Fan et al. 2013 Fig 9: the same, EoL beside Eulerian
//   scheme_energy.png/.csv         two-ring total energy at a fixed time, every scheme
#include <algorithm>
#include <cstdio>
#include <thread>

#include "app/cli_checks.hpp"
#include "app/clock.hpp"
#include "app/figures/catalogue.hpp"
#include "app/figures/chart_canvas.hpp"
#include "app/figures/ringing_frames.hpp"
#include "app/figures/roundtrip_figure.hpp"
#include "app/figures/scheme_energy_figure.hpp"
#include "app/figures/time_figure.hpp"
#include "app/jobs.hpp"
#include "cli.hpp"
#include "commands.hpp"

namespace apiclab::cli {
namespace {

using figures::wanted;

struct FiguresOptions {
  std::string out;
  bool quick = false;
  std::vector<std::string> only;
  int threads = 0;
};

int run_figures(const FiguresOptions& o) {
  const double t_start = now_seconds();
  ensure_writable_dir(o.out);
  const int threads =
      o.threads > 0 ? o.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  std::unique_ptr<figures::ChartCanvas> canvas;
  try {
    canvas = std::make_unique<figures::ChartCanvas>(14.0f);
  } catch (const std::exception& e) {
    throw UsageError(std::string("figures: ") + e.what());
  }
  std::fprintf(stderr, "apiclab figures: %s run, %d threads, charts through %s\n",
               o.quick ? "quick" : "full", threads, canvas->description().c_str());

  // The time figures asked for (Fig 1 draws frames of Fig 10's runs), one run per scheme.
  std::vector<figures::TimeFigure> chosen;
  std::vector<double> frame_times;
  const bool frames = wanted(o.only, figures::kRingingFramesId);
  for (figures::TimeFigure& f : figures::time_figures()) {
    const bool ringing = f.id == figures::kRingingFigureId;
    if (!wanted(o.only, f.id) && !(ringing && frames)) continue;
    double t_end = o.quick ? f.quick_t_end : 0;
    if (ringing) {  // long enough for Fig 1's last frame, or cut short in --quick
      const SceneDesc scene = load_scene(resolve_scene_path(f.scene));
      t_end = o.quick ? std::min(scene.time.end, f.quick_t_end)
                      : std::max(scene.time.end, figures::ringing_frame_times().back());
      for (double t : figures::ringing_frame_times())
        if (t <= t_end + 1e-12) frame_times.push_back(t);
      if (o.quick && frame_times.size() < 3) frame_times.push_back(t_end);
    }
    for (const std::string& s : f.schemes) {
      jobs::Run r;
      r.scene = f.scene, r.scheme = s, r.t_end = t_end, r.cost = f.cost;
      r.overrides = f.overrides;
      if (o.quick)
        r.overrides.insert(r.overrides.end(), f.quick_overrides.begin(), f.quick_overrides.end());
      if (f.methods) r.scheme.clear(), r.method = s;
      if (ringing && frames) r.snapshot_times = frame_times;
      f.runs.push_back(std::move(r));
    }
    chosen.push_back(std::move(f));
  }
  std::vector<jobs::Run*> runs;
  for (figures::TimeFigure& f : chosen)
    for (jobs::Run& r : f.runs) runs.push_back(&r);
  const double t_sims = now_seconds();
  try {
    jobs::execute_all(runs, threads);
  } catch (const jobs::JobError& e) {
    throw UsageError(e.what());
  }
  std::fprintf(stderr, "apiclab figures: %zu simulations in %.1f s\n", runs.size(),
               now_seconds() - t_sims);
  for (const figures::TimeFigure& f : chosen)
    for (const jobs::Run& r : f.runs)
      if (!r.failure.empty())
        std::fprintf(stderr, "apiclab figures: %s with %s failed: %s (charted up to there)\n",
                     r.scene.c_str(), (r.method.empty() ? r.scheme : r.method).c_str(),
                     r.failure.c_str());

  for (const figures::TimeFigure& f : chosen) {
    if (!wanted(o.only, f.id)) continue;
    write_time_figure(*canvas, f, o.out);
    std::fprintf(stderr, "apiclab figures: wrote %s/%s.png and .csv\n", o.out.c_str(),
                 f.file.c_str());
  }
  for (const figures::TimeFigure& f : chosen)
    if (f.id == figures::kRingingFigureId && frames) {
      write_ringing_frames(*canvas, f.runs, frame_times, o.out);
      std::fprintf(stderr, "apiclab figures: wrote %s/fig1_ringing.png\n", o.out.c_str());
    }
  if (wanted(o.only, "11")) {
    const double t0 = now_seconds();
    const std::vector<int> res =
        o.quick ? std::vector<int>{16, 32, 64} : std::vector<int>{16, 32, 64, 128, 256};
    write_roundtrip_figure(*canvas, res, threads, o.out);
    std::fprintf(stderr, "apiclab figures: wrote %s/fig11_roundtrip.png and .csv (%.1f s)\n",
                 o.out.c_str(), now_seconds() - t0);
  }
  if (wanted(o.only, figures::kSchemeEnergyId)) {
    const double t0 = now_seconds();
    try {
      write_scheme_energy_figure(*canvas, o.quick, threads, o.out);
    } catch (const jobs::JobError& e) {
      throw UsageError(e.what());
    }
    std::fprintf(stderr, "apiclab figures: wrote %s/scheme_energy.png and .csv (%.1f s)\n",
                 o.out.c_str(), now_seconds() - t0);
  }
  std::fprintf(stderr, "apiclab figures: done in %.1f s\n", now_seconds() - t_start);
  return 0;
}

}  // namespace

void register_figures(CLI::App& root, CommandTable& table) {
  auto o = std::make_shared<FiguresOptions>();
  CLI::App* cmd = root.add_subcommand(
      "figures",
      "the paper's figures (Jiang et al. 2017, Sec 6) as PNG charts and frames, with their CSV");
  cmd->add_option("--out", o->out, "output directory [required]")->required();
  cmd->add_flag("--quick", o->quick,
                "coarser and shorter runs (CI): end times cut, round trip to 64 [default: off]");
  std::string ids;
  for (const std::string& id : figures::figure_ids()) ids += (ids.empty() ? "" : ",") + id;
  cmd->add_option("--only", o->only,
                  "figures to make, a comma-separated list of: " + ids + " [default: all]")
      ->delimiter(',');
  cmd->add_option("--threads", o->threads,
                  "simulations run at once [allowed: 1-4096; default: all cores]")
      ->check(whole_number(1, 4096));
  table.push_back({cmd, [o] {
                     figures::check_figure_ids(o->only);
                     return run_figures(*o);
                   }});
}

}  // namespace apiclab::cli
