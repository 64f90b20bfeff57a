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

// A log-log scatter of series (one per spec.series value, or per method for convergence);
// returns the run clicked, or -1.
long scatter_chart(const char* id, ImVec2 size, const sweep::OpenedSweep& sw,
                   const std::vector<sweep::Series>& series, const std::vector<std::size_t>* front,
                   const std::string& title, const std::string& x_label, long open_run) {
  std::vector<PlotSeries> plots;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const sweep::Series& s = series[k];
    const std::string value =
        s.runs.empty() ? s.label : sw.results[s.runs.front()].run->value_text(sw.spec.series);
    const ImU32 color = front ? sweep::series_color(sw.spec, value, k)
                              : render::packed_abgr(render::palette_color(int(k)));
    std::string label = s.label;
    if (!front && std::isfinite(s.slope))
      label += " (slope " + sweep::number_text(s.slope, 3) + ")";
    plots.push_back(sweep::scatter(label, color, s.x, s.y));
  }
  std::vector<double> fx, fy;
  if (front) {
    const std::string& error = sw.spec.errors.front();
    for (std::size_t i : *front) {
      fx.push_back(sw.results[i].cost());
      fy.push_back(sw.results[i].error(error));
    }
    PlotSeries p;
    p.label = "Pareto front";
    p.color = IM_COL32(40, 40, 40, 255);
    p.count = fx.size();
    p.x = [&fx](std::size_t i) { return fx[i]; };
    p.y = [&fy](std::size_t i) { return fy[i]; };
    p.dashed = true;
    p.thickness = 1.4f;
    plots.push_back(p);
  }
  // The run whose panes are live: a larger dark disk drawn first, so its own point sits on it as
  // a ring. Series k of the plot is series k - first of the chart.
  std::vector<double> ox, oy;
  for (const sweep::Series& s : series)
    for (std::size_t i = 0; i < s.runs.size(); ++i)
      if (long(s.runs[i]) == open_run) ox.push_back(s.x[i]), oy.push_back(s.y[i]);
  const std::size_t first = ox.empty() ? 0 : 1;
  if (first) {
    PlotSeries ring = sweep::scatter("open in the panes", IM_COL32(20, 20, 20, 255), ox, oy);
    ring.thickness = 5.0f;
    plots.insert(plots.begin(), ring);
  }
  auto run_of = [&](std::size_t k, std::size_t i) {
    return k < first ? std::size_t(open_run) : series[k - first].runs[i / 2];
  };
  PlotOptions o;
  o.title = title;
  o.x_label = x_label;
  o.y_label = sweep::error_label(sw.spec.errors.front());
  o.log_x = o.log_y = true;
  o.minor_log_grid = true;
  o.legend_corner = PlotOptions::Corner::best;
  o.pick_points = true;
  // Series k's sample 2 i is its run i (the scatter's NaN gaps sit at odd samples).
  o.point_tooltip = [&](std::size_t k, std::size_t i) { run_tooltip(sw, run_of(k, i)); };
  const PlotPick pick = plot(id, size, o, plots);
  if (pick.hit && pick.clicked && pick.series < series.size() + first)
    return long(run_of(pick.series, pick.point));
  return -1;
}

// The stability map as a grid of coloured cells with their text; returns the run clicked or -1.
long stability_map(ImVec2 size, const sweep::OpenedSweep& sw, const sweep::StabilityMap& m,
                   long open_run) {
  long clicked = -1;
  ImGui::BeginChild("stability", size, true, ImGuiWindowFlags_HorizontalScrollbar);
  ImGui::TextUnformatted(("stability map, columns " + m.column_key).c_str());
  ImDrawList* dl = ImGui::GetWindowDrawList();
  float label_w = 0;
  for (const std::string& r : m.row_labels)
    label_w = std::max(label_w, ImGui::CalcTextSize(r.c_str()).x);
  label_w += 12;
  float cell_w = 60;  // as wide as the longest cell text
  for (const auto& row : m.cells)
    for (long i : row)
      if (i >= 0)
        cell_w = std::max(
            cell_w,
            ImGui::CalcTextSize(sweep::cell_text(sw.results[std::size_t(i)]).c_str()).x + 12);
  const float cell_h = ImGui::GetFontSize() + 8;
  const ImU32 ink = IM_COL32(20, 20, 20, 255);
  ImVec2 origin = ImGui::GetCursorScreenPos();
  for (std::size_t c = 0; c < m.column_labels.size(); ++c)
    dl->AddText(ImVec2(origin.x + label_w + cell_w * float(c) + 4, origin.y),
                IM_COL32(90, 90, 90, 255), m.column_labels[c].c_str());
  ImGui::Dummy(ImVec2(label_w + cell_w * float(m.column_labels.size()), cell_h - 4));
  for (std::size_t r = 0; r < m.row_labels.size(); ++r) {
    const ImVec2 p = ImGui::GetCursorScreenPos();
    dl->AddText(ImVec2(p.x, p.y + 4), ink, m.row_labels[r].c_str());
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
      if (i < 0) continue;
      if (hovered || i == open_run) dl->AddRect(a, b, ink, 0, 0, hovered ? 1.5f : 2.5f);
      const std::string t = sweep::cell_text(sw.results[std::size_t(i)]);
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
  for (const char* o : {"completed", "noisy", "not_converged", "blew_up"}) {
    ImGui::ColorButton(o, ImGui::ColorConvertU32ToFloat4(sweep::outcome_color(o)),
                       ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
    ImGui::SameLine();
    ImGui::TextUnformatted(std::string(o) == "completed" ? "stable" : o);
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
  const float w = (avail.x - gap * float(parts - 1)) / float(parts);
  if (c.cost.empty())
    ImGui::Dummy(ImVec2(w, avail.y));  // no run with an error yet
  else
    clicked = std::max(clicked, scatter_chart("cost", ImVec2(w, avail.y), sw, c.cost, &c.front,
                                              "error against cost (" + c.scene + ")",
                                              "cost: wall seconds inside the steps", st.sweep_run));
  if (c.stability) {
    ImGui::SameLine();
    clicked = std::max(clicked, stability_map(ImVec2(w, avail.y), sw, *c.stability, st.sweep_run));
  }
  if (!c.convergence.empty()) {
    ImGui::SameLine();
    clicked = std::max(
        clicked, scatter_chart("convergence", ImVec2(w, avail.y), sw, c.convergence, nullptr,
                               "convergence (" + c.scene + ")", "grid spacing dx", st.sweep_run));
  }
  ImGui::End();
  if (clicked >= 0) open_sweep_run(st, worker, std::size_t(clicked));
  return size.y;
}

}  // namespace apiclab::gui
