// The sweep panel: a sweep folder's charts drawn live with the plot widget (error against cost
// with its Pareto front, the stability map, convergence), as `apiclab sweep` draws them
// (app/sweep/charts.cpp). Hover shows a run's configuration and numbers; a click opens that run
// beside its reference in the panes above.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "app/assets.hpp"
#include "app/gui/plot.hpp"
#include "app/gui/viewer_state.hpp"
#include "app/sweep/charts.hpp"

namespace apiclab::gui {
namespace {

const ImVec4 kError{0.80f, 0.12f, 0.12f, 1};
const ImVec4 kMuted{0.42f, 0.42f, 0.45f, 1};

void run_tooltip(const sweep::OpenedSweep& sw, std::size_t run) {
  ImGui::TextUnformatted(sweep::run_summary(sw, run).c_str());
  ImGui::TextColored(kMuted, "click: open it beside its reference");
}

// The charts' plots of the scene shown, built once per sweep and scene (building reads every
// run's scene for the legends): the same series as the PNGs (app/sweep/charts.cpp).
struct PlotsCache {
  std::shared_ptr<const sweep::OpenedSweep> sweep;  // held, so its address is not reused
  int scene = -1;
  sweep::ChartPlots cost, convergence;
};

const PlotsCache& plots_of(const std::shared_ptr<const sweep::OpenedSweep>& sw, int scene) {
  static PlotsCache cache;
  if (cache.sweep != sw || cache.scene != scene) {
    const std::string& name = sw->charts[std::size_t(scene)].scene;
    cache.sweep = sw;
    cache.scene = scene;
    cache.cost = sweep::cost_plots(sw->spec, sw->results, name, std::nullopt);
    cache.convergence = sweep::convergence_plots(sw->spec, sw->results, name);
  }
  return cache;
}

// A log-log chart of the sweep's plots; hover names the run's configuration, a click returns
// the run (or -1).
long scatter_chart(const char* id, ImVec2 size, const sweep::OpenedSweep& sw,
                   const sweep::ChartPlots& chart, const std::string& title,
                   const std::string& x_label, long open_run) {
  std::vector<PlotSeries> plots = chart.series;
  std::vector<std::vector<long>> runs = chart.runs;
  // The run whose panes are live: a larger dark disk drawn first, so its own point sits on it as
  // a ring.
  std::vector<double> ox, oy;
  for (std::size_t k = 0; k < chart.series.size(); ++k)
    for (std::size_t i = 0; i < chart.runs[k].size(); ++i)
      if (chart.series[k].markers && chart.runs[k][i] == open_run && ox.empty())
        ox.push_back(chart.series[k].x(i)), oy.push_back(chart.series[k].y(i));
  if (!ox.empty()) {
    PlotSeries ring = sweep::scatter("open in the panes", IM_COL32(20, 20, 20, 255), ox, oy);
    ring.thickness = 5.0f;
    plots.insert(plots.begin(), ring);
    runs.insert(runs.begin(), std::vector<long>{open_run, -1L});
  }
  auto run_of = [&](std::size_t k, std::size_t i) {
    return k < runs.size() && i < runs[k].size() ? runs[k][i] : -1L;
  };
  PlotOptions o;
  o.title = title;
  o.x_label = x_label;
  o.y_label = sweep::error_label(sw.spec.errors.front());
  o.log_x = o.log_y = true;
  o.minor_log_grid = true;
  o.pick_points = true;
  o.point_tooltip = [&](std::size_t k, std::size_t i) {
    if (const long r = run_of(k, i); r >= 0)
      run_tooltip(sw, std::size_t(r));
    else
      ImGui::TextUnformatted(plots[k].label.c_str());
  };
  const PlotPick pick = plot(id, size, o, plots);
  if (pick.hit && pick.clicked) return run_of(pick.series, pick.point);
  return -1;
}

// `text`, or as much of it as fits in `width` pixels followed by "...".
std::string cut_to(const std::string& text, float width) {
  if (ImGui::CalcTextSize(text.c_str()).x <= width) return text;
  std::string cut = text;
  while (!cut.empty() && ImGui::CalcTextSize((cut + "...").c_str()).x > width) cut.pop_back();
  return cut + "...";
}

// A cell's text in `width` pixels: whole, or its number alone ("0.19" of "noisy 0.19", the
// colour saying the outcome), or nothing.
std::string cell_fit(const std::string& text, float width) {
  if (ImGui::CalcTextSize(text.c_str()).x <= width) return text;
  const std::string tail = text.substr(text.find_last_of(' ') + 1);
  return ImGui::CalcTextSize(tail.c_str()).x <= width ? tail : "";
}

// The stability map's row-label and cell widths: as wide as their longest text.
struct MapWidths {
  float label = 0, cell = 60;
  float total(std::size_t columns) const { return label + cell * float(columns) + 16; }
};
MapWidths natural_widths(const sweep::OpenedSweep& sw, const sweep::StabilityMap& m) {
  MapWidths w;
  for (const std::string& r : m.row_labels)
    w.label = std::max(w.label, ImGui::CalcTextSize(r.c_str()).x);
  w.label += 12;
  for (const std::string& c : m.column_labels)
    w.cell = std::max(w.cell, ImGui::CalcTextSize(c.c_str()).x + 12);
  for (const auto& row : m.cells)
    for (long i : row)
      if (i >= 0)
        w.cell = std::max(
            w.cell,
            ImGui::CalcTextSize(sweep::cell_text(sw.results[std::size_t(i)]).c_str()).x + 12);
  return w;
}

// The stability map as a grid of coloured cells with their text, every column inside `size`:
// where the texts are wider than the room, cells and row labels are narrowed and their texts
// cut with "..." (hover shows the run whole). Returns the run clicked or -1.
long stability_map(ViewerState& st, ImVec2 size, const sweep::OpenedSweep& sw,
                   const sweep::StabilityMap& m, long open_run) {
  long clicked = -1;
  const ImVec2 child_at = ImGui::GetCursorScreenPos();
  ImGui::BeginChild("stability", size, true);
  ImGui::TextUnformatted(("stability map, columns " + m.column_key).c_str());
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const std::size_t columns = std::max<std::size_t>(m.column_labels.size(), 1);
  MapWidths natural = natural_widths(sw, m);
  const float room = ImGui::GetContentRegionAvail().x;
  float label_w = std::min(natural.label, 0.4f * room);
  const float cell_w = std::min(natural.cell, (room - label_w) / float(columns));
  if (cell_w * float(columns) + label_w < room && label_w < natural.label)
    label_w = std::min(natural.label, room - cell_w * float(columns));
  const float cell_h = ImGui::GetFontSize() + 8;
  const ImU32 ink = IM_COL32(20, 20, 20, 255);
  ImVec2 origin = ImGui::GetCursorScreenPos();
  for (std::size_t c = 0; c < m.column_labels.size(); ++c) {
    const ImVec2 at(origin.x + label_w + cell_w * float(c), origin.y);
    dl->AddText(ImVec2(at.x + 4, at.y), IM_COL32(90, 90, 90, 255),
                cut_to(m.column_labels[c], cell_w - 8).c_str());
    st.layout["stability column " + std::to_string(c)] = ImVec4(at.x, at.y, cell_w - 2, cell_h);
  }
  st.layout["stability map"] = ImVec4(child_at.x, child_at.y, size.x, size.y);
  ImGui::Dummy(ImVec2(label_w + cell_w * float(m.column_labels.size()), cell_h - 4));
  for (std::size_t r = 0; r < m.row_labels.size(); ++r) {
    const ImVec2 p = ImGui::GetCursorScreenPos();
    dl->AddText(ImVec2(p.x, p.y + 4), ink, cut_to(m.row_labels[r], label_w - 8).c_str());
    for (std::size_t c = 0; c < m.column_labels.size(); ++c) {
      const long i = m.cells[r][c];
      const ImVec2 a(p.x + label_w + cell_w * float(c), p.y), b(a.x + cell_w - 2, a.y + cell_h - 2);
      ImGui::SetCursorScreenPos(a);
      ImGui::PushID(int(r * m.column_labels.size() + c));
      ImGui::InvisibleButton("cell", ImVec2(cell_w - 2, cell_h - 2));
      ImGui::PopID();
      const bool hovered = ImGui::IsItemHovered();
      dl->AddRectFilled(a, b,
                        sweep::outcome_color(i < 0 ? "" : sw.results[std::size_t(i)].outcome));
      if (i < 0) {
        dl->AddText(ImVec2(a.x + 4, a.y + 3), IM_COL32(120, 120, 120, 255),
                    cell_fit("excluded", cell_w - 8).c_str());
        continue;
      }
      if (hovered || i == open_run) dl->AddRect(a, b, ink, 0, 0, hovered ? 1.5f : 2.5f);
      const std::string t = cell_fit(sweep::cell_text(sw.results[std::size_t(i)]), cell_w - 8);
      dl->AddText(ImVec2(a.x + 4, a.y + 3), ink, t.c_str());
      if (hovered) {
        ImGui::BeginTooltip();
        run_tooltip(sw, std::size_t(i));
        ImGui::EndTooltip();
        if (ImGui::IsItemClicked(ImGuiMouseButton_Left)) clicked = i;
      }
    }
    ImGui::SetCursorScreenPos(ImVec2(p.x, p.y + cell_h));
  }
  ImGui::Dummy(ImVec2(1, 4));
  std::vector<std::string> legend = {"completed", "noisy", "not_converged", "blew_up"};
  for (const std::string o : {"refused", "no_result", ""})  // the kinds this map has
    for (const auto& row : m.cells)
      for (long i : row)
        if ((i < 0 ? "" : sw.results[std::size_t(i)].outcome) == o &&
            std::find(legend.begin(), legend.end(), o) == legend.end())
          legend.push_back(o);
  for (const std::string& o : legend) {
    ImGui::ColorButton(("##" + o).c_str(), ImGui::ColorConvertU32ToFloat4(sweep::outcome_color(o)),
                       ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
    ImGui::SameLine();
    ImGui::TextUnformatted(o == "completed" ? "stable" : sweep::outcome_legend(o).c_str());
    ImGui::SameLine();
  }
  ImGui::NewLine();
  ImGui::EndChild();
  return clicked;
}

}  // namespace

void show_sweep(ViewerState& st, SimWorker& worker,
                std::shared_ptr<const sweep::OpenedSweep> sweep) {
  st.sweep = std::move(sweep);
  st.sweep_error.clear();
  st.sweep_scene = 0;
  st.sweep_plots = false;
  st.sweep_run = -1;
  open_sweep_run(st, worker, st.sweep->plan.runs.front().reference);
}

bool open_sweep_folder(ViewerState& st, SimWorker& worker, const std::string& dir) {
  try {
    show_sweep(st, worker, sweep::open_sweep(dir));
    return true;
  } catch (const std::exception& e) {
    st.sweep_error = e.what();
    return false;
  }
}

void open_sweep_run(ViewerState& st, SimWorker& worker, std::size_t run) {
  try {
    sweep::SweepLaunch l = sweep::launch_run(*st.sweep, run);
    st.scene = std::move(l.scene);
    st.scene_path = st.sweep->plan.runs[l.reference].scene_path;
    st.scene_loaded = true;
    st.load_error.clear();
    st.panes = std::move(l.panes);
    st.precision = l.precision;
    st.sweep_run = long(run);
    st.notice = run == l.reference ? "sweep: the reference run, from t = 0"
                                   : "sweep: the run beside its reference, from t = 0";
    restart(st, worker);
    worker.play(true);
  } catch (const std::exception& e) {
    st.sweep_error = e.what();
  }
}

float draw_sweep_panel(ViewerState& st, SimWorker& worker, ImVec2 pos, ImVec2 size) {
  const sweep::OpenedSweep& sw = *st.sweep;
  ImGui::SetNextWindowPos(pos);
  ImGui::SetNextWindowSize(
      ImVec2(size.x, st.sweep_plots ? ImGui::GetFrameHeightWithSpacing() + 12 : size.y));
  ImGui::Begin("Sweep", nullptr,
               ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoBringToFrontOnFocus);
  ImGui::AlignTextToFramePadding();
  ImGui::Text("Sweep %s: %zu runs", sw.spec.name.c_str(), sw.results.size());
  if (sw.missing) {
    ImGui::SameLine();
    ImGui::TextColored(kError, "(%zu without a result yet)", sw.missing);
  }
  if (const auto refused = std::count_if(sw.results.begin(), sw.results.end(),
                                         [](const auto& r) { return r.outcome == "refused"; })) {
    ImGui::SameLine();
    ImGui::TextColored(kError, "(%ld refused)", long(refused));
  }
  st.sweep_scene = std::clamp(st.sweep_scene, 0, int(sw.charts.size()) - 1);
  const sweep::SceneCharts& c = sw.charts[std::size_t(st.sweep_scene)];
  if (sw.charts.size() > 1) {
    ImGui::SameLine();
    ImGui::SetNextItemWidth(180);
    if (ImGui::BeginCombo("##sweep_scene", c.scene.c_str())) {
      for (std::size_t k = 0; k < sw.charts.size(); ++k)
        if (ImGui::Selectable(sw.charts[k].scene.c_str(), int(k) == st.sweep_scene))
          st.sweep_scene = int(k);
      ImGui::EndCombo();
    }
  }
  ImGui::SameLine();
  ImGui::Checkbox("live plots instead", &st.sweep_plots);
  ImGui::SameLine();
  ImGui::TextColored(kMuted, "hover a point or a cell for its run; click to open it");
  const float header = ImGui::GetCursorPosY();
  if (st.sweep_plots) {
    ImGui::End();
    return header;
  }
  long clicked = -1;
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float gap = ImGui::GetStyle().ItemSpacing.x;
  const int parts = 1 + (c.stability != nullptr) + !c.convergence.empty();
  float w = (avail.x - gap * float(parts - 1)) / float(parts);
  // The stability map takes the width its columns need, up to 45 % of the panel; beyond that
  // its cells' texts are cut (hovering a cell shows its run whole).
  float map_w = w;
  if (c.stability && parts > 1) {
    const float charts_room = avail.x - gap * float(parts - 1);
    map_w = std::clamp(natural_widths(sw, *c.stability).total(c.stability->column_labels.size()), w,
                       std::max(w, 0.45f * charts_room));
    w = (charts_room - map_w) / float(parts - 1);
  }
  const PlotsCache& plots = plots_of(st.sweep, st.sweep_scene);
  if (plots.cost.series.empty())
    ImGui::Dummy(ImVec2(w, avail.y));  // no run with an error yet
  else
    clicked = std::max(clicked, scatter_chart("cost", ImVec2(w, avail.y), sw, plots.cost,
                                              "error against cost (" + c.scene + ")",
                                              "cost: wall seconds inside the steps", st.sweep_run));
  if (c.stability) {
    ImGui::SameLine();
    clicked = std::max(clicked,
                       stability_map(st, ImVec2(map_w, avail.y), sw, *c.stability, st.sweep_run));
  }
  if (!c.convergence.empty()) {
    ImGui::SameLine();
    clicked = std::max(
        clicked, scatter_chart("convergence", ImVec2(w, avail.y), sw, plots.convergence,
                               "convergence (" + c.scene + ")", "grid spacing dx", st.sweep_run));
  }
  ImGui::End();
  if (clicked >= 0) open_sweep_run(st, worker, std::size_t(clicked));
  return size.y;
}

}  // namespace apiclab::gui
