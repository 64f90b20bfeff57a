// Live plots under the panes: energy, linear and angular momentum, and relative drift on a
// log axis. One pane: every component; several: one series per pane, component picked above.
// One pane with the conservation ledger (solver.ledger): its energy by stage instead of the drift.
#include <array>
#include <cmath>

#include "app/drift_series.hpp"
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

// A series over a computed vector (the drift plot, app/drift_series.hpp).
PlotSeries series_of(std::shared_ptr<const DriftPlot> d, const std::vector<double>& y,
                     std::string label, ImU32 color) {
  PlotSeries s;
  s.label = std::move(label);
  s.color = color;
  s.count = y.size();
  s.x = [d](std::size_t i) { return d->t[i]; };
  s.y = [d, &y](std::size_t i) { return y[i]; };
  return s;
}

// A legend entry without samples: a pane's colour, or a quantity's stroke.
PlotSeries legend_only(std::string label, ImU32 color, bool dashed) {
  PlotSeries s;
  s.label = std::move(label);
  s.color = color;
  s.dashed = dashed;
  return s;
}

constexpr ImU32 kStroke = IM_COL32(90, 90, 90, 255);

// The ledger's energy changes since t = 0, stacked: line k is the sum of stages 0..k, so the
// band between lines k − 1 and k is stage k's share and the top line is E(t) − E(0)
// (docs/outputs.md, Conservation ledger).
std::vector<PlotSeries> ledger_stack(const History& h) {
  using Sums = std::array<double, ledger_stage_count>;
  auto stacked = std::make_shared<std::vector<Sums>>(h.size());
  Sums running{};
  for (std::size_t i = 0; i < h.size(); ++i) {
    double below = 0;
    for (int s = 0; s < ledger_stage_count; ++s) {
      running[std::size_t(s)] += h[i].stages[std::size_t(s)].energy;
      below += running[std::size_t(s)];
      (*stacked)[i][std::size_t(s)] = below;
    }
  }
  std::vector<PlotSeries> out;
  for (int s = 0; s < ledger_stage_count; ++s) {
    PlotSeries l;
    l.label = std::string(s == 0 ? "" : "+ ") + ledger_stage_name(LedgerStage(s));
    l.color = render::packed_abgr(render::palette_color(s));
    l.count = h.size();
    l.x = [&h](std::size_t i) { return h[i].t; };
    l.y = [stacked, s](std::size_t i) { return (*stacked)[i][std::size_t(s)]; };
    out.push_back(std::move(l));
  }
  return out;
}

// A plot's data box and legend band, for the layout tests (ViewerState::layout).
void record_plot(ViewerState& st, const std::string& name, const PlotPick& p) {
  st.layout["plot " + name + " box"] =
      ImVec4(p.box_min.x, p.box_min.y, p.box_max.x - p.box_min.x, p.box_max.y - p.box_min.y);
  if (p.legend_max.y > p.legend_min.y)
    st.layout["plot " + name + " legend"] =
        ImVec4(p.legend_min.x, p.legend_min.y, p.legend_max.x - p.legend_min.x,
               p.legend_max.y - p.legend_min.y);
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
  std::string drift_title = "relative drift (log)";
  std::vector<PlotSeries> drift_legend;  // several panes: pane names, then the two strokes
  std::string energy_label, momentum_label;
  const char* ek[3] = {"kinetic", "potential", "total"};
  for (std::size_t k = 0; k < pub.panes.size(); ++k) {
    const History& h = pub.panes[k].history;
    if (h.empty()) continue;
    const std::string name = pane_label(pub.panes[k]);
    // Run's rule (sim/measure/run_summary.hpp), round-off momenta as zero (app/drift_series.hpp).
    const auto row = [&h](std::size_t i) -> const DiagnosticsRow& { return h[i]; };
    const MomentumRoundOff round_off =
        pub.scene ? momentum_round_off(row, h.size(), pub.panes[k].total_mass,
                                       DriftRule::domain_extent(*pub.scene))
                  : MomentumRoundOff{};
    auto d = std::make_shared<const DriftPlot>(
        drift_plot(*pub.panes[k].drift, row, h.size(), round_off.L));
    drift_title = d->title;
    auto energy_of = [](const DiagnosticsRow& r, int c) {
      return c == 0 ? r.kinetic : c == 1 ? r.potential : r.total;
    };
    const auto p_of = [p0 = round_off.p](const DiagnosticsRow& r, int c) {
      return plotted_momentum(r.p[c], p0);
    };
    const auto L_of = [L0 = round_off.L](const DiagnosticsRow& r, int c) {
      return plotted_momentum(r.L[c], L0);
    };
    if (!multi) {
      for (int c = 0; c < 3; ++c)
        energy.push_back(series_of(h, std::string(ek[c]) + " [J]", kComponent[c],
                                   [=](const DiagnosticsRow& r) { return energy_of(r, c); }));
      for (int c = 0; c < dim; ++c)
        momentum.push_back(series_of(h, std::string("p_") + kAxes[c] + " [kg m/s]", kComponent[c],
                                     [=](const DiagnosticsRow& r) { return p_of(r, c); }));
      for (int c = dim == 2 ? 2 : 0; c < 3; ++c)
        angular.push_back(series_of(h, std::string("L_") + kAxes[c] + " [kg m^2/s]", kComponent[c],
                                    [=](const DiagnosticsRow& r) { return L_of(r, c); }));
      drift.push_back(series_of(d, d->energy, d->energy_label, kComponent[0]));
      drift.push_back(series_of(d, d->momentum, d->momentum_label, kComponent[1]));
      continue;
    }
    const ImU32 col = pane_color(k);
    const int ec = st.energy_component, pc = std::min(st.momentum_component, dim - 1),
              ac = st.angular_component;
    energy.push_back(
        series_of(h, name, col, [=](const DiagnosticsRow& r) { return energy_of(r, ec); }));
    momentum.push_back(
        series_of(h, name, col, [=](const DiagnosticsRow& r) { return p_of(r, pc); }));
    angular.push_back(
        series_of(h, name, col, [=](const DiagnosticsRow& r) { return L_of(r, ac); }));
    // The legend names each pane once, and each quantity once by its stroke (below).
    drift.push_back(series_of(d, d->energy, "", col));
    PlotSeries l = series_of(d, d->momentum, "", col);
    l.dashed = true;  // the second quantity in the pane's colour
    drift.push_back(std::move(l));
    drift_legend.push_back(legend_only(name, col, false));
    energy_label = d->energy_label, momentum_label = d->momentum_label;
  }
  if (multi && !drift_legend.empty()) {
    drift_legend.push_back(legend_only(energy_label, kStroke, false));
    drift_legend.push_back(legend_only(momentum_label, kStroke, true));
    drift.insert(drift.begin(), drift_legend.begin(), drift_legend.end());
  }
  PlotOptions o;
  o.title = multi ? std::string(ek[st.energy_component]) + " energy [J]" : "energy [J]";
  record_plot(st, "energy", plot("energy", cell, o, energy));
  ImGui::SameLine();
  o.title = multi ? std::string("linear momentum p_") +
                        kAxes[std::min(st.momentum_component, dim - 1)] + " [kg m/s]"
                  : "linear momentum [kg m/s]";
  record_plot(st, "momentum", plot("momentum", cell, o, momentum));
  ImGui::SameLine();
  o.title = std::string("angular momentum ") +
            (multi || dim == 2 ? std::string("L_") + kAxes[st.angular_component] : "") +
            " [kg m^2/s]";
  record_plot(st, "angular", plot("angular", cell, o, angular));
  ImGui::SameLine();
  if (!multi && !pub.panes.empty() && !pub.panes[0].history.empty() &&
      pub.panes[0].history.back().ledger) {
    o.title = "energy change by stage, stacked [J]";
    record_plot(st, "ledger", plot("ledger", cell, o, ledger_stack(pub.panes[0].history)));
  } else {
    o.title = drift_title;
    o.log_y = true;
    record_plot(st, "drift", plot("drift", cell, o, drift));
  }
  ImGui::End();
}

}  // namespace apiclab::gui
