#include "app/lockstep.hpp"

#include <omp.h>

#include "app/clock.hpp"
#include "app/stop_signal.hpp"
#include "app/thread_pool.hpp"

namespace apiclab {

bool Lockstep::all_reached(double t) const {
  for (const Simulation* s : panes_)
    if (!reached(*s, t)) return false;
  return true;
}

bool Lockstep::all_failed() const {
  for (const Simulation* s : panes_)
    if (!s->failure()) return false;
  return true;
}

double Lockstep::step_round(double t, const OnRow& on_row) {
  const double t0 = now_seconds();
  due_.clear();
  bool side_by_side = true;
  for (std::size_t k = 0; k < panes_.size(); ++k)
    if (!reached(*panes_[k], t)) {
      due_.push_back(k);
      side_by_side = side_by_side && !panes_[k]->steps_in_parallel();
    }
  rows_.resize(panes_.size());
  has_row_.assign(panes_.size(), 0);
  // A failed step has no row: the failure is the pane's state from now on.
  const auto step_one = [&](std::size_t j) {
    const std::size_t k = due_[j];
    has_row_[k] = !panes_[k]->step(t, &rows_[k]);
  };
  const int threads = omp_get_max_threads();
  if (side_by_side && due_.size() > 1 && threads > 1)
    run_pool(due_.size(), threads, step_one);
  else
    for (std::size_t j = 0; j < due_.size(); ++j) step_one(j);
  double particle_steps = 0;
  for (std::size_t k : due_) {
    if (has_row_[k] && on_row) on_row(k, rows_[k]);
    particle_steps += double(particle_count(*panes_[k]));
  }
  stepping_seconds_ += now_seconds() - t0;
  return particle_steps;
}

void Lockstep::advance_to(double t, const OnRow& on_row) {
  // Until every pane reached t (not until a round takes no particle-steps: a solver without
  // particles, such as EoL, takes none), or until SIGINT/SIGTERM asked to stop.
  while (!all_reached(t) && !stop_signal()) step_round(t, on_row);
}

}  // namespace apiclab
