#include "app/figures/roundtrip_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "app/cli.hpp"
#include "app/figures/chart_style.hpp"
#include "app/gui/plot.hpp"
#include "app/jobs.hpp"
#include "render/image.hpp"
#include "sim/mpm/roundtrip.hpp"

namespace apiclab::figures {
namespace {

// Least-squares slope of log(error) against log(Δx): the order of the error.
double fitted_slope(const std::vector<RoundTripResult>& r) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = double(r.size());
  for (auto& e : r) {
    const double x = std::log(e.dx), y = std::log(e.l2_error);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

void write_roundtrip_figure(ChartCanvas& canvas, const std::vector<int>& resolutions, int threads,
                            const std::string& dir) {
  // Every scheme in the registry the probe can run: FLIP and ASFLIP blend with a prior
  // particle velocity, which a probe that starts from a grid field does not have.
  std::vector<std::string> schemes;
  for (const auto& c : scheme_choices())
    if (!blends_flip(c.value)) schemes.emplace_back(c.key);
  std::vector<std::vector<RoundTripResult>> results(
      schemes.size(), std::vector<RoundTripResult>(resolutions.size()));
  // Largest resolutions first, so that the pool ends together.
  jobs::run_pool(schemes.size() * resolutions.size(), threads, [&](std::size_t i) {
    const std::size_t s = i % schemes.size(), k = resolutions.size() - 1 - i / schemes.size();
    results[s][k] =
        roundtrip_error(KernelType::quadratic, parse_choice(scheme_choices(), schemes[s], "scheme"),
                        resolutions[k]);
  });
  const auto base = std::filesystem::path(dir) / "fig11_roundtrip";
  std::vector<double> slopes;
  {
    std::ofstream csv(base.string() + ".csv");
    csv << "scheme,resolution,dx,l2_error\n";
    csv.precision(17);
    for (std::size_t s = 0; s < schemes.size(); ++s)
      for (auto& e : results[s])
        csv << schemes[s] << ',' << e.resolution << ',' << e.dx << ',' << e.l2_error << '\n';
    if (!csv) throw cli::UsageError("cannot write " + base.string() + ".csv");
  }
  std::vector<gui::PlotSeries> series;
  for (std::size_t s = 0; s < schemes.size(); ++s) {
    // Data sorted by increasing Δx (the plot wants x not to decrease).
    std::sort(results[s].begin(), results[s].end(), [](auto& a, auto& b) { return a.dx < b.dx; });
    const double slope = fitted_slope(results[s]);
    slopes.push_back(slope);
    // The probe's own XPIC(2) and PolyPIC with every 2D mode (roundtrip_error's scene).
    const SchemeParameters probed{2, polypic::full_modes(2), 1.0};
    char label[96];
    std::snprintf(label, sizeof label, "%s (slope %.2f)",
                  style_of(schemes[s], probed, 1.0).label.c_str(), slope);
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
    o.x_label = "grid spacing Δx [m]";
    o.y_label = "L² error of grid velocity [m/s]";
    o.log_x = o.log_y = true;
    o.minor_log_grid = true;
    o.interactive = false;
    ImGui::SetCursorScreenPos(ImVec2(10, top));
    gui::plot("roundtrip", ImVec2(W - 20, H - top - 6), o, series);
  });
  render::write_png(image, base.string() + ".png");
  const auto at = [&](const char* key) {
    return std::size_t(std::find(schemes.begin(), schemes.end(), key) - schemes.begin());
  };
  const std::size_t pic_at = at("pic"), apic_at = at("apic");
  std::fprintf(stderr,
               "apiclab figures: Fig 11 slopes: PIC %.3f, APIC %.3f; error ratio PIC/APIC at "
               "Δx=%.4g: %.1f\n",
               slopes[pic_at], slopes[apic_at], results[pic_at].front().dx,
               results[pic_at].front().l2_error / results[apic_at].front().l2_error);
}

}  // namespace apiclab::figures
