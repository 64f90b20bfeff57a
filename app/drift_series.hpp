// What the GUI's drift and momentum plots draw (app/gui/plots_panel.cpp), computed apart from
// the drawing so tests can check it: the drift by run's rule (sim/measure/run_summary.hpp
// DriftRule: |ΔL| absolute when L₀ is below round-off), labelled with which it is, the energy drift
// always, and momenta of round-off size drawn as zero rather than as noise.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "sim/measure/run_summary.hpp"

namespace apiclab {

// Relative drifts below double round-off are drawn at this floor on the log axis (an exact
// zero, e.g. the first row, would otherwise leave the curve out).
inline constexpr double kRelativeDriftFloor = 1e-16;
// A momentum counts as round-off below this fraction of the run's momentum scale.
inline constexpr double kMomentumRoundOff = 1e-12;

// Round-off of the momenta of a run so far: kMomentumRoundOff of the scale √(2 K_max M) [kg m/s]
// and, for L, of that times the domain's extent [kg m²/s]. `row(i)` gives row i of n.
struct MomentumRoundOff {
  double p = 0, L = 0;
};
template <class Row>
MomentumRoundOff momentum_round_off(const Row& row, std::size_t n, double total_mass,
                                    double extent) {
  double kinetic = 0;
  for (std::size_t i = 0; i < n; ++i) kinetic = std::max(kinetic, row(i).kinetic);
  const double p = kMomentumRoundOff * std::sqrt(2 * kinetic * std::max(total_mass, 0.0));
  return {p, p * extent};
}

// A momentum component as plotted: zero when its size is round-off.
inline double plotted_momentum(double value, double round_off) {
  return std::abs(value) <= round_off ? 0.0 : value;
}

struct DriftPlot {
  bool momentum_relative = true;
  std::string energy_label = "|dE|/|E0|";
  std::string momentum_label;               // "|dL|/|L0|", or "|dL| [kg m^2/s] (L0 = 0)"
  std::string title;                        // says whether |dL| is relative or absolute
  std::vector<double> t, energy, momentum;  // on a log axis: 0 (an absolute drift) left out
};

// The drift series of rows 1..n-1 by `rule` (row 0 alone before the first step). The energy
// drift is always there (a relative one floored at kRelativeDriftFloor); an absolute |ΔL| is
// floored at the momentum round-off `L_round_off` (a change of L below it is none), a relative
// one at kRelativeDriftFloor.
template <class Row>
DriftPlot drift_plot(const DriftRule& rule, const Row& row, std::size_t n, double L_round_off) {
  DriftPlot d;
  d.momentum_relative = rule.angular_momentum_relative();
  if (!rule.energy_relative()) d.energy_label = "|dE| [J] (E0 = 0)";
  d.momentum_label = d.momentum_relative ? "|dL|/|L0|" : "|dL| [kg m^2/s] (L0 = 0)";
  // Short enough for a quarter of the window; the legend names each series with its unit.
  const bool energy_relative = rule.energy_relative();
  d.title = energy_relative && d.momentum_relative ? "relative drift (log)"
            : energy_relative                      ? "drift (log): |dL| absolute"
            : d.momentum_relative                  ? "drift (log): |dE| absolute"
                                                   : "drift (log): absolute";
  const double L_floor = d.momentum_relative ? kRelativeDriftFloor : L_round_off;
  // Row 0 is the reference itself (drift 0 by definition): left out once there are steps, so
  // the log axis is not stretched down to the floor by it.
  for (std::size_t i = n > 1 ? 1 : 0; i < n; ++i) {
    d.t.push_back(row(i).t);
    // An absolute |ΔE| (E₀ round-off) has no floor: an exact 0 is left out, as |ΔL|'s below.
    const double dE = std::abs(rule.energy(row(i)));
    d.energy.push_back(rule.energy_relative() ? std::max(dE, kRelativeDriftFloor) : dE);
    const double dL = rule.angular_momentum(row(i));
    // With no scale at all (nothing ever moved) there is no floor: an exact 0 is left out.
    d.momentum.push_back(L_floor > 0 ? std::max(dL, L_floor) : dL);
  }
  return d;
}

}  // namespace apiclab
