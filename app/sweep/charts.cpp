#include "app/sweep/charts.hpp"

#include <imgui.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

#include "app/figures/chart_canvas.hpp"
#include "app/figures/chart_style.hpp"
#include "app/gui/plot.hpp"
#include "app/output_file.hpp"
#include "app/sweep/tables.hpp"
#include "render/image.hpp"
#include "render/palette.hpp"
#include "sim/mpm/schemes/scheme_label.hpp"

namespace apiclab::sweep {
namespace fs = std::filesystem;
using figures::ChartCanvas;

// A series' legend with its scheme's parameter, "xpic" -> "xpic(2)"
// (sim/mpm/schemes/scheme_label.hpp), read from the scenes its runs simulated. Unchanged when they
// name no scheme with a parameter or disagree (another axis varies the parameter, and names it in
// the label itself).
std::string legend_label(const Series& s, const std::vector<RunResult>& results) {
  std::string key, named;
  for (std::size_t i : s.runs) {
    SceneDesc scene;
    try {
      scene = scene_of(*results[i].run);
    } catch (const std::exception&) {
      return s.label;
    }
    if (scene.solver.method != "mpm") return s.label;
    const std::string n = run_label(scene);
    if (!named.empty() && n != named) return s.label;
    named = n, key = std::string(key_of(scene.solver.scheme));
  }
  if (named.empty() || named == key) return s.label;
  if (s.label == key) return named;          // the series axis is the scheme
  const std::string part = "scheme=" + key;  // or one of the axes in "scheme=xpic, kernel=..."
  const std::size_t at = s.label.find(part), end = at + part.size();
  if (at == std::string::npos || (end < s.label.size() && s.label[end] != ',')) return s.label;
  return s.label.substr(0, at) + "scheme=" + named + s.label.substr(end);
}

ImU32 series_color(const Spec& spec, const std::string& value, std::size_t k) {
  if (spec.series == "solver.scheme") return figures::style_of(value).color;
  return render::packed_abgr(render::palette_color(int(k)));
}

// A scatter through the line plot: a NaN between points breaks the line, markers stay.
gui::PlotSeries scatter(const std::string& label, ImU32 color, const std::vector<double>& x,
                        const std::vector<double>& y) {
  gui::PlotSeries s;
  s.label = label;
  s.color = color;
  s.count = 2 * x.size();
  s.x = [&x](std::size_t i) { return x[i / 2]; };
  s.y = [&y](std::size_t i) { return i % 2 ? std::numeric_limits<double>::quiet_NaN() : y[i / 2]; };
  s.markers = true;
  s.thickness = 2.0f;
  return s;
}

std::string error_label(const std::string& error) {
  if (error == "displacement") return "displacement error ||u - u_ref|| / ||u_ref||";
  if (error == "com") return "centre-of-mass error / body radius";
  if (error == "kinetic") return "kinetic energy error (rel. L2)";
  if (error == "elastic") return "elastic energy error (rel. L2)";
  if (error == "energy") return "max |dE|/E0";
  if (error == "rigid") return "distance to rigid rotation ||u - u_rigid|| / ||u_rigid||";
  return "max |dL|/|L0|";
}

ImU32 outcome_color(const std::string& outcome) {
  if (outcome == "completed") return IM_COL32(150, 210, 150, 255);
  if (outcome == "noisy") return IM_COL32(245, 200, 90, 255);
  if (outcome == "not_converged") return IM_COL32(185, 160, 220, 255);
  if (outcome == "blew_up") return IM_COL32(230, 110, 100, 255);
  if (outcome == "refused") return IM_COL32(120, 180, 235, 255);
  if (outcome == "no_result") return IM_COL32(200, 200, 200, 255);
  return IM_COL32(242, 242, 242, 255);  // no run: the configuration is excluded
}

std::string outcome_legend(const std::string& outcome) {
  if (outcome == "completed") return "stable (dE: final energy change)";
  if (outcome == "not_converged") return "not converged";
  if (outcome == "blew_up") return "blew up";
  if (outcome == "refused") return "refused (no record; exit status)";
  if (outcome == "no_result") return "no result yet";
  if (outcome.empty()) return "excluded";
  return outcome;
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// A scatter over vectors it keeps: sample 2 i is point i, the odd samples NaN gaps.
gui::PlotSeries owned_scatter(const std::string& label, ImU32 color, std::vector<double> x,
                              std::vector<double> y) {
  auto px = std::make_shared<const std::vector<double>>(std::move(x));
  auto py = std::make_shared<const std::vector<double>>(std::move(y));
  gui::PlotSeries s = scatter(label, color, *px, *py);
  s.x = [px](std::size_t i) { return (*px)[i / 2]; };
  s.y = [py](std::size_t i) { return i % 2 ? kNaN : (*py)[i / 2]; };
  return s;
}

// A legend entry without samples: a marker shape, a dashed line or only text.
gui::PlotSeries legend_entry(const std::string& label, ImU32 color, bool marker,
                             gui::Marker shape = gui::Marker::circle) {
  gui::PlotSeries s;
  s.label = label;
  s.color = color;
  s.markers = marker;
  s.marker = shape;
  s.thickness = 0;
  return s;
}

gui::Marker shape_of(std::size_t k) { return gui::Marker(int(k % gui::kMarkerShapes)); }

}  // namespace

ChartPlots cost_plots(const Spec& spec, const std::vector<RunResult>& results,
                      const std::string& scene, std::optional<double> target_error) {
  ChartPlots c;
  const std::string& error = spec.errors.front();
  const auto series = cost_series(spec, results, error, scene);
  const Marking mark = marking(spec, results, scene, {spec.series}, gui::kMarkerShapes);
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = 0, y_hi = 0;
  for (const Series& s : series)
    for (std::size_t k = 0; k < s.x.size(); ++k)
      x_lo = std::min(x_lo, s.x[k]), x_hi = std::max(x_hi, s.x[k]), y_hi = std::max(y_hi, s.y[k]);
  // Runs without an error: blew up (their cost up to the blow-up) or refused (no cost either).
  std::vector<std::size_t> blew, refused;
  for (std::size_t i = 0; i < results.size(); ++i) {
    if (results[i].run->value_text("scene") != scene) continue;
    if (results[i].outcome == "blew_up") blew.push_back(i);
    if (results[i].outcome == "refused") refused.push_back(i);
  }
  std::sort(blew.begin(), blew.end(),
            [&](auto a, auto b) { return results[a].cost() < results[b].cost(); });
  for (std::size_t i : blew)
    if (results[i].cost() > 0)
      x_lo = std::min(x_lo, results[i].cost()), x_hi = std::max(x_hi, results[i].cost());
  if (!(x_hi > 0)) x_lo = 1e-3, x_hi = 1;
  if (target_error) y_hi = std::max(y_hi, *target_error);
  c.edge = y_hi > 0 ? 3 * y_hi : 1;  // half a decade above every point
  auto add = [&](gui::PlotSeries p, std::vector<long> runs) {
    c.series.push_back(std::move(p));
    c.runs.push_back(std::move(runs));
  };
  auto sample_runs = [](const std::vector<std::size_t>& runs) {
    std::vector<long> out;
    for (std::size_t i : runs) out.push_back(long(i)), out.push_back(-1);
    return out;
  };
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    const std::string value = results[s.runs.front()].run->value_text(spec.series);
    gui::PlotSeries p =
        owned_scatter(legend_label(s, results), series_color(spec, value, k), s.x, s.y);
    const std::vector<std::size_t> runs = s.runs;
    p.marker_of = [runs, mark, &results](std::size_t i) {
      return shape_of(mark.shape(*results[runs[i / 2]].run));
    };
    if (!mark.label_keys.empty())
      p.point_label = [runs, mark, &results](std::size_t i) {
        return mark.label(*results[runs[i / 2]].run);
      };
    add(std::move(p), sample_runs(s.runs));
  }
  // Failed runs, ringed or at the top edge in their outcome's colour.
  std::vector<std::size_t> unconverged;
  std::vector<double> ux, uy, bx, by, rx, ry;
  for (const Series& s : series)
    for (std::size_t k = 0; k < s.runs.size(); ++k)
      if (results[s.runs[k]].outcome == "not_converged") {
        unconverged.push_back(s.runs[k]);
        ux.push_back(s.x[k]);
        uy.push_back(s.y[k]);
      }
  if (!unconverged.empty()) {
    gui::PlotSeries p =
        owned_scatter("not converged (ringed)", outcome_color("not_converged"), ux, uy);
    p.marker = gui::Marker::ring;
    p.thickness = 4.0f;
    add(std::move(p), sample_runs(unconverged));
  }
  for (std::size_t i : blew) {
    bx.push_back(results[i].cost() > 0 ? results[i].cost() : x_lo);
    by.push_back(c.edge);
  }
  if (!blew.empty()) {
    gui::PlotSeries p =
        owned_scatter("blew up: no error, at the top edge (" + std::to_string(blew.size()) + ")",
                      IM_COL32(200, 40, 30, 255), bx, by);
    p.marker = gui::Marker::cross;
    add(std::move(p), sample_runs(blew));
  }
  for (std::size_t k = 0; k < refused.size(); ++k) rx.push_back(x_lo), ry.push_back(c.edge);
  if (!refused.empty()) {
    gui::PlotSeries p = owned_scatter(
        "refused: no cost, no error, top left (" + std::to_string(refused.size()) + ")",
        outcome_color("refused"), rx, ry);
    p.marker = gui::Marker::square;
    add(std::move(p), sample_runs(refused));
  }
  const auto front = pareto_front(results, error, scene);
  if (!front.empty()) {
    std::vector<double> fx, fy;
    for (std::size_t i : front)
      fx.push_back(results[i].cost()), fy.push_back(results[i].error(error));
    gui::PlotSeries p;
    p.label = "Pareto front";
    p.color = IM_COL32(40, 40, 40, 255);
    p.count = fx.size();
    auto px = std::make_shared<const std::vector<double>>(fx);
    auto py = std::make_shared<const std::vector<double>>(fy);
    p.x = [px](std::size_t i) { return (*px)[i]; };
    p.y = [py](std::size_t i) { return (*py)[i]; };
    p.dashed = true;
    p.thickness = 1.4f;
    std::vector<long> runs(front.begin(), front.end());
    add(std::move(p), std::move(runs));
  }
  if (target_error) {
    gui::PlotSeries p;
    p.label = "target error " + number_text(*target_error, 3);
    p.color = IM_COL32(200, 40, 30, 255);
    p.count = 2;
    const double lo = x_lo / 1.5, hi = x_hi * 1.5, y = *target_error;  // past every point
    p.x = [lo, hi](std::size_t i) { return i ? hi : lo; };
    p.y = [y](std::size_t) { return y; };
    p.dashed = true;
    p.thickness = 1.2f;
    add(std::move(p), {-1, -1});
  }
  if (mark.shapes.size() > 1)
    for (std::size_t k = 0; k < mark.shapes.size(); ++k)
      add(legend_entry(mark.shapes[k], IM_COL32(90, 90, 90, 255), true, shape_of(k)), {});
  if (!mark.label_keys.empty()) {
    std::string keys;
    for (const std::string& key : mark.label_keys) keys += (keys.empty() ? "" : "/") + key;
    add(legend_entry("beside each point: " + keys, IM_COL32(90, 90, 90, 255), false), {});
  }
  return c;
}

ChartPlots convergence_plots(const Spec& spec, const std::vector<RunResult>& results,
                             const std::string& scene) {
  ChartPlots c;
  const std::string& error = spec.errors.front();
  const auto series = convergence_series(spec, results, error, scene);
  const std::vector<std::string> keys = distinguishing_axes(spec, {"resolution"});
  const bool by_series =
      std::find(keys.begin(), keys.end(), spec.series) != keys.end() && spec.series != "resolution";
  const Marking mark =
      marking(spec, results, scene, {"resolution", spec.series}, gui::kMarkerShapes);
  std::vector<std::string> values;  // the series axis's values, in order, for their colours
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    const PlannedRun& first = *results[s.runs.front()].run;
    const std::string value = first.value_text(spec.series);
    if (std::find(values.begin(), values.end(), value) == values.end()) values.push_back(value);
    const std::size_t v =
        std::size_t(std::find(values.begin(), values.end(), value) - values.begin());
    const std::string name = legend_label(s, results);
    char label[240];
    if (std::isfinite(s.slope))
      std::snprintf(label, sizeof label, "%s (slope %.2f)", name.c_str(), s.slope);
    else  // one resolution: no slope to fit
      std::snprintf(label, sizeof label, "%s (one dx, no slope)", name.c_str());
    gui::PlotSeries p;
    p.label = label;
    p.color = by_series ? series_color(spec, value, v)
                        : render::packed_abgr(render::palette_color(int(k)));
    auto px = std::make_shared<const std::vector<double>>(s.x);
    auto py = std::make_shared<const std::vector<double>>(s.y);
    p.count = s.x.size();
    p.x = [px](std::size_t i) { return (*px)[i]; };
    p.y = [py](std::size_t i) { return (*py)[i]; };
    p.markers = true;
    p.marker = by_series ? shape_of(mark.shape(first)) : gui::Marker::circle;
    p.thickness = 1.8f;
    c.series.push_back(std::move(p));
    c.runs.emplace_back(s.runs.begin(), s.runs.end());
  }
  return c;
}

namespace {

// A PNG whole or absent; a failed write is the command's "cannot write FILE: REASON".
void write_chart_png(const render::Image& image, const std::string& path) {
  try {
    render::write_png(image, path);
  } catch (const std::runtime_error& e) {
    throw WriteError(e.what());
  }
}

// A log-log chart under a heading, written to DIR/BASE.png, tall enough for its legend; returns
// "BASE.png".
std::string write_log_log_chart(ChartCanvas& canvas, const std::string& heading, gui::PlotOptions o,
                                const std::vector<gui::PlotSeries>& plots, const std::string& dir,
                                const std::string& base) {
  o.log_x = o.log_y = true;
  o.minor_log_grid = true;
  o.interactive = false;
  // The legend sits in a band above the plot box, at most 0.35 of the plot's height.
  const int W = 900, legend_h = 12 + 17 * int(plots.size());
  const int H = std::max(520, 50 + 60 + int(legend_h / 0.55));
  render::Image image = canvas.draw(W, H, [&] {
    const float top = figures::heading(canvas, heading, W);
    ImGui::SetCursorScreenPos(ImVec2(10, top));
    gui::plot(base.c_str(), ImVec2(W - 20, H - top - 6), o, plots);
  });
  write_chart_png(image, (fs::path(dir) / (base + ".png")).string());
  return base + ".png";
}

std::string file_part(const std::string& scene) {
  std::string s = fs::path(scene).stem().string();
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_') ch = '-';
  return s;
}

std::string error_vs_cost(ChartCanvas& canvas, const Spec& spec,
                          const std::vector<RunResult>& results, const std::string& scene,
                          const std::string& dir, std::optional<double> target_error) {
  const std::string& error = spec.errors.front();
  const ChartPlots c = cost_plots(spec, results, scene, target_error);
  if (std::none_of(c.runs.begin(), c.runs.end(), [](const auto& r) { return !r.empty(); }))
    return "";  // no run of this scene has a result
  const std::string base = "error_vs_cost_" + file_part(scene);
  const Marking mark = marking(spec, results, scene, {spec.series}, gui::kMarkerShapes);
  const auto front = pareto_front(results, error, scene);
  {
    std::ostringstream csv;
    // One row per point drawn: its run, where it is drawn and why ("; " between axes, so
    // that no field needs quotes).
    auto plain = [](std::string t) {
      for (std::size_t at; (at = t.find(", ")) != std::string::npos;) t.replace(at, 2, "; ");
      return csv_text(t);
    };
    csv << "id,series,outcome,cost_s," << error
        << "_error,plotted_cost_s,plotted_error,pareto,shape,point_label,configuration\n";
    for (std::size_t k = 0; k < c.series.size(); ++k) {
      const gui::PlotSeries& p = c.series[k];
      // The front and the target have their own rows' runs; the rings circle listed points.
      if (p.dashed || p.marker == gui::Marker::ring) continue;
      for (std::size_t j = 0; j < c.runs[k].size(); ++j) {
        if (c.runs[k][j] < 0) continue;
        const RunResult& r = results[std::size_t(c.runs[k][j])];
        const std::string value = r.run->value_text(spec.series);
        const bool on_front =
            std::find(front.begin(), front.end(), std::size_t(c.runs[k][j])) != front.end();
        csv << r.run->id << ',' << csv_text(value.empty() ? "all" : value) << ',' << r.outcome
            << ',' << (r.present ? number_text(r.cost(), 6) : "") << ','
            << number_text(r.error(error), 6) << ',' << number_text(p.x(j), 6) << ','
            << number_text(p.y(j), 6) << ',' << (on_front ? 1 : 0) << ','
            << plain(mark.shapes[mark.shape(*r.run)]) << ',' << csv_text(mark.label(*r.run)) << ','
            << plain(config_text(spec, *r.run)) << '\n';
      }
    }
    if (target_error) csv << "target,,,,,," << number_text(*target_error, 6) << ",,,,\n";
    write_file_whole((fs::path(dir) / (base + ".csv")).string(), csv.str());
  }
  gui::PlotOptions o;
  o.title = "each point one run; reference runs left out";
  o.x_label = "cost: wall seconds inside the steps";
  o.y_label = error_label(error);
  return write_log_log_chart(canvas, "Sweep " + spec.name + ", " + scene + ": error against cost",
                             o, c.series, dir, base);
}

}  // namespace

namespace {

std::string stability(ChartCanvas& canvas, const Spec& spec, const std::vector<RunResult>& results,
                      const StabilityMap& m, const std::string& dir) {
  const std::string base = "stability_" + file_part(m.scene);
  {
    std::ostringstream csv;
    csv << "row";
    for (const std::string& c : m.column_labels) csv << ',' << m.column_key << '=' << c;
    csv << '\n';
    for (std::size_t r = 0; r < m.row_labels.size(); ++r) {
      csv << m.row_labels[r];
      for (long i : m.cells[r])
        csv << ','
            << (i < 0 ? ""
                      : results[std::size_t(i)].outcome + " " + cell_text(results[std::size_t(i)]));
      csv << '\n';
    }
    write_file_whole((fs::path(dir) / (base + ".csv")).string(), csv.str());
  }
  // The legend: the four outcomes, and the kinds of grey and blue cells this map has.
  std::vector<std::string> legend = {"completed", "noisy", "not_converged", "blew_up"};
  for (const std::string o : {"refused", "no_result", ""})
    for (const auto& row : m.cells)
      for (long i : row)
        if ((i < 0 ? "" : results[std::size_t(i)].outcome) == o &&
            std::find(legend.begin(), legend.end(), o) == legend.end())
          legend.push_back(o);
  const float label_w = 230, cell_w = 124, cell_h = 30, legend_row = 24;
  const int W = std::max(640, int(label_w + cell_w * float(m.column_labels.size()) + 20));
  const int legend_rows = legend.size() > 4 ? 2 : 1;
  const int H =
      int(50 + 28 + cell_h * float(m.row_labels.size()) + legend_row * float(legend_rows) + 20);
  render::Image image = canvas.draw(W, H, [&] {
    const float top =
        figures::heading(canvas, "Stability map: " + m.scene + " (" + spec.name + ")", float(W));
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImU32 ink = IM_COL32(20, 20, 20, 255), muted = IM_COL32(90, 90, 90, 255);
    const float x0 = 10 + label_w, y0 = top + 24;
    for (std::size_t c = 0; c < m.column_labels.size(); ++c) {
      const std::string t = m.column_key + " " + m.column_labels[c];
      const float w = ImGui::CalcTextSize(t.c_str()).x;
      dl->AddText(ImVec2(x0 + cell_w * float(c) + (cell_w - w) / 2, top + 2), muted, t.c_str());
    }
    for (std::size_t r = 0; r < m.row_labels.size(); ++r) {
      const float y = y0 + cell_h * float(r);
      dl->AddText(ImVec2(12, y + 7), ink, m.row_labels[r].c_str());
      for (std::size_t c = 0; c < m.column_labels.size(); ++c) {
        const long i = m.cells[r][c];
        const ImVec2 a(x0 + cell_w * float(c), y), b(a.x + cell_w - 2, y + cell_h - 2);
        dl->AddRectFilled(a, b, outcome_color(i < 0 ? "" : results[std::size_t(i)].outcome));
        const std::string t = i < 0 ? "excluded" : cell_text(results[std::size_t(i)]);
        const float w = ImGui::CalcTextSize(t.c_str()).x;
        dl->AddText(ImVec2(a.x + (cell_w - 2 - w) / 2, y + 7), i < 0 ? muted : ink, t.c_str());
      }
    }
    float lx = 12, ly = y0 + cell_h * float(m.row_labels.size()) + 10;
    for (const std::string& o : legend) {
      const std::string t = outcome_legend(o);
      if (lx + 30 + ImGui::CalcTextSize(t.c_str()).x > float(W) - 10) lx = 12, ly += legend_row;
      dl->AddRectFilled(ImVec2(lx, ly), ImVec2(lx + 16, ly + 16), outcome_color(o));
      dl->AddRect(ImVec2(lx, ly), ImVec2(lx + 16, ly + 16), IM_COL32(170, 170, 170, 255));
      dl->AddText(ImVec2(lx + 22, ly), ink, t.c_str());
      lx += 30 + ImGui::CalcTextSize(t.c_str()).x;
    }
  });
  write_chart_png(image, (fs::path(dir) / (base + ".png")).string());
  return base + ".png";
}

std::string convergence(ChartCanvas& canvas, const Spec& spec,
                        const std::vector<RunResult>& results, const std::string& scene,
                        const std::string& dir) {
  const std::string& error = spec.errors.front();
  const auto series = convergence_series(spec, results, error, scene);
  if (series.empty()) return "";
  const ChartPlots c = convergence_plots(spec, results, scene);
  const std::string base = "convergence_" + file_part(scene);
  {
    std::ostringstream csv;
    csv << "id,series,dx," << error << "_error,slope\n";
    for (const Series& s : series)
      for (std::size_t k = 0; k < s.runs.size(); ++k)
        csv << results[s.runs[k]].run->id << ',' << csv_text(s.label) << ','
            << number_text(s.x[k], 6) << ',' << number_text(s.y[k], 6) << ','
            << number_text(s.slope, 4) << '\n';
    write_file_whole((fs::path(dir) / (base + ".csv")).string(), csv.str());
  }
  gui::PlotOptions o;
  o.title = "error against grid spacing, one line per configuration, fitted log-log slopes";
  o.x_label = "grid spacing dx";
  o.y_label = error_label(error);
  return write_log_log_chart(canvas, "Sweep " + spec.name + ", " + scene + ": convergence", o,
                             c.series, dir, base);
}

}  // namespace

std::vector<std::string> write_charts(const Spec& spec, const std::vector<RunResult>& results,
                                      const std::string& out_dir,
                                      std::optional<double> target_error) {
  ChartCanvas canvas;
  std::vector<std::string> names;
  for (const std::string& scene : scenes(spec))
    if (std::string n = error_vs_cost(canvas, spec, results, scene, out_dir, target_error);
        !n.empty())
      names.push_back(n);
  if (spec.axis(spec.columns) || spec.columns == "dt_factor")
    for (const StabilityMap& m : stability_maps(spec, results))
      names.push_back(stability(canvas, spec, results, m, out_dir));
  for (const std::string& scene : scenes(spec))
    if (std::string n = convergence(canvas, spec, results, scene, out_dir); !n.empty())
      names.push_back(n);
  return names;
}

}  // namespace apiclab::sweep
