// Figures of two charts side by side against time, one line per scheme in each (Figs 3-6, 10),
// written as PNG with the CSV of every run behind them.
#pragma once
#include <string>
#include <vector>

#include "app/figures/chart_canvas.hpp"
#include "app/gui/plot.hpp"
#include "app/jobs.hpp"

namespace apiclab::figures {

// A quantity of a diagnostics row, charted against time.
struct Quantity {
  std::string title, y_label;
  double (*of)(const DiagnosticsRow&);
  bool dashed = false;
  bool relative = false;  // divided by the run's value at t = 0
  bool log_y = false;
  // Coloured by the step's dt_limit (EoL, Sec 3.6) instead of by run: one line per run and
  // limit, the runs told apart by dashes (Fig 8).
  bool by_dt_limit = false;
  // When set: |of / per_start(the run's row at t = 0)|, at least 1e-18 on a log scale so that an
  // exact zero shows.
  double (*per_start)(const DiagnosticsRow&) = nullptr;
};

struct TimeFigure {
  std::string id;  // the paper's figure number, as --only takes it
  std::string file, heading, scene;
  double quick_t_end = 0;            // 0: the scene's end time in --quick as well
  double cost = 1;                   // relative cost of one run (jobs::Run::cost)
  std::vector<std::string> schemes;  // solver.scheme keys, or solver.method keys when `methods`
  Quantity left, right;
  std::vector<jobs::Run> runs;  // one per scheme, filled by the caller
  bool methods = false;  // EoL figures: one run per solver method, CSV with dt_limit, grid_nodes,
                         // grid_bytes, contact_pairs
  std::vector<std::string> overrides{};        // `--set` KEY=VALUE for every run
  std::vector<std::string> quick_overrides{};  // and in --quick besides
  bool ledger = false;  // CSV with each ledger stage's ΔL_z (solver.ledger among the overrides)
};

// DIR/<file>.png and DIR/<file>.csv; throws UsageError when the CSV cannot be written.
void write_time_figure(ChartCanvas& canvas, const TimeFigure& figure, const std::string& dir);

}  // namespace apiclab::figures
