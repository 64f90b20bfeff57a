#include "app/figures/ringing_frames.hpp"

#include <algorithm>
#include <filesystem>

#include "app/cli.hpp"
#include "app/particle_frame.hpp"
#include "render/figure.hpp"
#include "render/image.hpp"
#include "render/renderer.hpp"
#include "render/target.hpp"

namespace apiclab::figures {

void write_ringing_frames(ChartCanvas& canvas, const std::vector<jobs::Run>& runs,
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
    if (r.snapshots.size() < rows)
      throw cli::UsageError("Fig 1: the " + r.scheme + " run stopped early: " + r.failure);
  // Frame the bodies, not the whole domain: every particle of every row and scheme.
  std::vector<const Snapshot*> all;
  for (auto& r : runs)
    for (std::size_t k = 0; k < rows; ++k) all.push_back(r.snapshots[k].get());
  style.frame = particle_frame(all);
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
        std::copy(row.rgba.begin(), row.rgba.end(),
                  out.rgba.begin() + std::ptrdiff_t(k * row.rgba.size()));
      }
    }
  render::write_png(out, (std::filesystem::path(dir) / "fig1_ringing.png").string());
}

}  // namespace apiclab::figures
