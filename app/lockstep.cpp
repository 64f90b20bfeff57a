#include "app/lockstep.hpp"

#include "app/clock.hpp"

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
  double particle_steps = 0;
  DiagnosticsRow row;
  for (std::size_t k = 0; k < panes_.size(); ++k) {
    Simulation& s = *panes_[k];
    if (reached(s, t)) continue;
    // A failed step has no row: the failure is the pane's state from now on.
    if (!s.step(t, &row) && on_row) on_row(k, row);
    particle_steps += double(particle_count(s));
  }
  stepping_seconds_ += now_seconds() - t0;
  return particle_steps;
}

void Lockstep::advance_to(double t, const OnRow& on_row) {
  // Until every pane reached t (not until a round takes no particle-steps: a solver without
  // particles, such as EoL, takes none).
  while (!all_reached(t)) step_round(t, on_row);
}

}  // namespace apiclab
