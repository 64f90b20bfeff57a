// What a run comes to, by one rule for `run`, the GUI's drift plot and sweeps: relative energy
// drift, angular-momentum drift, the time steps taken and the wall time.
#pragma once
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "sim/measure/diagnostics.hpp"
#include "sim/scene/scene.hpp"

namespace apiclab {

// The drift of a diagnostics row from the initial one. dE/E is signed: (E − E₀)/|E₀|, except
// when |E₀| is at or below the round-off of a body at rest (Simulation::rest_energy_round_off:
// at rest without gravity E₀ is itself round-off); then E₀ counts as zero and dE is the signed
// absolute E − E₀ in J. dL is |ΔL|/|L₀|, except when |L₀| is below round-off of the momentum
// scale √(2 K₀ M)·extent (a body at rest, a symmetric impact): then L₀ counts as zero and dL is
// the absolute |ΔL|.
class DriftRule {
 public:
  // extent: the largest |max| + |min| of the domain over its axes (lever arm of L).
  DriftRule(const DiagnosticsRow& first, double total_mass, double extent,
            double energy_round_off = 0)
      : first_(first) {
    const double E0 = std::abs(first.total);
    E0_ = E0 > energy_round_off ? E0 : 0.0;
    const double L_scale = std::sqrt(2 * std::max(first.kinetic, 0.0) * total_mass) * extent;
    const double L0 = norm(first.L);
    L0_ = L0 > 1e-12 * L_scale ? L0 : 0.0;
  }
  // The rule for `sim`'s run from its first row.
  template <class Sim>
  static DriftRule of(const Sim& sim, const DiagnosticsRow& first) {
    return DriftRule(first, sim.total_mass(), domain_extent(sim.scene()),
                     sim.rest_energy_round_off());
  }
  static double domain_extent(const SceneDesc& scene) {
    double extent = 0;
    for (int a = 0; a < scene.dim; ++a)
      extent = std::max(extent, std::abs(scene.domain.max[a]) + std::abs(scene.domain.min[a]));
    return extent;
  }

  double energy(const DiagnosticsRow& r) const {
    return E0_ > 0 ? (r.total - first_.total) / E0_ : r.total - first_.total;
  }
  bool energy_relative() const { return E0_ > 0; }
  double angular_momentum(const DiagnosticsRow& r) const {
    const std::array<double, 3> dL{r.L[0] - first_.L[0], r.L[1] - first_.L[1],
                                   r.L[2] - first_.L[2]};
    return L0_ > 0 ? norm(dL) / L0_ : norm(dL);
  }
  bool angular_momentum_relative() const { return L0_ > 0; }

 private:
  friend class RunSummary;  // its checkpoint
  static double norm(const std::array<double, 3>& a) {
    return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  }
  DiagnosticsRow first_;
  double E0_, L0_ = 0;
};

// Fed the initial row and then every step's row.
class RunSummary {
 public:
  explicit RunSummary(const DriftRule& drift) : drift_(drift), last_(drift.first_) {}
  RunSummary(const DiagnosticsRow& first, double total_mass, double extent)
      : drift_(first, total_mass, extent), last_(first) {}

  void add(const DiagnosticsRow& row) {
    last_ = row;
    add_dt(row.dt);
    step_wall_seconds_ += row.wall_seconds;
    max_energy_drift_ = std::max(max_energy_drift_, std::abs(drift_.energy(row)));
    max_angular_momentum_drift_ =
        std::max(max_angular_momentum_drift_, drift_.angular_momentum(row));
    unconverged_ += row.converged ? 0 : 1;
  }

  const DriftRule& drift() const { return drift_; }
  double energy_drift() const { return drift_.energy(last_); }
  double angular_momentum_drift() const { return drift_.angular_momentum(last_); }
  bool angular_momentum_relative() const { return drift_.angular_momentum_relative(); }
  bool energy_relative() const { return drift_.energy_relative(); }
  // The largest |dE/E| and dL over the steps so far (dL by the same rule as above).
  double max_energy_drift() const { return max_energy_drift_; }
  double max_angular_momentum_drift() const { return max_angular_momentum_drift_; }
  long unconverged_steps() const { return unconverged_; }
  const DiagnosticsRow& last() const { return last_; }
  long steps() const { return steps_; }
  // Seconds inside the steps (DiagnosticsRow::wall_seconds), without I/O around them.
  double step_wall_seconds() const { return step_wall_seconds_; }

  // Its state for a checkpoint (sim/state_io.hpp), so a resumed run's summary is the whole run's.
  template <class Writer>
  void save(Writer& w) const {
    w.tag("summary");
    save_row(w, drift_.first_);
    w.value(drift_.E0_);
    w.value(drift_.L0_);
    save_row(w, last_);
    w.value(steps_);
    w.value(min_dt_);
    w.value(max_dt_);
    w.value(std::uint64_t(dt_bins_.size()));
    for (const auto& [bin, entry] : dt_bins_) {
      w.value(bin);
      w.value(entry.first);
      w.value(entry.second);
    }
    w.value(step_wall_seconds_);
    w.value(max_energy_drift_);
    w.value(max_angular_momentum_drift_);
    w.value(unconverged_);
  }
  template <class Reader>
  void load(Reader& r) {
    r.tag("summary");
    load_row(r, drift_.first_);
    r.value(drift_.E0_);
    r.value(drift_.L0_);
    load_row(r, last_);
    r.value(steps_);
    r.value(min_dt_);
    r.value(max_dt_);
    dt_bins_.clear();
    for (auto n = r.template value<std::uint64_t>(); n > 0; --n) {
      const auto bin = r.template value<long long>();
      const auto dt = r.template value<double>();
      dt_bins_[bin] = {dt, r.template value<long>()};
    }
    r.value(step_wall_seconds_);
    r.value(max_energy_drift_);
    r.value(max_angular_momentum_drift_);
    r.value(unconverged_);
  }

  struct DtStats {
    double min = 0, median = 0, max = 0;
  };
  // min and max exact; the median exact when the steps take few distinct values (a fixed step)
  // and otherwise to 1e-4 relative: steps are counted in bins of 1e-4 in log Δt, each bin holding
  // the first Δt it saw, so memory stays bounded over millions of steps (a stored list grew by
  // 2 MB over the 290k steps of a long eol-drop run).
  DtStats dt() const {
    if (steps_ == 0) return {};
    auto nth = [&](long k) {  // the k-th smallest (0-based), by bin
      for (const auto& [bin, entry] : dt_bins_) {
        if (k < entry.second) return entry.first;
        k -= entry.second;
      }
      return max_dt_;
    };
    const long n = steps_;
    const double median = n % 2 ? nth(n / 2) : 0.5 * (nth(n / 2 - 1) + nth(n / 2));
    return {min_dt_, median, max_dt_};
  }

 private:
  DriftRule drift_;
  DiagnosticsRow last_;
  template <class Writer>
  static void save_row(Writer& w, const DiagnosticsRow& r) {
    for (double v : {r.t, r.dt, r.kinetic, r.kinetic_grid, r.potential, r.elastic, r.total, r.p[0],
                     r.p[1], r.p[2], r.L[0], r.L[1], r.L[2], r.wall_seconds, r.newton_iters,
                     r.cg_iters, r.residual, r.grid_nodes, r.grid_bytes})
      w.value(v);
    w.value(r.step);
    w.value(std::uint8_t(r.converged));
    w.text(r.dt_limit);
  }
  template <class Reader>
  static void load_row(Reader& in, DiagnosticsRow& r) {
    for (double* v : {&r.t, &r.dt, &r.kinetic, &r.kinetic_grid, &r.potential, &r.elastic, &r.total,
                      &r.p[0], &r.p[1], &r.p[2], &r.L[0], &r.L[1], &r.L[2], &r.wall_seconds,
                      &r.newton_iters, &r.cg_iters, &r.residual, &r.grid_nodes, &r.grid_bytes})
      in.value(*v);
    in.value(r.step);
    r.converged = in.template value<std::uint8_t>() != 0;
    r.dt_limit = in.text();
  }
  void add_dt(double dt) {
    if (steps_ == 0 || dt < min_dt_) min_dt_ = dt;
    if (steps_ == 0 || dt > max_dt_) max_dt_ = dt;
    ++steps_;
    const long long bin = dt > 0 ? std::llround(std::log(dt) * 1e4) : LLONG_MIN;
    auto [it, fresh] = dt_bins_.try_emplace(bin, dt, 0);
    ++it->second.second;
  }
  long steps_ = 0;
  double min_dt_ = 0, max_dt_ = 0;
  std::map<long long, std::pair<double, long>> dt_bins_;  // log-Δt bin → (first Δt, count)
  double step_wall_seconds_ = 0, max_energy_drift_ = 0, max_angular_momentum_drift_ = 0;
  long unconverged_ = 0;
};

}  // namespace apiclab
