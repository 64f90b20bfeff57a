#include "app/figures/scheme_energy_figure.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "app/assets.hpp"
#include "app/cli.hpp"
#include "app/figures/chart_style.hpp"
#include "app/jobs.hpp"
#include "render/image.hpp"
#include "sim/method_registry.hpp"
#include "sim/scene/registry.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab::figures {
namespace {

// Every scheme runs the same explicit step (MLS-MPM has no implicit form): symplectic Euler
// with the elastic limit ν Δx / (c + max|v|), ν = 0.3.
const std::vector<std::string> kOverrides{"solver.integrator=symplectic",
                                          R"(time.dt={"rule":"elastic","nu":0.3})"};
constexpr const char* kScene = "ring-collision";

struct Bar {
  std::string scheme, label;  // the key, and the legend's name with its parameter: "XPIC(2)"
  double t = 0, total = 0, kinetic = 0, potential = 0, initial = 0;
  std::string failure;
};

// Bars with a value label, one per scheme, on a linear axis from 0.
void draw_bars(const std::vector<Bar>& bars, ImVec2 origin, ImVec2 size) {
  ImDrawList* dl = ImGui::GetWindowDrawList();
  double top = 0;
  for (const Bar& b : bars)  // a run that blew up is labelled, not drawn
    top = std::max(top, b.failure.empty() ? std::max(b.total, b.initial) : b.initial);
  top *= 1.12;
  const float left = origin.x + 70, bottom = origin.y + size.y - 40, height = bottom - origin.y;
  const float width = origin.x + size.x - left;
  const ImU32 ink = IM_COL32(40, 40, 40, 255), grid = IM_COL32(215, 215, 215, 255);
  for (int k = 0; k <= 5; ++k) {  // axis ticks at fifths of the range
    const double v = top * k / 5;
    const float y = bottom - float(v / top) * height;
    dl->AddLine(ImVec2(left, y), ImVec2(left + width, y), grid);
    char label[32];
    std::snprintf(label, sizeof label, "%.0f", v);
    dl->AddText(ImVec2(origin.x + 4, y - 7), ink, label);
  }
  dl->AddText(ImVec2(left, origin.y - 22), ink, "total energy [J]");
  const float slot = width / float(std::max<std::size_t>(1, bars.size()));
  for (std::size_t k = 0; k < bars.size(); ++k) {
    const Bar& b = bars[k];
    const SchemeStyle st = style_of(b.scheme);
    const float x0 = left + slot * float(k) + slot * 0.18f, x1 = x0 + slot * 0.64f;
    const float y =
        b.failure.empty() ? bottom - float(std::max(0.0, b.total) / top) * height : bottom;
    if (b.failure.empty()) dl->AddRectFilled(ImVec2(x0, y), ImVec2(x1, bottom), st.color);
    char value[48];
    if (b.failure.empty())
      std::snprintf(value, sizeof value, "%.1f", b.total);
    else
      std::snprintf(value, sizeof value, "blew up");
    dl->AddText(ImVec2(x0, y - 18), ink, value);
    // The parameter, "(9 modes)", on a line of its own: nine names side by side would overlap.
    const std::size_t open = b.label.find('(');
    dl->AddText(ImVec2(x0, bottom + 6), ink, b.label.substr(0, open).c_str());
    if (open != std::string::npos)
      dl->AddText(ImVec2(x0, bottom + 21), ink, b.label.substr(open).c_str());
  }
  if (!bars.empty()) {  // the initial energy, the same for every scheme up to its C terms
    const float y = bottom - float(bars.front().initial / top) * height;
    dl->AddLine(ImVec2(left, y), ImVec2(left + width, y), IM_COL32(120, 120, 120, 255), 1.5f);
    dl->AddText(ImVec2(left + width - 150, y - 18), ink, "initial energy");
  }
  dl->AddLine(ImVec2(left, bottom), ImVec2(left + width, bottom), ink);
}

}  // namespace

void write_scheme_energy_figure(ChartCanvas& canvas, bool quick, int threads,
                                const std::string& dir) {
  const SceneDesc scene = load_scene(resolve_scene_path(kScene), kOverrides);
  const double t_end = quick ? 0.005 : scene.time.end;
  std::vector<jobs::Run> runs;
  std::vector<Bar> bars;
  for (const auto& choice : scheme_choices()) {
    SolverDesc solver = scene.solver;
    solver.scheme = choice.value;
    if (const std::string why = scheme_conflict(solver); !why.empty()) {
      std::fprintf(stderr, "apiclab figures: scheme-energy leaves out %s: %s\n",
                   std::string(choice.key).c_str(), why.c_str());
      continue;
    }
    jobs::Run r;
    r.scene = kScene, r.scheme = std::string(choice.key), r.t_end = t_end;
    r.overrides = kOverrides;
    runs.push_back(std::move(r));
  }
  std::vector<jobs::Run*> pointers;
  for (jobs::Run& r : runs) pointers.push_back(&r);
  jobs::execute_all(pointers, threads);
  for (const jobs::Run& r : runs) {
    Bar b;
    b.scheme = r.scheme;
    b.label = style_of(r.scheme, r.scheme_parameters, r.flip_alpha).label;
    b.failure = r.failure;
    if (!r.rows.empty()) {
      const DiagnosticsRow& last = r.rows.back();
      b.t = last.t, b.total = last.total, b.kinetic = last.kinetic, b.potential = last.potential;
      b.initial = r.rows.front().total;
    }
    bars.push_back(b);
  }
  const auto base = std::filesystem::path(dir) / "scheme_energy";
  {
    std::ofstream csv(base.string() + ".csv");
    csv << "scheme,t,total_energy,kinetic,potential,initial_total,failure\n";
    csv.precision(17);
    for (const Bar& b : bars)
      csv << b.scheme << ',' << b.t << ',' << b.total << ',' << b.kinetic << ',' << b.potential
          << ',' << b.initial << ',' << b.failure << '\n';
    if (!csv) throw cli::UsageError("cannot write " + base.string() + ".csv");
  }
  const int W = kChartW, H = 440;
  char title[160];
  std::snprintf(title, sizeof title,
                "Two-ring collision (Sec. 6.4): total energy at t = %g s, symplectic Euler", t_end);
  render::Image image = canvas.draw(W, H, [&] {
    const float top = heading(canvas, title, float(W));
    draw_bars(bars, ImVec2(10, top + 26), ImVec2(float(W) - 30, float(H) - top - 30));
  });
  render::write_png(image, base.string() + ".png");
  // docs/transfer-schemes.md's table, from the same numbers.
  std::fprintf(stderr,
               "| scheme | total energy at t = %g s [J] | of the initial |\n| --- | --- | --- |\n",
               t_end);
  for (const Bar& b : bars)
    if (b.failure.empty())
      std::fprintf(stderr, "| %s | %.1f | %.1f %% |\n", b.label.c_str(), b.total,
                   100 * b.total / b.initial);
    else  // the blow-up report names the time
      std::fprintf(stderr, "| %s | blew up at t = %.3g s | – |\n", b.label.c_str(), b.t);
}

}  // namespace apiclab::figures
