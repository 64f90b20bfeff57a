#include "app/figures/time_figure.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "app/cli.hpp"
#include "app/figures/chart_style.hpp"
#include "app/run_outputs.hpp"
#include "render/image.hpp"

namespace apiclab::figures {
namespace {

const std::string& key_of(const jobs::Run& r) { return r.method.empty() ? r.scheme : r.method; }

// Methods have no palette slot: EoL and Eulerian take two of the schemes' colours.
SchemeStyle run_style(const jobs::Run& r) {
  if (r.method == "eol") return {"EoL", style_of("apic").color};
  if (r.method == "eulerian") return {"Eulerian", style_of("flip").color};
  return style_of(key_of(r), r.scheme_parameters, r.flip_alpha);
}

double value(const jobs::Run& r, const Quantity& q, std::size_t i) {
  const double v = q.of(r.rows[i]);
  if (q.per_start) {
    const double scaled = std::abs(v / q.per_start(r.rows.front()));
    return q.log_y ? std::max(scaled, 1e-18) : scaled;  // NaN stays NaN
  }
  return q.relative ? v / q.of(r.rows.front()) : v;
}

std::string series_label(const jobs::Run& r) {
  std::string label = run_style(r).label;
  if (!r.failure.empty()) label += " (failed)";
  return label;
}

// The bounds of Sec 3.6 in the order of the legend, each with its colour (none of the schemes').
struct LimitStyle {
  const char* key;
  const char* label;
  ImU32 color;
};
const LimitStyle kLimits[] = {
    {"elastic", "elastic limit", IM_COL32(123, 50, 148, 255)},
    {"advection", "advection, eq 33", IM_COL32(230, 159, 0, 255)},
    {"contact", "contact bound", IM_COL32(200, 30, 60, 255)},
    {"frame", "frame time", IM_COL32(30, 30, 30, 255)},
    {"max", "time.dt.value", IM_COL32(150, 150, 150, 255)},
    {"fixed", "fixed", IM_COL32(140, 90, 40, 255)},
};

// The steps whose objects' surfaces overlapped (Fig 8's contact interval), a grey bar at half the
// run's smallest value; none (no samples) when no step touched.
gui::PlotSeries contact_interval(const jobs::Run& r, const Quantity& q) {
  double low = std::numeric_limits<double>::infinity();
  bool touched = false;
  for (std::size_t i = 1; i < r.rows.size(); ++i) {
    const double v = value(r, q, i);
    if (v > 0) low = std::min(low, v);
    touched = touched || r.rows[i].contact_pairs > 0;
  }
  gui::PlotSeries s;
  if (!touched || !std::isfinite(low)) return s;
  s.label = series_label(r) + ": contact (surfaces overlap)";
  s.color = IM_COL32(120, 120, 120, 255);
  s.count = r.rows.size();
  s.x = [&r](std::size_t i) { return r.rows[i].t; };
  s.y = [&r, y = r.method == "eol" ? 0.5 * low : 0.35 * low](std::size_t i) {
    return r.rows[i].contact_pairs > 0 ? y : std::nan("");
  };
  s.thickness = 6.0f;
  s.dashed = r.method != "eol";
  return s;
}

// One series per run and bound: the steps that bound set, the others left out (gaps). A bound
// that set fewer than half the steps gets a dot on each of its steps, so single steps show.
// Row 0 is the state at t = 0, before any step: it has no bound.
std::vector<gui::PlotSeries> limit_series(const std::vector<jobs::Run>& runs, const Quantity& q) {
  std::vector<gui::PlotSeries> out;
  for (const jobs::Run& r : runs)
    for (const LimitStyle& l : kLimits) {
      std::size_t steps = 0;
      for (const DiagnosticsRow& d : r.rows) steps += d.step > 0 && d.dt_limit == l.key;
      if (steps == 0) continue;
      gui::PlotSeries s;
      s.label = series_label(r) + ": " + l.label;
      s.color = l.color;
      s.count = r.rows.size();
      s.x = [&r](std::size_t i) { return r.rows[i].t; };
      s.y = [&r, &q, key = std::string(l.key)](std::size_t i) {
        const DiagnosticsRow& d = r.rows[i];
        return d.step > 0 && d.dt_limit == key ? value(r, q, i) : std::nan("");
      };
      s.thickness = 2.0f;
      s.dashed = r.method != "eol";
      s.markers = 2 * steps < r.rows.size();
      out.push_back(std::move(s));
    }
  for (const jobs::Run& r : runs) out.push_back(contact_interval(r, q));
  std::erase_if(out, [](const gui::PlotSeries& s) { return s.count == 0; });
  return out;
}

std::vector<gui::PlotSeries> time_series(const std::vector<jobs::Run>& runs, const Quantity& q) {
  if (q.by_dt_limit) return limit_series(runs, q);
  std::vector<gui::PlotSeries> out;
  for (const jobs::Run& r : runs) {
    gui::PlotSeries s;
    s.label = series_label(r);
    s.color = run_style(r).color;
    s.count = r.rows.size();
    s.x = [&r](std::size_t i) { return r.rows[i].t; };
    s.y = [&r, &q](std::size_t i) { return value(r, q, i); };
    s.thickness = 2.0f;
    s.dashed = q.dashed || r.scheme == "rpic";  // RPIC often lies on APIC: dashes show both
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace

void write_time_figure(ChartCanvas& canvas, const TimeFigure& f, const std::string& dir) {
  const auto base = std::filesystem::path(dir) / f.file;
  {
    std::ofstream csv(base.string() + ".csv");
    csv << "scheme,step,t,dt,kinetic,kinetic_grid,potential,total_energy,angular_momentum"
        << (f.methods ? ",dt_limit,grid_nodes,grid_bytes,contact_pairs" : "");
    if (f.ledger)
      for (int s = 0; s < ledger_stage_count; ++s)
        csv << ',' << ledger_stage_name(LedgerStage(s)) << "_dLz";
    csv << '\n';
    csv.precision(17);
    for (const jobs::Run& r : f.runs)
      for (const DiagnosticsRow& d : r.rows) {
        csv << key_of(r) << ',' << d.step << ',' << d.t << ',' << d.dt << ',' << d.kinetic << ','
            << d.kinetic_grid << ',' << d.potential << ',' << d.total << ',' << d.L[2]
            << (f.methods ? "," + d.dt_limit + "," + std::to_string(std::llround(d.grid_nodes)) +
                                "," + std::to_string(std::llround(d.grid_bytes)) + "," +
                                std::to_string(d.contact_pairs)
                          : "");
        if (f.ledger)
          for (const ConservedSums& c : d.stages) csv << ',' << c.L[2];
        csv << '\n';
      }
    if (!csv) throw cli::UsageError("cannot write " + base.string() + ".csv");
  }
  // The runs behind the CSV, as a sidecar (app/run_outputs.hpp): scene, scheme, overrides.
  nlohmann::json runs = nlohmann::json::array();
  for (const jobs::Run& r : f.runs)
    runs.push_back({{"scene", r.scene},
                    {"scheme", r.scheme},
                    {"method", r.method},
                    {"overrides", r.overrides},
                    {"t_end", r.t_end > 0 ? nlohmann::json(r.t_end) : nlohmann::json("scene's")},
                    {"failure", r.failure}});
  write_csv_sidecar(base.string() + ".csv", {{"runs", runs}});
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
      o.log_y = q->log_y;
      ImGui::SetCursorScreenPos(ImVec2(10 + k * (w + 10), top));
      gui::plot(q->title.c_str(), ImVec2(w, h), o, time_series(f.runs, *q));
      ++k;
    }
  });
  render::write_png(image, base.string() + ".png");
}

}  // namespace apiclab::figures
