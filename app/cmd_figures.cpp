// `apiclab figures --out DIR [--quick]`: the figures of Jiang et al. 2017, Sec 6, as PNG
// charts (drawn by the GUI's plot widget offscreen, app/figures/chart_canvas.hpp) and frames,
// each with the CSV behind it:
//   fig1_ringing.png               Fig 1: ringing frames at t = 2/24, 5/24, 40/24 s (PIC, FLIP, APIC)
//   fig3_rotating_disk.png/.csv    Fig 3: angular momentum and total energy, Sec 6.1
//   fig4_cylinder_rebound.png/.csv Fig 4: Sec 6.2     fig5_skew_impact.png/.csv  Fig 5: Sec 6.3
//   fig6_ring_collision.png/.csv   Fig 6: Sec 6.4
//   fig10_ringing_energy.png/.csv  Fig 10: total and kinetic energy of the ringing test, Sec 6.7
//   fig11_roundtrip.png/.csv       Fig 11: round-trip transfer error against Δx, Sec 6.8
#ifdef APICLAB_HAVE_FIGURES
#include <imgui.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include "app/figures/chart_canvas.hpp"
#include "app/gui/plot.hpp"
#include "cli.hpp"
#include "commands.hpp"
#include "render/figure.hpp"
#include "render/image.hpp"
#include "render/palette.hpp"
#include "render/renderer.hpp"
#include "render/target.hpp"
#include "sim/roundtrip.hpp"
#include "sim/simulation.hpp"

namespace apiclab::cli {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// One colour and label per scheme, the same in every figure and the GUI (render/palette.hpp).
struct SchemeStyle {
  std::string label;
  ImU32 color;
};
SchemeStyle style_of(const std::string& key) {
  return {render::scheme_label(key), render::packed_abgr(render::scheme_color(key))};
}

// One simulation run: the diagnostics rows from t = 0 and, when asked, snapshots at given times.
struct Run {
  std::string scene, scheme;
  std::vector<std::string> overrides;
  double t_end = 0;
  std::vector<double> snapshot_times;
  // Results.
  std::vector<DiagnosticsRow> rows;
  std::vector<std::shared_ptr<Snapshot>> snapshots;
  std::string failure;
  double seconds = 0;
};

void execute(Run& r) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::string> overrides = r.overrides;
  overrides.push_back("solver.scheme=" + r.scheme);
  SceneDesc scene = load_scene(resolve_scene_path(r.scene), overrides);
  if (r.t_end <= 0) r.t_end = scene.time.end;
  auto sim = make_simulation(scene);
  r.rows.push_back(sim->measure());
  auto on_step = [&](const DiagnosticsRow& row) { r.rows.push_back(row); };
  std::vector<double> stops = r.snapshot_times;
  stops.push_back(r.t_end);
  std::sort(stops.begin(), stops.end());
  for (double t : stops) {
    if (t > r.t_end + 1e-12) break;
    if (auto failure = sim->advance_to(t, on_step)) {
      char buf[64];
      std::snprintf(buf, sizeof buf, " (at t = %.4g)", sim->time());
      r.failure = failure->message + buf;
      break;
    }
    if (std::find(r.snapshot_times.begin(), r.snapshot_times.end(), t) != r.snapshot_times.end())
      r.snapshots.push_back(sim->snapshot());
  }
  r.seconds = seconds_since(t0);
}

// Runs the jobs on up to `threads` threads (each simulation is small: one thread apiece).
void execute_all(std::vector<Run*>& runs, int threads) {
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::string error;
  auto worker = [&] {
    for (std::size_t i; (i = next++) < runs.size();) {
      try {
        execute(*runs[i]);
      } catch (const std::exception& e) {
        std::lock_guard lock(error_mutex);
        if (error.empty()) error = runs[i]->scene + " (" + runs[i]->scheme + "): " + e.what();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int k = 0; k < std::max(1, std::min<int>(threads, int(runs.size()))); ++k)
    pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (!error.empty()) throw UsageError(error);
}

// A quantity of a diagnostics row, charted against time.
struct Quantity {
  std::string title, y_label;
  double (*of)(const DiagnosticsRow&);
  bool dashed = false;
};
double angular_momentum(const DiagnosticsRow& r) { return r.L[2]; }
double total_energy(const DiagnosticsRow& r) { return r.total; }
double kinetic_energy(const DiagnosticsRow& r) { return r.kinetic; }

// A figure of two charts side by side, one line per scheme in each.
struct TimeFigure {
  std::string file, heading, scene;
  double quick_t_end = 0;  // 0: the scene's end time in --quick as well
  std::vector<std::string> schemes;
  Quantity left, right;
  gui::PlotOptions::Corner left_legend = gui::PlotOptions::Corner::best,
                           right_legend = gui::PlotOptions::Corner::best;
  std::vector<Run> runs;
};

std::string series_label(const Run& r) {
  std::string label = style_of(r.scheme).label;
  if (!r.failure.empty()) label += " (failed)";
  return label;
}

std::vector<gui::PlotSeries> time_series(const std::vector<Run>& runs, const Quantity& q) {
  std::vector<gui::PlotSeries> out;
  for (const Run& r : runs) {
    gui::PlotSeries s;
    s.label = series_label(r);
    s.color = style_of(r.scheme).color;
    s.count = r.rows.size();
    s.x = [&r](std::size_t i) { return r.rows[i].t; };
    s.y = [&r, of = q.of](std::size_t i) { return of(r.rows[i]); };
    s.thickness = 2.0f;
    s.dashed = q.dashed || r.scheme == "rpic";  // RPIC often lies on APIC: dashes show both
    out.push_back(std::move(s));
  }
  return out;
}

constexpr int kChartW = 900, kChartH = 400;

// Draws the heading across the top and returns the y where the charts start.
float heading(figures::ChartCanvas& canvas, const std::string& text, float width) {
  ImGui::PushFont(canvas.title_font());
  const ImVec2 ts = ImGui::CalcTextSize(text.c_str());
  ImGui::GetWindowDrawList()->AddText(ImVec2((width - ts.x) / 2, 6), IM_COL32(20, 20, 20, 255),
                                      text.c_str());
  ImGui::PopFont();
  return ts.y + 12;
}

void write_time_figure(figures::ChartCanvas& canvas, const TimeFigure& f, const std::string& dir) {
  const auto base = std::filesystem::path(dir) / f.file;
  {
    std::ofstream csv(base.string() + ".csv");
    csv << "scheme,step,t,dt,kinetic,kinetic_grid,potential,total_energy,angular_momentum\n";
    csv.precision(17);
    for (const Run& r : f.runs)
      for (const DiagnosticsRow& d : r.rows)
        csv << r.scheme << ',' << d.step << ',' << d.t << ',' << d.dt << ',' << d.kinetic << ','
            << d.kinetic_grid << ',' << d.potential << ',' << d.total << ',' << d.L[2] << '\n';
    if (!csv) throw UsageError("cannot write " + base.string() + ".csv");
  }
  render::Image image = canvas.draw(kChartW, kChartH, [&] {
    const float top = heading(canvas, f.heading, kChartW);
    const float w = (kChartW - 30) / 2.0f, h = kChartH - top - 6;
    int k = 0;
    for (const Quantity* q : {&f.left, &f.right}) {
      gui::PlotOptions o;
      o.title = q->title;
      o.y_label = q->y_label;
      o.x_label = "time t [s]";
      o.interactive = false;
      o.legend_corner = k == 0 ? f.left_legend : f.right_legend;
      ImGui::SetCursorScreenPos(ImVec2(10 + k * (w + 10), top));
      gui::plot(q->title.c_str(), ImVec2(w, h), o, time_series(f.runs, *q));
      ++k;
    }
  });
  render::write_png(image, base.string() + ".png");
}

// Fig 11: log-log round-trip error with least-squares slopes.
double fitted_slope(const std::vector<RoundTripResult>& r) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = double(r.size());
  for (auto& e : r) {
    const double x = std::log(e.dx), y = std::log(e.l2_error);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

void write_roundtrip_figure(figures::ChartCanvas& canvas, const std::vector<int>& resolutions,
                            int threads, const std::string& dir) {
  const std::vector<std::string> schemes{"pic", "apic"};
  std::vector<std::vector<RoundTripResult>> results(schemes.size(),
                                                    std::vector<RoundTripResult>(resolutions.size()));
  {
    std::atomic<std::size_t> next{0};
    const std::size_t jobs = schemes.size() * resolutions.size();
    auto worker = [&] {
      // Largest resolutions first, so that the pool ends together.
      for (std::size_t i; (i = next++) < jobs;) {
        const std::size_t s = i % schemes.size(), k = resolutions.size() - 1 - i / schemes.size();
        results[s][k] = roundtrip_error(KernelType::quadratic,
                                        parse_choice(scheme_choices(), schemes[s], "scheme"),
                                        resolutions[k]);
      }
    };
    std::vector<std::thread> pool;
    for (int t = 0; t < std::max(1, std::min<int>(threads, int(jobs))); ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  }
  const auto base = std::filesystem::path(dir) / "fig11_roundtrip";
  std::vector<double> slopes;
  {
    std::ofstream csv(base.string() + ".csv");
    csv << "scheme,resolution,dx,l2_error\n";
    csv.precision(17);
    for (std::size_t s = 0; s < schemes.size(); ++s)
      for (auto& e : results[s])
        csv << schemes[s] << ',' << e.resolution << ',' << e.dx << ',' << e.l2_error << '\n';
    if (!csv) throw UsageError("cannot write " + base.string() + ".csv");
  }
  std::vector<gui::PlotSeries> series;
  for (std::size_t s = 0; s < schemes.size(); ++s) {
    // Data sorted by increasing Δx (the plot wants x not to decrease).
    std::sort(results[s].begin(), results[s].end(),
              [](auto& a, auto& b) { return a.dx < b.dx; });
    const double slope = fitted_slope(results[s]);
    slopes.push_back(slope);
    char label[64];
    std::snprintf(label, sizeof label, "%s (slope %.2f)", style_of(schemes[s]).label.c_str(), slope);
    gui::PlotSeries p;
    p.label = label;
    p.color = style_of(schemes[s]).color;
    p.count = results[s].size();
    p.x = [&r = results[s]](std::size_t i) { return r[i].dx; };
    p.y = [&r = results[s]](std::size_t i) { return r[i].l2_error; };
    p.thickness = 2.0f;
    p.markers = true;
    series.push_back(std::move(p));
  }
  // A first-order reference line through PIC's coarsest point, a decade below.
  const auto& pic = results[0];
  gui::PlotSeries ref;
  ref.label = "first order (slope 1)";
  ref.color = IM_COL32(120, 120, 120, 255);
  ref.count = 2;
  ref.x = [&pic](std::size_t i) { return i == 0 ? pic.front().dx : pic.back().dx; };
  ref.y = [&pic](std::size_t i) {
    const double x = i == 0 ? pic.front().dx : pic.back().dx;
    return 0.3 * pic.back().l2_error * x / pic.back().dx;
  };
  ref.dashed = true;
  ref.thickness = 1.4f;
  series.push_back(std::move(ref));
  const int W = 640, H = 440;
  render::Image image = canvas.draw(W, H, [&] {
    const float top = heading(canvas, "Fig. 11 — Round-trip transfer error (Sec. 6.8)", W);
    gui::PlotOptions o;
    o.title = "G2P then P2G, Δt = 0, quadratic B-splines";
    o.x_label = "grid spacing Δx";
    o.y_label = "L² error of grid velocity";
    o.log_x = o.log_y = true;
    o.minor_log_grid = true;
    o.interactive = false;
    o.legend_corner = gui::PlotOptions::Corner::best;
    ImGui::SetCursorScreenPos(ImVec2(10, top));
    gui::plot("roundtrip", ImVec2(W - 20, H - top - 6), o, series);
  });
  render::write_png(image, base.string() + ".png");
  std::fprintf(stderr, "apiclab figures: Fig 11 slopes: PIC %.3f, APIC %.3f; error ratio PIC/APIC at Δx=%.4g: %.1f\n",
               slopes[0], slopes[1], results[0].front().dx,
               results[0].front().l2_error / results[1].front().l2_error);
}

// Fig 1: the ringing frames, one row per time, one pane per scheme, velocity vectors on.
void write_ringing_frames(figures::ChartCanvas& canvas, const std::vector<Run>& runs,
                          const std::vector<double>& times, const std::string& dir) {
  canvas.make_current();
  const int W = 1200, H = 420;
  render::RenderTarget target(W, H);
  render::Renderer renderer;
  render::FigureStyle style;
  style.vectors = true;
  style.color = render::ColorMode::speed;
  style.time_step = 1.0 / 24;
  render::FigureState state;
  const std::size_t rows = std::min(times.size(), runs.front().snapshots.size());
  for (auto& r : runs)
    if (r.snapshots.size() < rows) throw UsageError("Fig 1: the " + r.scheme + " run stopped early: " + r.failure);
  // Frame the bodies, not the whole domain: every particle of every row and scheme, with
  // a sixth of their extent and two cells around them (and the walls they touch).
  {
    const Snapshot& first = *runs.front().snapshots.front();
    render::Box3 b = render::particle_box(first);
    for (auto& r : runs)
      for (std::size_t k = 0; k < rows; ++k) {
        const render::Box3 q = render::particle_box(*r.snapshots[k]);
        for (int a = 0; a < 3; ++a)
          b.min[a] = std::min(b.min[a], q.min[a]), b.max[a] = std::max(b.max[a], q.max[a]);
      }
    const render::Box3 domain = render::domain_box(first);
    const render::Vec3 size = b.size();
    const float room = std::max(size.x, size.y) / 6 + 2 * float(first.dx);
    for (int a = 0; a < first.dim; ++a) {
      b.min[a] = std::max(b.min[a] - room, domain.min[a]);
      b.max[a] = std::min(b.max[a] + room, domain.max[a]);
    }
    style.frame = b;
  }
  render::Image out(W, int(H * rows));
  // Twice: the first pass settles the shared color and arrow scales over all rows.
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t k = 0; k < rows; ++k) {
      std::vector<const Snapshot*> panes;
      for (auto& r : runs) panes.push_back(r.snapshots[k].get());
      target.bind();
      render::draw_figure(renderer, W, H, panes, style, state);
      if (pass == 1) {
        const render::Image row = target.read();
        std::copy(row.rgba.begin(), row.rgba.end(), out.rgba.begin() + std::ptrdiff_t(k * row.rgba.size()));
      }
    }
  render::write_png(out, (std::filesystem::path(dir) / "fig1_ringing.png").string());
}

struct FiguresOptions {
  std::string out;
  bool quick = false;
  std::vector<std::string> only;
  int threads = 0;
};

bool wanted(const FiguresOptions& o, const std::string& fig) {
  return o.only.empty() || std::find(o.only.begin(), o.only.end(), fig) != o.only.end();
}

int run_figures(const FiguresOptions& o) {
  const auto t_start = std::chrono::steady_clock::now();
  ensure_writable_dir(o.out);
  const int threads = o.threads > 0 ? o.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  std::unique_ptr<figures::ChartCanvas> canvas;
  try {
    canvas = std::make_unique<figures::ChartCanvas>(14.0f);
  } catch (const std::exception& e) {
    throw UsageError(std::string("figures: ") + e.what());
  }
  std::fprintf(stderr, "apiclab figures: %s run, %d threads, charts through %s\n",
               o.quick ? "quick" : "full", threads, canvas->description().c_str());

  // Figs 3-6: the scenes as shipped, the scheme set per series.
  const std::vector<std::string> four{"pic", "flip", "apic", "rpic"};
  const Quantity L{"Angular momentum", "angular momentum L", angular_momentum};
  const Quantity E{"Total energy", "total energy E", total_energy};
  std::vector<TimeFigure> figs = {
      {"fig3_rotating_disk", "Fig. 3 — Rotating elastic disk (Sec. 6.1)", "rotating-disk", 0.5, four, L, E},
      {"fig4_cylinder_rebound", "Fig. 4 — Rebound of an elastic cylinder (Sec. 6.2)", "cylinder-rebound", 0, four, L, E},
      {"fig5_skew_impact", "Fig. 5 — Skew impact of two elastic cylinders (Sec. 6.3)", "skew-impact", 0, four, L, E},
      {"fig6_ring_collision", "Fig. 6 — Collision of two elastic rings (Sec. 6.4)", "ring-collision", 0.004, four, L, E},
  };
  const char* fig_ids[] = {"3", "4", "5", "6"};
  std::vector<TimeFigure*> chosen;
  for (std::size_t i = 0; i < figs.size(); ++i)
    if (wanted(o, fig_ids[i])) chosen.push_back(&figs[i]);

  // Figs 1 and 10: the ringing test (Sec 6.7), when its scene is there.
  const double ringing_times[] = {2.0 / 24, 5.0 / 24, 40.0 / 24};
  std::vector<double> frame_times;
  TimeFigure ringing{"fig10_ringing_energy", "Fig. 10 — Ringing test: energy (Sec. 6.7)", "ringing", 10.0 / 24,
                     {"pic", "flip", "apic"},
                     {"Total energy", "total energy E", total_energy},
                     {"Kinetic energy", "kinetic energy", kinetic_energy}};
  bool do_ringing = wanted(o, "1") || wanted(o, "10");
  if (do_ringing) {
    const std::string path = resolve_scene_path("ringing");
    if (!std::filesystem::is_regular_file(path)) {
      std::fprintf(stderr,
                   "apiclab figures: skipping Fig 1 and Fig 10: the ringing scene (%s/ringing.json) "
                   "is not there yet\n",
                   scenes_directory().c_str());
      do_ringing = false;
    }
  }

  std::vector<Run*> jobs;
  for (TimeFigure* f : chosen)
    for (const std::string& s : f->schemes) {
      Run r;
      r.scene = f->scene, r.scheme = s;
      if (o.quick) r.t_end = f->quick_t_end;
      f->runs.push_back(std::move(r));
    }
  if (do_ringing) {
    const SceneDesc scene = load_scene(resolve_scene_path("ringing"));
    const double t_end = o.quick ? std::min(scene.time.end, ringing.quick_t_end)
                                 : std::max(scene.time.end, ringing_times[2]);
    for (double t : ringing_times)
      if (t <= t_end + 1e-12) frame_times.push_back(t);
    if (o.quick && frame_times.size() < 3) frame_times.push_back(t_end);
    for (const std::string& s : ringing.schemes) {
      Run r;
      r.scene = "ringing", r.scheme = s, r.t_end = t_end;
      if (wanted(o, "1")) r.snapshot_times = frame_times;
      ringing.runs.push_back(std::move(r));
    }
    chosen.push_back(&ringing);
  }
  for (TimeFigure* f : chosen)
    for (Run& r : f->runs) jobs.push_back(&r);
  // Longest first: the rotating disk and the ring collision dominate.
  std::stable_sort(jobs.begin(), jobs.end(), [](Run* a, Run* b) {
    auto cost = [](Run* r) { return r->scene == "rotating-disk" ? 2 : r->scene == "ringing" ? 3 : r->scene == "ring-collision" ? 1 : 0; };
    return cost(a) > cost(b);
  });
  const auto t_sims = std::chrono::steady_clock::now();
  try {
    execute_all(jobs, threads);
  } catch (const SceneError& e) {
    throw UsageError(e.what());
  }
  std::fprintf(stderr, "apiclab figures: %zu simulations in %.1f s\n", jobs.size(), seconds_since(t_sims));
  for (TimeFigure* f : chosen)
    for (const Run& r : f->runs)
      if (!r.failure.empty())
        std::fprintf(stderr, "apiclab figures: %s with %s failed: %s (charted up to there)\n",
                     r.scene.c_str(), r.scheme.c_str(), r.failure.c_str());

  for (TimeFigure* f : chosen) {
    if (f == &ringing && !wanted(o, "10")) continue;
    write_time_figure(*canvas, *f, o.out);
    std::fprintf(stderr, "apiclab figures: wrote %s/%s.png and .csv\n", o.out.c_str(), f->file.c_str());
  }
  if (do_ringing && wanted(o, "1")) {
    write_ringing_frames(*canvas, ringing.runs, frame_times, o.out);
    std::fprintf(stderr, "apiclab figures: wrote %s/fig1_ringing.png\n", o.out.c_str());
  }
  if (wanted(o, "11")) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<int> res = o.quick ? std::vector<int>{16, 32, 64} : std::vector<int>{16, 32, 64, 128, 256};
    write_roundtrip_figure(*canvas, res, threads, o.out);
    std::fprintf(stderr, "apiclab figures: wrote %s/fig11_roundtrip.png and .csv (%.1f s)\n", o.out.c_str(),
                 seconds_since(t0));
  }
  std::fprintf(stderr, "apiclab figures: done in %.1f s\n", seconds_since(t_start));
  return 0;
}

}  // namespace

void register_figures(CLI::App& root, CommandTable& table) {
  auto o = std::make_shared<FiguresOptions>();
  CLI::App* cmd = root.add_subcommand(
      "figures", "the paper's figures (Jiang et al. 2017, Sec 6) as PNG charts and frames, with their CSV");
  cmd->add_option("--out", o->out, "output directory")->required();
  cmd->add_flag("--quick", o->quick, "coarser and shorter runs (CI): end times cut, round trip to 64");
  cmd->add_option("--only", o->only, "figure numbers to make, e.g. 3,11 (default: all)")->delimiter(',');
  cmd->add_option("--threads", o->threads, "simulations run at once (default: all cores)");
  table.push_back({cmd, [o] {
                     for (auto& f : o->only)
                       if (f != "1" && f != "3" && f != "4" && f != "5" && f != "6" && f != "10" && f != "11")
                         throw UsageError("--only: unknown figure '" + f + "' (expected 1,3,4,5,6,10,11)");
                     return run_figures(*o);
                   }});
}

}  // namespace apiclab::cli
#endif  // APICLAB_HAVE_FIGURES
