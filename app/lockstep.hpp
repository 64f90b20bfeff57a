// Several simulations advanced to the same times, one step per pane per round, so that no pane
// runs ahead of the others: compare's panes and the GUI's panes. Panes whose steps run on one
// thread (small scenes) take their steps of a round side by side, one per core; larger ones in
// turn, each with every core. A pane that failed stays frozen where it failed (its state, and
// therefore its picture, no longer changes).
#pragma once
#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "sim/simulation.hpp"

namespace apiclab {

class Lockstep {
 public:
  using OnRow = std::function<void(std::size_t pane, const DiagnosticsRow& row)>;

  explicit Lockstep(std::vector<Simulation*> panes = {}) : panes_(std::move(panes)) {}

  std::size_t size() const { return panes_.size(); }
  Simulation& operator[](std::size_t k) const { return *panes_[k]; }

  // Whether the pane is at t or failed: nothing left to do for it before t.
  static bool reached(const Simulation& s, double t) { return s.failure() || s.time() >= t; }
  bool all_reached(double t) const;
  bool all_failed() const;

  // One step of every pane short of t (steps land exactly on t); on_row sees each step's row,
  // in pane order, on the calling thread.
  // Returns the particle-steps taken, 0 when every pane had reached t.
  double step_round(double t, const OnRow& on_row = {});
  // Rounds until every pane reached t.
  void advance_to(double t, const OnRow& on_row = {});

  // Wall seconds spent stepping, over the lockstep's life.
  double stepping_seconds() const { return stepping_seconds_; }

 private:
  std::vector<Simulation*> panes_;
  double stepping_seconds_ = 0;
  // One round's work, kept so that a round allocates nothing.
  std::vector<std::size_t> due_;
  std::vector<DiagnosticsRow> rows_;
  std::vector<char> has_row_;
};

}  // namespace apiclab
