// Live plots under the panes: energy, linear and angular momentum, and relative drift on a
// log axis. One pane: every component; several: one series per pane, component picked above.
#include <cmath>

#include "app/gui/plot.hpp"
#include "app/gui/viewer_state.hpp"
#include "render/palette.hpp"

namespace apiclab::gui {
namespace {

// x, y, z (or kinetic, potential, total): the palette's first three colours.
constexpr ImU32 kComponent[3] = {render::packed_abgr(render::palette_color(0)),
                                 render::packed_abgr(render::palette_color(1)),
                                 render::packed_abgr(render::palette_color(2))};
const char* kAxes[3] = {"x", "y", "z"};

PlotSeries series_of(const History& h, std::string label, ImU32 color,
                     std::function<double(const DiagnosticsRow&)> f) {
  PlotSeries s;
  s.label = std::move(label);
  s.color = color;
  s.count = h.size();
  s.x = [&h](std::size_t i) { return h[i].t; };
  s.y = [&h, f = std::move(f)](std::size_t i) { return f(h[i]); };
  return s;
}

}  // namespace

void draw_plots(ViewerState& st, const Published& pub, ImVec2 pos, ImVec2 size) {
  ImGui::SetNextWindowPos(pos);
  ImGui::SetNextWindowSize(size);
  ImGui::Begin("Plots", nullptr,
               ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoBringToFrontOnFocus);
  const bool multi = pub.panes.size() > 1;
  const int dim = pub.scene ? pub.scene->dim : 2;
  if (multi) {  // component pickers for the shared plots
    const float w = ImGui::GetContentRegionAvail().x / 4;
    ImGui::SetNextItemWidth(w * 0.5f);
    ImGui::Combo("energy##c", &st.energy_component, "kinetic\0potential\0total\0");
    ImGui::SameLine(w);
    ImGui::SetNextItemWidth(w * 0.5f);
    ImGui::Combo("momentum##c", &st.momentum_component,
                 dim == 3 ? "p_x\0p_y\0p_z\0" : "p_x\0p_y\0");
    if (dim == 3) {
      ImGui::SameLine(2 * w);
      ImGui::SetNextItemWidth(w * 0.5f);
      ImGui::Combo("angular momentum##c", &st.angular_component, "L_x\0L_y\0L_z\0");
    }
  }
  if (dim == 2) st.angular_component = 2;
  const float spacing = ImGui::GetStyle().ItemSpacing.x;
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const ImVec2 cell((avail.x - 3 * spacing) / 4, avail.y);

  std::vector<PlotSeries> energy, momentum, angular, drift;
  const char* ek[3] = {"kinetic", "potential", "total"};
  for (std::size_t k = 0; k < pub.panes.size(); ++k) {
    const History& h = pub.panes[k].history;
    if (h.empty()) continue;
    const std::string name = pane_label(pub.panes[k]);
    const DriftRule drift_rule = *pub.panes[k].drift;  // run's rule (sim/run_summary.hpp)
    const auto dE = [=](const DiagnosticsRow& r) { return std::abs(drift_rule.energy(r)); };
    const auto dL = [=](const DiagnosticsRow& r) { return drift_rule.angular_momentum(r); };
    const char* dL_label = drift_rule.angular_momentum_relative() ? "|dL|/|L0|" : "|dL| (L0 = 0)";
    auto energy_of = [](const DiagnosticsRow& r, int c) {
      return c == 0 ? r.kinetic : c == 1 ? r.potential : r.total;
    };
    if (!multi) {
      for (int c = 0; c < 3; ++c)
        energy.push_back(series_of(h, ek[c], kComponent[c],
                                   [=](const DiagnosticsRow& r) { return energy_of(r, c); }));
      for (int c = 0; c < dim; ++c)
        momentum.push_back(series_of(h, std::string("p_") + kAxes[c], kComponent[c],
                                     [=](const DiagnosticsRow& r) { return r.p[c]; }));
      for (int c = dim == 2 ? 2 : 0; c < 3; ++c)
        angular.push_back(series_of(h, std::string("L_") + kAxes[c], kComponent[c],
                                    [=](const DiagnosticsRow& r) { return r.L[c]; }));
      drift.push_back(series_of(h, "|dE|/|E0|", kComponent[0], dE));
      drift.push_back(series_of(h, dL_label, kComponent[1], dL));
      continue;
    }
    const ImU32 col = pane_color(k);
    const int ec = st.energy_component, pc = std::min(st.momentum_component, dim - 1),
              ac = st.angular_component;
    energy.push_back(
        series_of(h, name, col, [=](const DiagnosticsRow& r) { return energy_of(r, ec); }));
    momentum.push_back(series_of(h, name, col, [=](const DiagnosticsRow& r) { return r.p[pc]; }));
    angular.push_back(series_of(h, name, col, [=](const DiagnosticsRow& r) { return r.L[ac]; }));
    drift.push_back(series_of(h, name + " E", col, dE));
    PlotSeries l = series_of(h, name + " L", (col & 0x00FFFFFF) | (IM_COL32(0, 0, 0, 120)), dL);
    l.thickness = 1.2f;
    drift.push_back(std::move(l));
  }
  PlotOptions o;
  o.title = multi ? std::string(ek[st.energy_component]) + " energy [J]" : "energy [J]";
  plot("energy", cell, o, energy);
  ImGui::SameLine();
  o.title = multi ? std::string("linear momentum p_") +
                        kAxes[std::min(st.momentum_component, dim - 1)] + " [kg m/s]"
                  : "linear momentum [kg m/s]";
  plot("momentum", cell, o, momentum);
  ImGui::SameLine();
  o.title = std::string("angular momentum ") +
            (multi || dim == 2 ? std::string("L_") + kAxes[st.angular_component] : "") +
            " [kg m^2/s]";
  plot("angular", cell, o, angular);
  ImGui::SameLine();
  o.title = "relative drift |dE|/|E0|, |dL|/|L0| (log)";
  o.log_y = true;
  plot("drift", cell, o, drift);
  ImGui::End();
}

}  // namespace apiclab::gui
