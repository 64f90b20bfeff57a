// MPM's time-step rules (registry `dt_rule_choices`): Δt before the Sec 6.7 landing on the
// frame time, which Simulation::step applies to every family (land_on_frame, sim/simulation.hpp).
//
// The CFL rule of Sec 4.3: Δt ≤ ν Δx / max_p (|v_p| + 6√d/Δx ‖B_p‖_F). It bounds the grid
// velocity of eq 24 through |D_p⁻¹ (x_i − x_p)|, which needs D_p = k Δx² I (quadratic k = 1/4,
// cubic k = 1/3); with B_p = C_p D_p = k Δx² C_p the particle term is |v_p| + 6√d k Δx ‖C_p‖_F.
// For the multilinear kernel D_p is not invertible and Sec 5.9 shows the grid velocity of an
// affine particle is unbounded (∇w_ip / w_ip), so there is no CFL bound: the scene reader
// rejects the `cfl` rule with the linear kernel (validate_mpm, sim/mpm/mpm_method.cpp).
#pragma once
#include <cmath>

#include "sim/mpm/mpm.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"

namespace apiclab {

template <class T, int D>
double MpmSimulation<T, D>::choose_dt() {
  const TimeDesc& tm = scene_.time;
  const double dx = scene_.domain.dx;
  double dt_star = tm.dt;
  if (tm.rule != DtRule::fixed) {
    double vmax = 0, cterm = 0;
    const double affine_reach =
        6.0 * std::sqrt(double(D)) * inertia_factor(scene_.solver.kernel) * dx;
    const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
    // The particle term |v_p| + 6√d/Δx ‖B_p‖_F (+ PolyPIC's modes) is the cfl rule's alone; the
    // elastic and two-step rules read only v_max.
    const bool cfl = tm.rule == DtRule::cfl;
    // PolyPIC's higher modes, in the row form P2G uses: two axis functions per axis without the
    // G modes, three with them.
    const bool g_modes = polypic::keeps_g_modes(1 + D + int(p_.modes.size()), D);
#pragma omp parallel for reduction(max : vmax, cterm) if (parallel_worthwhile())
    for (std::ptrdiff_t q = 0; q < n; ++q) {
      double v = double(p_.v[q].norm());
      vmax = std::max(vmax, v);
      if (!cfl) continue;
      double modes = 0;  // PolyPIC: the largest speed its higher modes give a stencil node
      if (!p_.modes.empty()) {
        Stencil<T, D, QuadraticKernel> st;
        st.compute(p_.x[q], grid_);
        const std::size_t p = std::size_t(q);
        modes =
            double(g_modes ? polypic::max_modes_speed_rows<T, D, 3>(st, grid_.inv_dx, p_.modes, p)
                           : polypic::max_modes_speed_rows<T, D, 2>(st, grid_.inv_dx, p_.modes, p));
      }
      // |v_p| + 6√d/Δx ‖B_p‖_F
      cterm = std::max(cterm, v + affine_reach * double(p_.C[q].norm()) + modes);
    }
    if (tm.rule == DtRule::cfl) {
      dt_star = std::min(dt_star, tm.nu * dx / std::max(cterm, 1e-300));
    } else if (tm.rule == DtRule::elastic) {
      dt_star = std::min(dt_star, tm.nu * dx / (max_wave_speed_ + vmax));
    } else {
      // Sec 6.7: dt* = max(dt_min, min(dt_max, ν Δx / max(v_max, v_τ))) with grid speeds.
      vmax = std::max(vmax, max_grid_speed_);
      dt_star = std::max(tm.dt_min, std::min(tm.dt, tm.nu * dx / std::max(vmax, tm.v_tau)));
    }
  }
  return dt_star;
}

}  // namespace apiclab
