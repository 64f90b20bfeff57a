#include "app/figures/catalogue.hpp"

#include <algorithm>
#include <cmath>

#include "app/cli.hpp"

namespace apiclab::figures {
namespace {

double angular_momentum(const DiagnosticsRow& r) { return r.L[2]; }
double total_energy(const DiagnosticsRow& r) { return r.total; }
double kinetic_energy(const DiagnosticsRow& r) { return r.kinetic; }
double time_step(const DiagnosticsRow& r) { return r.dt; }
double grid_nodes(const DiagnosticsRow& r) { return r.grid_nodes; }
double grid_mib(const DiagnosticsRow& r) { return r.grid_bytes / (1024.0 * 1024.0); }
// A ledger stage's ΔL_z (docs/outputs.md, Conservation ledger); none for row 0, the state before
// any step. Charted per |L_z| at t = 0, the scene's scale: a scheme whose L_z decays through zero
// (PIC) would otherwise chart its own denominator.
double stage_dL(const DiagnosticsRow& r, LedgerStage s) {
  if (r.step == 0) return std::nan("");
  return r.stages[std::size_t(s)].L[2];
}
double p2g_dL(const DiagnosticsRow& r) { return stage_dL(r, LedgerStage::p2g); }
double g2p_dL(const DiagnosticsRow& r) { return stage_dL(r, LedgerStage::g2p); }

}  // namespace

const std::vector<std::string>& figure_ids() {
  static const std::vector<std::string> ids{
      "1",     "3", "4", "5", "6", "10", "11", "eol6", "eol7", "eol8", "eol9", "scheme-energy",
      "ledger"};
  return ids;
}

void check_figure_ids(const std::vector<std::string>& only) {
  std::string all;
  for (const std::string& id : figure_ids()) all += (all.empty() ? "" : ",") + id;
  for (const std::string& f : only)
    if (std::find(figure_ids().begin(), figure_ids().end(), f) == figure_ids().end())
      throw cli::UsageError("--only: unknown figure '" + f + "' (expected " + all + ")");
}

bool wanted(const std::vector<std::string>& only, const std::string& id) {
  return only.empty() || std::find(only.begin(), only.end(), id) != only.end();
}

std::vector<TimeFigure> time_figures() {
  const std::vector<std::string> four{"pic", "flip", "apic", "rpic"};
  const Quantity L{"Angular momentum", "angular momentum L [kg m^2/s]", angular_momentum};
  const Quantity E{"Total energy", "total energy E [J]", total_energy};
  const Quantity K{"Kinetic energy", "kinetic energy", kinetic_energy};
  // The disk's moment of inertia stays that of its rest shape (it spins without stretching
  // much), so L_z(t) / L_z(0) is ω(t) / ω₀.
  const Quantity omega{"Angular velocity (L_z / I0)", "omega / omega0 = L_z(t) / L_z(0)",
                       angular_momentum, false, true};
  Quantity dt{"Time step, coloured by the bound that set it", "dt [s]", time_step};
  dt.by_dt_limit = true;
  // Fig 6: what each solver allocated for its grids (EolSimulation::grid_bytes), per step.
  Quantity nodes{"Grid nodes", "grid nodes", grid_nodes};
  Quantity memory{"Grid memory", "grid memory [MiB]", grid_mib};
  nodes.log_y = memory.log_y = true;
  const Quantity KJ{"Kinetic energy", "kinetic energy [J]", kinetic_energy};
  Quantity dt_log = dt;
  dt_log.log_y = true;
  const std::vector<std::string> eol_methods{"eol", "eulerian"};
  Quantity g2p_L{"G2P: |dL_z| / |L_z(0)| per step", "|g2p_dLz / Lz(0)|", g2p_dL};
  Quantity p2g_L{"P2G: |dL_z| / |L_z(0)| per step", "|p2g_dLz / Lz(0)|", p2g_dL};
  g2p_L.log_y = p2g_L.log_y = true;
  g2p_L.per_start = p2g_L.per_start = angular_momentum;
  // Figs 8 and 9 under backward Euler elasticity (docs/eol.md, "Implicit elasticity"): with the
  // paper's explicit elasticity the elastic cap sets every step. Its damping does the
  // viscosity's work, so the scene's Kelvin–Voigt term (an explicit step limit) is left out.
  const std::vector<std::string> implicit{"solver.elasticity=implicit", "materials.0.viscosity=0"};
  // cost: relative run time, so that the job pool starts the longest runs first.
  return {
      {"3",
       "fig3_rotating_disk",
       "Fig. 3 — Rotating elastic disk (Sec. 6.1)",
       "rotating-disk",
       0.5,
       2,
       four,
       L,
       E,
       {}},
      {"4",
       "fig4_cylinder_rebound",
       "Fig. 4 — Rebound of an elastic cylinder (Sec. 6.2)",
       "cylinder-rebound",
       0,
       0,
       four,
       L,
       E,
       {}},
      {"5",
       "fig5_skew_impact",
       "Fig. 5 — Skew impact of two elastic cylinders (Sec. 6.3)",
       "skew-impact",
       0,
       0,
       four,
       L,
       E,
       {}},
      {"6",
       "fig6_ring_collision",
       "Fig. 6 — Collision of two elastic rings (Sec. 6.4)",
       "ring-collision",
       0.004,
       1,
       four,
       L,
       E,
       {}},
      {kRingingFigureId,
       "fig10_ringing_energy",
       "Fig. 10 — Ringing test: energy (Sec. 6.7)",
       "ringing",
       10.0 / 24,
       3,
       {"pic", "flip", "apic"},
       E,
       K,
       {}},
      // Fan et al. 2013 (Eulerian-on-Lagrangian), Figs 6, 7 and 8.
      {"eol6",
       "eol_fig6_translation",
       "Fan et al. 2013, Fig. 6 — Translation: grid EoL and Eulerian allocate",
       "eol-translation",
       0.25,
       3,
       eol_methods,
       nodes,
       memory,
       {},
       true},
      {"eol7",
       "eol_fig7_spin",
       "Fan et al. 2013, Fig. 7 — Spinning disk: EoL against Eulerian",
       "eol-spin",
       0.5,
       4,
       eol_methods,
       omega,
       E,
       {},
       true},
      {"eol8",
       "eol_fig8_two_balls",
       "Fan et al. 2013, Fig. 8 — Time step of EoL through the two-ball collision (implicit "
       "elasticity)",
       "eol-two-balls",
       0.4,
       2,
       {"eol"},
       dt_log,
       KJ,
       {},
       true,
       implicit},
      {"eol9",
       "eol_fig9_two_balls",
       "Fan et al. 2013, Fig. 9 — Time step of the two balls, EoL against Eulerian (implicit "
       "elasticity)",
       "eol-two-balls",
       0.125,  // three frames at 24 fps: EoL's steps 1/fps, none shortened to land on the end
       20,
       eol_methods,
       dt_log,
       KJ,
       {},
       true,
       implicit},
      // Jiang et al. 2017, Sec 5, stage by stage: the conservation ledger's ΔL of each transfer
      // under symplectic Euler, where the paper's transfers are the step's.
      {"ledger",
       "ledger_rotating_disk",
       "Conservation ledger — angular momentum each transfer changes, rotating disk (Sec. 5)",
       "rotating-disk",
       0.5,
       2,
       four,
       g2p_L,
       p2g_L,
       {},
       false,
       {"solver.ledger=true", "solver.integrator=symplectic", "time.dt.rule=fixed",
        "time.dt.value=0.0005"},
       {},
       true},
  };
}

const std::vector<double>& ringing_frame_times() {
  static const std::vector<double> times{2.0 / 24, 5.0 / 24, 40.0 / 24};
  return times;
}

}  // namespace apiclab::figures
