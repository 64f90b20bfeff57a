// Contact between objects in the EoL step (2D): objects whose grid boxes meet take one QP of
// eq 29 over their pair rows and plane rows (sim/eol/contact/eol_contact.hpp). Two elastic disks
// thrown head-on at ±1 m/s bounce off each other; objects whose boxes never meet step exactly as
// they would alone.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "tests/eol/eol_test_scenes.hpp"

namespace apiclab {
namespace {

using namespace apiclab::eol;

// Two disks of radius 0.15 m (eol-drop's jelly, Δx 0.025) centred at x = left, right, y = y,
// thrown at each other at ±speed (and at vy) in a 1.2 × 0.6 m box, no gravity.
std::unique_ptr<EolSimulation<double, 2>> two_disks(double left, double right, double speed,
                                                    double end, double contact_cell = 0,
                                                    double y = 0.3, double vy = 0,
                                                    const std::string& method = "eol") {
  test::EolSceneSpec spec;
  spec.method = method;
  spec.domain_max = {1.2, 0.6};
  spec.dx = 0.025;
  spec.radius = 0.15;
  spec.center = {left, y};
  spec.velocity = {speed, vy};
  spec.E = 2000;
  spec.boundary = "separate";
  spec.end = end;
  spec.fps = 24;
  nlohmann::json scene = nlohmann::json::parse(test::eol_scene_json(spec));
  scene["solver"]["contact_cell"] = contact_cell;
  nlohmann::json second = scene["objects"][0];
  second["shape"]["center"] = {right, y};
  second["velocity"] = {-speed, vy};
  scene["objects"].push_back(second);
  std::unique_ptr<Simulation> sim = make_simulation(parse_scene_text(scene.dump(), "two.json"));
  auto* eol = dynamic_cast<EolSimulation<double, 2>*>(sim.get());
  if (!eol) return nullptr;
  sim.release();
  return std::unique_ptr<EolSimulation<double, 2>>(eol);
}

// An object's mass-weighted centre and velocity over its nodes.
struct ObjectMotion {
  double mass = 0;
  Vec<double, 2> centre = Vec<double, 2>::Zero(), velocity = Vec<double, 2>::Zero();
};

ObjectMotion motion(const EolObject<double, 2>& o) {
  ObjectMotion m;
  for (std::size_t i = 0; i < o.grid.size(); ++i) {
    const double w = o.grid.mass[i];
    if (!(w > 0)) continue;
    m.mass += w;
    m.centre += w * o.x[i];
    m.velocity += w * o.u[i];
  }
  m.centre /= m.mass;
  m.velocity /= m.mass;
  return m;
}

// What both methods' head-on runs must show: contact happened without the disks (r = 0.15)
// passing into each other beyond half a cell, they end apart and moving apart, momentum held to
// 1 % and the energy never above its start beyond the round-off of the sums (1e-12 of E0).
void expect_bounced_apart(long contact_steps, double max_overlap, double cell,
                          const ObjectMotion& a, const ObjectMotion& b, double max_drift,
                          double p_scale, double max_gain, double e0) {
  EXPECT_GT(contact_steps, 0);
  EXPECT_LE(max_overlap, 0.5 * cell);
  EXPECT_LT(a.centre[0] + 0.15, b.centre[0] - 0.15);
  EXPECT_LT(a.velocity[0], 0.0);
  EXPECT_GT(b.velocity[0], 0.0);
  EXPECT_LT(max_drift, 0.01 * p_scale);
  EXPECT_LE(max_gain, 1e-12 * e0);
}

// The acceptance test: the disks meet at t ≈ 0.05 s, do not pass through each other (overlap
// |Ω| at most half a cell's area per pair), bounce and move apart; momentum and energy hold.
// Without the object rows (meeting_objects() returning none) they overlap by 0.3 m and swap.
TEST(EolObjectContactStep, TwoDisksThrownHeadOnBounceApart2D) {
  const double end = 0.25;
  auto sim = two_disks(0.4, 0.8, 1.0, end);  // 0.1 m apart
  ASSERT_TRUE(sim);
  const EolSimulation<double, 2>& s = *sim;
  ASSERT_EQ(s.objects().size(), 2u);
  sim->record_energy_ledger(true);
  const DiagnosticsRow start = s.measure();
  const ObjectMotion a0 = motion(s.objects()[0]), b0 = motion(s.objects()[1]);
  const double p_scale = a0.mass * a0.velocity.norm() + b0.mass * b0.velocity.norm();
  const double cell = 0.025 * 0.025;
  double max_overlap = 0, max_gain = -1e300, max_drift = 0, max_rows = 0;
  double before = start.total, max_step_closure = 0;  // |the step's ledger ΔE − its ΔE|
  long contact_steps = 0;
  int max_sweeps = 0;
  double qp_seconds = 0;
  std::map<int, std::array<double, 3>> by_rows;  // rows → solves, sweeps, seconds
  const auto failure = sim->advance_to(end, [&](const DiagnosticsRow& row) {
    for (const auto& pair : s.last_object_pairs())
      max_overlap = std::max(max_overlap, double(pair.volume));
    if (!s.last_object_pairs().empty()) {
      ++contact_steps;
      max_rows = std::max(max_rows, double(s.last_contact_solve().rows));
      max_sweeps = std::max(max_sweeps, s.last_contact_solve().sweeps);
      qp_seconds += s.last_contact_solve().seconds;
      auto& b = by_rows[s.last_contact_solve().rows];
      b[0] += 1;
      b[1] += s.last_contact_solve().sweeps;
      b[2] += s.last_contact_solve().seconds;
    }
    max_gain = std::max(max_gain, row.total - start.total);
    max_step_closure = std::max(
        max_step_closure, std::abs(s.last_step_ledger().total_change() - (row.total - before)));
    before = row.total;
    max_drift = std::max(max_drift, std::hypot(row.p[0] - start.p[0], row.p[1] - start.p[1]));
  });
  ASSERT_FALSE(failure) << failure->message;
  const ObjectMotion a = motion(s.objects()[0]), b = motion(s.objects()[1]);
  const EnergyLedger& l = s.energy_ledger();
  const double closure = l.total_change() - (s.measure().total - start.total);
  std::printf(
      "[eol two disks] %ld contact steps, up to %.0f rows, %d sweeps, QP %.3e s in all; max "
      "overlap %.3e m^2 (%.3f cell); centres %.4f / %.4f m, velocities %+.4f / %+.4f m/s; "
      "momentum drift %.2e of %.3e; max (E - E0) %+.2e J of %.3e J; impulse and QP loss %.3e J, "
      "ledger "
      "closure %.1e (per step at most %.1e), min step loss %+.1e\n",
      contact_steps, max_rows, max_sweeps, qp_seconds, max_overlap, max_overlap / cell, a.centre[0],
      b.centre[0], a.velocity[0], b.velocity[0], max_drift, p_scale, max_gain, start.total,
      l.impulse_loss, closure, max_step_closure, l.min_step_impulse_loss);
  for (const auto& [rows, b] : by_rows)
    std::printf("[eol two disks] QP of %2d rows: %3.0f solves, %5.1f sweeps, %.2e s each\n", rows,
                b[0], b[1] / b[0], b[2] / b[0]);
  expect_bounced_apart(contact_steps, max_overlap, cell, a, b, max_drift, p_scale, max_gain,
                       start.total);
  // The ledger holds the QP's loss and still adds up, every step to the round-off of its sums
  // (measured 2.8e-14 J, 4e-13 E0; over the run's 1,700 steps 1.7e-11 J); each step's loss
  // (over both objects together) is ≥ 0.
  EXPECT_GT(l.impulse_loss, 0.0);
  EXPECT_LT(max_step_closure, 1e-12 * start.total);
  EXPECT_LT(std::abs(closure), 1e-9 * start.total);
  EXPECT_GE(l.min_step_impulse_loss, -1e-13 * start.total);
}

// The Eulerian baseline (solver.method eulerian) with one X and v field per object on the world
// grid (eq 27's v^A, v^B) and the same pair rows and QP: the head-on disks bounce apart instead
// of blowing up (one shared field blew up at t = 0.123 s, the disks 2 cells apart).
TEST(EolObjectContactStep, EulerianTwoDisksThrownHeadOnBounceApart2D) {
  const double end = 0.25;
  auto sim = two_disks(0.4, 0.8, 1.0, end, 0, 0.3, 0, "eulerian");
  ASSERT_TRUE(sim);
  const EolSimulation<double, 2>& s = *sim;
  ASSERT_FALSE(s.lagrangian());
  ASSERT_EQ(s.objects().size(), 2u);
  const DiagnosticsRow start = s.measure();
  const ObjectMotion a0 = motion(s.objects()[0]), b0 = motion(s.objects()[1]);
  const double p_scale = a0.mass * a0.velocity.norm() + b0.mass * b0.velocity.norm();
  const double cell = 0.025 * 0.025;
  double max_overlap = 0, max_gain = -1e300, max_drift = 0;
  long contact_steps = 0;
  const auto failure = sim->advance_to(end, [&](const DiagnosticsRow& row) {
    for (const auto& pair : s.last_object_pairs())
      max_overlap = std::max(max_overlap, double(pair.volume));
    contact_steps += !s.last_object_pairs().empty();
    max_gain = std::max(max_gain, row.total - start.total);
    max_drift = std::max(max_drift, std::hypot(row.p[0] - start.p[0], row.p[1] - start.p[1]));
  });
  ASSERT_FALSE(failure) << failure->message;
  const ObjectMotion a = motion(s.objects()[0]), b = motion(s.objects()[1]);
  std::printf(
      "[eulerian two disks] %ld contact steps; max overlap %.3f cell; centres %.4f / %.4f m, "
      "velocities %+.4f / %+.4f m/s; momentum drift %.2e of %.3e; max (E - E0) %+.2e J of "
      "%.3e J, E at the end %.3e J\n",
      contact_steps, max_overlap / cell, a.centre[0], b.centre[0], a.velocity[0], b.velocity[0],
      max_drift, p_scale, max_gain, start.total, s.measure().total);
  expect_bounced_apart(contact_steps, max_overlap, cell, a, b, max_drift, p_scale, max_gain,
                       start.total);
}

// The pair and the floor in one QP: the disks thrown down and at each other meet each other and
// the floor (the domain's separate wall y = 0) in the same steps. Neither sinks into the floor
// by more than 0.3 Δx (EolSurfaceContact.DropDoesNotSinkIntoTheFloor2D's bound) nor into the
// other by more than half a cell; both bounce up and apart; E never above E₀.
TEST(EolObjectContactStep, TwoDisksMeetingOnTheFloorShareOneQP2D) {
  const double end = 0.15;
  auto sim = two_disks(0.4, 0.8, 1.0, end, 0, 0.2, -1.0);
  ASSERT_TRUE(sim);
  const EolSimulation<double, 2>& s = *sim;
  const double e0 = s.measure().total, cell = 0.025 * 0.025;
  double depth = 0, overlap = 0, gain = -1e300;
  long shared = 0;  // steps whose QP held pair rows and floor rows
  const auto failure = sim->advance_to(end, [&](const DiagnosticsRow& row) {
    std::uint32_t pair_rows = 0;
    for (const auto& pair : s.last_object_pairs()) {
      overlap = std::max(overlap, double(pair.volume));
      pair_rows += pair.rows;
    }
    shared += pair_rows > 0 && std::size_t(s.last_contact_solve().rows) > pair_rows;
    for (const auto& o : s.objects())
      for (std::size_t k = 0; k < o.surface_y.size(); ++k)
        depth = std::max(depth, -o.surface_world(k)[1]);
    gain = std::max(gain, row.total - e0);
  });
  ASSERT_FALSE(failure) << failure->message;
  const ObjectMotion a = motion(s.objects()[0]), b = motion(s.objects()[1]);
  std::printf(
      "[eol two disks on the floor] %ld steps with pair and floor rows in one QP; deepest vertex "
      "%.2e m below the floor, max overlap %.3f cell; velocities (%+.3f, %+.3f) / (%+.3f, "
      "%+.3f) m/s; max (E - E0) %+.1e J of %.3e J\n",
      shared, depth, overlap / cell, a.velocity[0], a.velocity[1], b.velocity[0], b.velocity[1],
      gain, e0);
  EXPECT_GT(shared, 0);
  EXPECT_LT(depth, 0.3 * 0.025);
  EXPECT_LE(overlap, 0.5 * cell);
  EXPECT_GT(a.velocity[1], 0.0);
  EXPECT_GT(b.velocity[1], 0.0);
  EXPECT_LT(a.velocity[0], 0.0);
  EXPECT_GT(b.velocity[0], 0.0);
  EXPECT_LE(gain, 1e-12 * e0);
}

// Objects whose grid boxes never meet take the per-object step: positions after 200 steps are
// bit-identical to each disk stepped alone.
TEST(EolObjectContactStep, ObjectsApartStepAsTheyWouldAlone2D) {
  auto both = two_disks(0.3, 0.9, -0.5, 1);  // 0.3 m apart, thrown apart
  ASSERT_TRUE(both);
  const double dt = 1e-4;
  for (int n = 0; n < 200; ++n) both->step_fixed(dt);
  EXPECT_TRUE(both->last_object_pairs().empty());
  for (int k = 0; k < 2; ++k) {
    test::EolSceneSpec spec;
    spec.domain_max = {1.2, 0.6};
    spec.dx = 0.025;
    spec.radius = 0.15;
    spec.center = {k ? 0.9 : 0.3, 0.3};
    spec.velocity = {k ? 0.5 : -0.5, 0};
    spec.E = 2000;
    spec.boundary = "separate";
    auto alone = test::make_eol<2>(spec);
    ASSERT_TRUE(alone);
    for (int n = 0; n < 200; ++n) alone->step_fixed(dt);
    const auto& o = std::as_const(*alone).objects()[0];
    const auto& p = std::as_const(*both).objects()[std::size_t(k)];
    ASSERT_EQ(o.x.size(), p.x.size());
    for (std::size_t i = 0; i < o.x.size(); ++i) ASSERT_EQ(o.x[i], p.x[i]) << k << " node " << i;
    EXPECT_EQ(o.frame.p, p.frame.p);
  }
}

// Not in the default tier (DISABLED_): the QP's Gauss–Seidel sweeps and time against its rows
// through the head-on collision, the collision cell shrunk to give more rows. Run with
// --gtest_also_run_disabled_tests --gtest_filter='*QPAgainstRowsInTheCollision*'.
TEST(EolObjectContactStep, DISABLED_QPAgainstRowsInTheCollision) {
  for (const double cell : {0.0, 0.0125, 0.00625, 0.003125, 0.0015625}) {
    auto sim = two_disks(0.4, 0.8, 1.0, 0.12, cell);
    const EolSimulation<double, 2>& s = *sim;
    long solves = 0, sweeps = 0, polished = 0;
    double violation = 0;
    int rows = 0, most = 0;
    double seconds = 0, slowest = 0;
    sim->advance_to(0.12, [&](const DiagnosticsRow&) {
      if (s.last_object_pairs().empty()) return;
      const ContactSolveStats& st = s.last_contact_solve();
      ++solves;
      sweeps += st.sweeps;
      polished += st.polished;
      violation = std::max(violation, st.max_violation);
      rows = std::max(rows, st.rows);
      most = std::max(most, st.sweeps);
      seconds += st.seconds;
      slowest = std::max(slowest, st.seconds);
    });
    std::printf(
        "[eol two disks] collision cell %.5f m: %ld solves, up to %d rows, sweeps mean %.1f max "
        "%d, time mean %.2e s max %.2e s; %ld polished, max violation %.1e\n",
        cell > 0 ? cell : 0.025, solves, rows, double(sweeps) / double(solves), most,
        seconds / double(solves), slowest, polished, violation);
  }
}

}  // namespace
}  // namespace apiclab
