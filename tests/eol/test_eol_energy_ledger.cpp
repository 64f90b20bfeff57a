// An object that hits a floor gains energy under eol when its grid lands turned to
// the floor (and under eulerian). The energy ledger (sim/eol/energy_ledger.hpp) says which
// stage of the step adds it. Measured with the node-plane rows (solver.contact nodes; the drop
// below, ledger from t = 0 to the most compressed step of the impact):
// - the spin is not the cause; the angle of the object's grid to the floor when it lands is
//   (the frame turns with the spin). Without spin, the grid turned 45°: +58 % of the energy
//   the impact brings (3D +64 %); turned 0° or 90°: no gain (2D).
// - the gain is W_e + ΔΨ > 0: the advection of X by v* (eq 15) leaves more elastic energy
//   than the elastic forces took out of the velocities. 2D: −0.036 J aligned, +0.204 J
//   turned 45°, +0.060 J for the Eulerian baseline (aligned, but the whole body moves through
//   its grid). The plane rows dissipate 0.02–0.03 J in each; gravity's work returns to G,
//   and f_qvv's and the advection of v return or dissipate theirs.
// - not friction: a sticky floor gives the same numbers (+57 % turned, none aligned).
// The cause: one row per node behind the plane makes a staircase of constrained nodes when the
// grid is turned, a node-scale kink in v* along the floor that the advection of X turns into
// elastic energy. The surface rows of eqs 27-29 (solver.contact surface, the default) bound the
// surface's volume behind the plane per collision cell instead: W_e + ΔΨ is −0.003 J aligned,
// −0.019 J at 22° and 70°, −0.032 J at 45° (2D), and no angle gains (the acceptance test below;
// the Eulerian baseline +0.5 % 2D, +0.7 % 3D of what the impact brings).
// These tests hold the ledger to the diagnostics and the other stages to dissipating.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "tests/eol/eol_test_scenes.hpp"

namespace apiclab {
namespace {

using namespace apiclab::eol;

struct DropResult {
  // Over the run, up to the step of the highest energy, up to the most compressed step.
  EnergyLedger ledger, at_peak, at_compression;
  double e0 = 0, gain = 0, released = 0, closure = 0, scale = 0, dt_max = 0;
};

// A ball thrown down onto a slip floor (a collider plane) past its first bounce, its grid
// turned by `tilt` about z before it starts (a ball about its own centre: the material does
// not move, X = p + y still, so only the grid's angle to the floor changes).
template <int D>
DropResult drop(double tilt, const std::string& method = "eol", const std::string& contact = "") {
  test::EolSceneSpec spec;
  spec.contact = contact;
  spec.dim = D;
  spec.method = method;
  spec.radius = 0.15;
  spec.dx = D == 2 ? 1.0 / 40 : 1.0 / 16;
  spec.center = {0.5, 0.4, 0.5};
  spec.velocity = {0, -2.5, 0};
  spec.gravity = {0, -9.8, 0};
  spec.end = 0.16;
  spec.colliders = nlohmann::json::array(
      {{{"type", "plane"},
        {"point", std::vector<double>(std::size_t(D), 0.0)},
        {"normal", D == 2 ? std::vector<double>{0, 1} : std::vector<double>{0, 1, 0}},
        {"condition", "slip"}}});
  spec.colliders[0]["point"][1] = 0.1;
  auto sim = test::make_eol<D>(spec);
  auto& o = sim->objects()[0];
  if constexpr (D == 2)
    o.frame.angle = tilt;  // eulerian: tilt 0 only (its frame is the world)
  else
    o.frame.q = Eigen::Quaterniond(Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitZ()));
  sim->spatial_state(o);
  sim->reset_energy_reference();
  sim->record_energy_ledger(true);
  DropResult r;
  r.e0 = sim->measure().total;
  double worst = -1e300, most_elastic = 0;
  const auto failure = sim->advance_to(spec.end, [&](const DiagnosticsRow& row) {
    if (row.total > worst) r.at_peak = sim->energy_ledger();
    if (row.elastic > most_elastic) {
      most_elastic = row.elastic;
      r.at_compression = sim->energy_ledger();
    }
    worst = std::max(worst, row.total);
    r.dt_max = std::max(r.dt_max, row.dt);
  });
  EXPECT_FALSE(failure) << failure->message;
  r.ledger = sim->energy_ledger();
  r.gain = worst - r.e0;
  // What the impact brings: the kinetic energy at t = 0 and the fall to the floor.
  r.released = 0.5 * sim->total_mass() * 2.5 * 2.5 + sim->total_mass() * 9.8 * 0.15;
  const EnergyLedger& l = r.ledger;
  r.closure = l.total_change() - (sim->measure().total - r.e0);
  r.scale = std::abs(l.elastic_work) + std::abs(l.elastic_change) + std::abs(l.gravity_work) +
            std::abs(l.gravity_change) + std::abs(l.qvv_work) +
            std::abs(l.transport_kinetic_change) + std::abs(l.impulse_loss);
  const EnergyLedger& p = r.at_peak;
  const EnergyLedger& c = r.at_compression;
  std::printf(
      "[eol ledger] %s %s %dD drop, grid at %2.0f deg to the floor: max (E - E0) = %+.3e J of "
      "%.3e J (%+.1f %%); to the peak / to the end: W_e + dPsi %+.3e / %+.3e, W_g + dG %+.3e / "
      "%+.3e, W_qvv + dK_transport %+.3e / %+.3e, impulse loss %.3e / %.3e (min per step "
      "%+.1e); closure %.1e; at the most compressed step: W_e + dPsi %+.3e, impulse loss %.3e, "
      "dE %+.3e\n",
      method.c_str(), contact.empty() ? "default" : contact.c_str(), D, tilt * 180 / M_PI, r.gain,
      r.released, 100 * r.gain / r.released, p.elastic_residual(), l.elastic_residual(),
      p.gravity_residual(), l.gravity_residual(), p.qvv_residual(), l.qvv_residual(),
      p.impulse_loss, l.impulse_loss, l.min_step_impulse_loss, r.closure, c.elastic_residual(),
      c.impulse_loss, c.total_change());
  return r;
}

// The ledger adds up to the diagnostics' total energy (its K, G and Ψ are measure()'s), and
// every stage but the elastic transport dissipates: the impulse and plane rows never add
// kinetic energy beyond the forces' work (loss ≥ 0 in every step, the rows only remove normal
// velocity), and gravity's and f_qvv's work return to G and K. Aligned grid and turned grid.
// Both contact kinds: the surface rows (eqs 27-29) and the node-plane rows.
template <int D>
void check_ledger_with(double tilt, const std::string& method, const std::string& contact) {
  const DropResult r = drop<D>(tilt, method, contact);
  const EnergyLedger& l = r.ledger;
  EXPECT_LT(std::abs(r.closure), 1e-10 * r.scale) << D << "D, tilt " << tilt;
  // A step's loss ½ Σ m|u⁺ − u|² is ≥ 0 exactly; its round-off is that of W − ΔK.
  EXPECT_GE(l.min_step_impulse_loss, -1e-13 * r.scale) << D << "D, tilt " << tilt;
  EXPECT_LE(l.gravity_residual() + l.qvv_residual() - l.impulse_loss, 0.0)
      << D << "D, tilt " << tilt << ", " << contact;
}

template <int D>
void check_ledger(double tilt, const std::string& method = "eol") {
  for (const char* contact : {"surface", "nodes"}) check_ledger_with<D>(tilt, method, contact);
}

TEST(EolEnergyLedger, AddsUpAndOnlyTheElasticTransportCanGain2D) {
  check_ledger<2>(0.0);
  check_ledger<2>(M_PI / 4);
  check_ledger<2>(0.0, "eulerian");
}

TEST(EolEnergyLedger, AddsUpAndOnlyTheElasticTransportCanGain3D) {
  check_ledger<3>(0.0);
  check_ledger<3>(M_PI / 4);
  check_ledger<3>(0.0, "eulerian");
}

// The diagnostics CSV's ledger columns (solver.ledger): the stages of every step add up to the
// row's change of energy, momentum and angular momentum, and the floor's rows act in `walls`.
TEST(EolEnergyLedger, CsvStagesAddUpToTheStep) {
  test::EolSceneSpec spec;
  spec.radius = 0.15;
  spec.dx = 1.0 / 40;
  spec.center = {0.5, 0.4, 0.5};
  spec.velocity = {0, -2.5, 0};
  spec.gravity = {0, -9.8, 0};
  spec.spin = 1;
  spec.colliders = nlohmann::json::array(
      {{{"type", "plane"}, {"point", {0.0, 0.1}}, {"normal", {0, 1}}, {"condition", "slip"}}});
  SceneDesc scene = parse_scene_text(test::eol_scene_json(spec), "eol-test.json");
  scene.solver.ledger = true;
  auto sim = make_simulation(scene);
  DiagnosticsRow before = sim->measure();
  ASSERT_TRUE(before.ledger);
  double walls = 0;
  const auto failure = sim->advance_to(0.1, [&](const DiagnosticsRow& row) {
    ConservedSums sum;
    double scale_E = std::abs(before.total) + std::abs(row.kinetic) + std::abs(row.potential);
    for (const ConservedSums& c : row.stages) {
      sum += c;
      scale_E += std::abs(c.energy);
    }
    EXPECT_NEAR(sum.energy, row.total - before.total, 1e-10 * scale_E) << "step " << row.step;
    for (int a = 0; a < 2; ++a)
      EXPECT_NEAR(sum.p[std::size_t(a)], row.p[std::size_t(a)] - before.p[std::size_t(a)],
                  1e-12 * (std::abs(before.p[1]) + sim->total_mass()))
          << "step " << row.step;
    EXPECT_NEAR(sum.L[2], row.L[2] - before.L[2], 1e-12 * (std::abs(before.L[2]) + 1))
        << "step " << row.step;
    walls += std::abs(row.stages[std::size_t(LedgerStage::walls)].p[1]);
    before = row;
  });
  EXPECT_FALSE(failure);
  EXPECT_GT(walls, 0.1 * sim->total_mass()) << "the floor never acted";
}

// The grid aligned with the floor (0° or 90°: the floor's rows are a row of nodes): no gain
// beyond the bound of the existing drop test (the symplectic bound on the released energy).
TEST(EolEnergyLedger, DropWithTheGridAlignedToTheFloorNeverGainsEnergy) {
  for (const double tilt : {0.0, M_PI / 2}) {
    const DropResult r = drop<2>(tilt);
    const double c_p = std::sqrt(1000.0 * 0.7 / (1.3 * 0.4) / 1.0);
    const double bound = 0.5 * r.dt_max * 2 * c_p / 0.15 * r.released;
    EXPECT_LE(r.gain, bound) << "tilt " << tilt;
  }
}

// The acceptance test: the surface contact rows (eqs 27-29, the default) at every angle
// of the grid to the floor, 2D and 3D. With solver.contact nodes (one row per node behind the
// floor) it fails: 2D +6.5e-02 J at 22°, +1.9e-01 J at 45°, +5.7e-02 J at 70°; 3D at 45°
// +4.2e-02 J (the table below prints them).
template <int D>
void check_no_gain(double tilt) {
  const DropResult r = drop<D>(tilt);
  const double c_p = std::sqrt(1000.0 * 0.7 / (1.3 * 0.4) / 1.0);
  const double bound = 0.5 * r.dt_max * 2 * c_p / 0.15 * r.released;
  EXPECT_LE(r.gain, bound) << D << "D, tilt " << tilt;
}

TEST(EolEnergyLedger, DropWithTheGridTurnedToTheFloorNeverGainsEnergy) {
  for (const double deg : {11.0, 22.0, 45.0, 70.0}) check_no_gain<2>(deg * M_PI / 180);
  check_no_gain<3>(M_PI / 4);
}

// The measurement behind the contact table (docs/eol.md): both contact kinds, eol at 0°, 22°, 45°,
// 70° (2D) and 45° (3D), and the Eulerian baseline. A tool, not a check (it only prints):
//   build/tests/apiclab_tests --gtest_filter='*ContactTable*' --gtest_also_run_disabled_tests
TEST(EolEnergyLedger, DISABLED_ContactTable) {
  for (const char* contact : {"nodes", "surface"}) {
    for (const double deg : {0.0, 22.0, 45.0, 70.0}) drop<2>(deg * M_PI / 180, "eol", contact);
    drop<2>(0.0, "eulerian", contact);
    drop<3>(M_PI / 4, "eol", contact);
    drop<3>(0.0, "eulerian", contact);
  }
}

}  // namespace
}  // namespace apiclab
