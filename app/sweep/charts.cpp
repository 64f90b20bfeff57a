#include "app/sweep/charts.hpp"

#include <imgui.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "app/figures/chart_canvas.hpp"
#include "app/figures/chart_style.hpp"
#include "app/gui/plot.hpp"
#include "app/output_file.hpp"
#include "app/sweep/tables.hpp"
#include "render/image.hpp"
#include "render/palette.hpp"
#include "sim/scheme_label.hpp"

namespace apiclab::sweep {
namespace fs = std::filesystem;
using figures::ChartCanvas;

// A series' legend with its scheme's parameter, "xpic" -> "xpic(2)" (sim/scheme_label.hpp), read
// from the scenes its runs simulated. Unchanged when they name no scheme with a parameter or
// disagree (another axis varies the parameter, and names it in the label itself).
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

namespace {

// A PNG whole or absent; a failed write is the command's "cannot write FILE: REASON".
void write_chart_png(const render::Image& image, const std::string& path) {
  try {
    render::write_png(image, path);
  } catch (const std::runtime_error& e) {
    throw WriteError(e.what());
  }
}

// A 900×520 log-log chart under a heading, written to DIR/BASE.png; returns "BASE.png".
std::string write_log_log_chart(ChartCanvas& canvas, const std::string& heading, gui::PlotOptions o,
                                const std::vector<gui::PlotSeries>& plots, const std::string& dir,
                                const std::string& base) {
  o.log_x = o.log_y = true;
  o.minor_log_grid = true;
  o.interactive = false;
  o.legend_corner = gui::PlotOptions::Corner::best;
  const int W = 900, H = 520;
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
                          const std::string& dir) {
  const std::string& error = spec.errors.front();
  const auto series = cost_series(spec, results, error, scene);
  if (series.empty()) return "";
  const auto front = pareto_front(results, error, scene);
  const std::string base = "error_vs_cost_" + file_part(scene);
  std::vector<double> fx, fy;
  for (std::size_t i : front) {
    fx.push_back(results[i].cost());
    fy.push_back(results[i].error(error));
  }
  {
    std::ostringstream csv;
    csv << "id,series,cost_s," << error << "_error,outcome,pareto\n";
    for (const Series& s : series)
      for (std::size_t i : s.runs)
        csv << results[i].run->id << ',' << s.label << ',' << number_text(results[i].cost(), 6)
            << ',' << number_text(results[i].error(error), 6) << ',' << results[i].outcome << ','
            << (std::find(front.begin(), front.end(), i) != front.end() ? 1 : 0) << '\n';
    write_file_whole((fs::path(dir) / (base + ".csv")).string(), csv.str());
  }
  std::vector<gui::PlotSeries> plots;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const std::string value = series[k].runs.empty()
                                  ? series[k].label
                                  : results[series[k].runs.front()].run->value_text(spec.series);
    plots.push_back(scatter(legend_label(series[k], results), series_color(spec, value, k),
                            series[k].x, series[k].y));
  }
  gui::PlotSeries pareto;
  pareto.label = "Pareto front";
  pareto.color = IM_COL32(40, 40, 40, 255);
  pareto.count = fx.size();
  pareto.x = [&fx](std::size_t i) { return fx[i]; };
  pareto.y = [&fy](std::size_t i) { return fy[i]; };
  pareto.dashed = true;
  pareto.thickness = 1.4f;
  plots.push_back(pareto);
  gui::PlotOptions o;
  o.title = "each point one run; reference runs left out";
  o.x_label = "cost: wall seconds inside the steps";
  o.y_label = error_label(error);
  return write_log_log_chart(canvas, "Sweep " + spec.name + ", " + scene + ": error against cost",
                             o, plots, dir, base);
}

}  // namespace

ImU32 outcome_color(const std::string& outcome) {
  if (outcome == "completed") return IM_COL32(150, 210, 150, 255);
  if (outcome == "noisy") return IM_COL32(245, 200, 90, 255);
  if (outcome == "not_converged") return IM_COL32(185, 160, 220, 255);
  if (outcome == "blew_up") return IM_COL32(230, 110, 100, 255);
  return IM_COL32(210, 210, 210, 255);
}

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
  const float label_w = 230, cell_w = 124, cell_h = 30, legend_h = 34;
  const int W = int(label_w + cell_w * float(m.column_labels.size()) + 20);
  const int H = int(50 + 28 + cell_h * float(m.row_labels.size()) + legend_h + 10);
  render::Image image = canvas.draw(std::max(W, 640), H, [&] {
    const float top =
        figures::heading(canvas, "Stability map: " + m.scene + " (" + spec.name + ")", W);
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
        if (i < 0) continue;
        const std::string t = cell_text(results[std::size_t(i)]);
        const float w = ImGui::CalcTextSize(t.c_str()).x;
        dl->AddText(ImVec2(a.x + (cell_w - 2 - w) / 2, y + 7), ink, t.c_str());
      }
    }
    float lx = 12;
    const float ly = y0 + cell_h * float(m.row_labels.size()) + 10;
    for (const char* o : {"completed", "noisy", "not_converged", "blew_up"}) {
      dl->AddRectFilled(ImVec2(lx, ly), ImVec2(lx + 16, ly + 16), outcome_color(o));
      const std::string t = std::string(o) == "completed" ? "stable (dE: final energy change)" : o;
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
  const std::string base = "convergence_" + file_part(scene);
  {
    std::ostringstream csv;
    csv << "id,series,dx," << error << "_error,slope\n";
    for (const Series& s : series)
      for (std::size_t k = 0; k < s.runs.size(); ++k)
        csv << results[s.runs[k]].run->id << ',' << s.label << ',' << number_text(s.x[k], 6) << ','
            << number_text(s.y[k], 6) << ',' << number_text(s.slope, 4) << '\n';
    write_file_whole((fs::path(dir) / (base + ".csv")).string(), csv.str());
  }
  std::vector<gui::PlotSeries> plots;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    const std::string name = legend_label(s, results);
    char label[200];
    if (std::isfinite(s.slope))
      std::snprintf(label, sizeof label, "%s (slope %.2f)", name.c_str(), s.slope);
    else  // one resolution: no slope to fit
      std::snprintf(label, sizeof label, "%s (one dx, no slope)", name.c_str());
    gui::PlotSeries p;
    p.label = label;
    p.color = render::packed_abgr(render::palette_color(int(k)));
    p.count = s.x.size();
    p.x = [&s](std::size_t i) { return s.x[i]; };
    p.y = [&s](std::size_t i) { return s.y[i]; };
    p.markers = true;
    p.thickness = 1.8f;
    plots.push_back(std::move(p));
  }
  gui::PlotOptions o;
  o.title = "error against grid spacing, fitted log-log slopes";
  o.x_label = "grid spacing dx";
  o.y_label = error_label(error);
  return write_log_log_chart(canvas, "Sweep " + spec.name + ", " + scene + ": convergence", o,
                             plots, dir, base);
}

}  // namespace

std::vector<std::string> write_charts(const Spec& spec, const std::vector<RunResult>& results,
                                      const std::string& out_dir) {
  ChartCanvas canvas;
  std::vector<std::string> names;
  for (const std::string& scene : scenes(spec))
    if (std::string n = error_vs_cost(canvas, spec, results, scene, out_dir); !n.empty())
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
