// The plastic model (Fan et al. 2013, Sec 3.7, eqs 34-37) in the EoL solver, with F_p⁻¹ at
// material samples, and in its MPM twin, with F_p⁻¹ per particle: eq 37 keeps the volume, below
// yield nothing changes, the samples never smear (an advected F_p does), a checkpoint resumes
// bit for bit, and a rod leaves a dent where it pressed and nowhere else.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "sim/eol/eol_simulation.hpp"
#include "sim/eol/grid/advection.hpp"
#include "sim/mpm/mpm.hpp"
#include "sim/mpm/probe.hpp"
#include "sim/plasticity.hpp"
#include "sim/scene/scene.hpp"
#include "sim/simulation.hpp"
#include "sim/state_io.hpp"

namespace apiclab {
namespace {

using nlohmann::json;
constexpr double kEps = 2.220446049250313e-16;

// A disk of plastic material (2D), as the shipped scenes write one; `extra` merged last.
json plastic_disk(double yield, const json& extra = json::object()) {
  json scene = {
      {"name", "plastic-test"},
      {"dim", 2},
      {"domain", {{"min", {0, 0}}, {"max", {1, 1}}, {"dx", 1.0 / 32}, {"boundary", "separate"}}},
      {"gravity", {0, -9.8}},
      {"time", {{"end", 1}, {"fps", 24}, {"dt", {{"rule", "elastic"}, {"nu", 0.3}}}}},
      {"solver", {{"method", "eol"}}},
      {"materials",
       {{{"name", "clay"},
         {"model", "plastic"},
         {"E", 1000},
         {"nu", 0.3},
         {"rho", 1},
         {"yield_stress", yield}}}},
      {"objects",
       {{{"shape", {{"type", "ball"}, {"center", {0.5, 0.3}}, {"radius", 0.15}}},
         {"material", 0},
         {"velocity", {0, -2}}}}}};
  scene.merge_patch(extra);
  return scene;
}

std::unique_ptr<Simulation> make(const json& scene) {
  return make_simulation(parse_scene_text(scene.dump(), "plastic-test.json"));
}
eol::EolSimulation<double, 2>& eol2(Simulation& s) {
  return dynamic_cast<eol::EolSimulation<double, 2>&>(s);
}
MpmSimulation<double, 2>& mpm2(Simulation& s) { return dynamic_cast<MpmSimulation<double, 2>&>(s); }

bool all_identity(const std::vector<Mat<double, 2>>& f) {
  const Mat<double, 2> I = Mat<double, 2>::Identity();
  for (const auto& m : f)
    if (std::memcmp(m.data(), I.data(), sizeof(m)) != 0) return false;
  return true;
}

// Eq 37 on random elastic gradients: det ΔF_p⁻¹ = 1 to round-off whenever it flows, the
// deviatoric stress falls (to the yield surface for ν = 1 in the small-strain limit), and
// below yield it reports no flow.
TEST(Plasticity, UpdateKeepsVolumeAndSkipsBelowYield) {
  std::mt19937 rng(44);
  std::uniform_real_distribution<double> u(-0.4, 0.4);
  const Lame<double> l{385, 577};
  int flowed = 0;
  double worst = 0;
  for (int k = 0; k < 2000; ++k) {
    Mat<double, 3> F = Mat<double, 3>::Identity();
    for (int i = 0; i < 9; ++i) F.data()[i] += u(rng);
    if (!(F.determinant() > 0.2)) continue;
    const double norm = deviatoric_stress_norm<double, 3>(F, l);
    Mat<double, 3> d = Mat<double, 3>::Constant(7.0);
    const PlasticParams<double> p{100, 1};
    const bool flows = plastic_flow_step<double, 3>(F, l, p, d);
    ASSERT_EQ(flows, norm > p.yield_stress);
    if (!flows) {
      EXPECT_TRUE((d == Mat<double, 3>::Constant(7.0)));  // untouched
      continue;
    }
    ++flowed;
    worst = std::max(worst, std::abs(d.determinant() - 1));
    const Mat<double, 3> Fd = F * d;
    EXPECT_LT((deviatoric_stress_norm<double, 3>(Fd, l)), norm);
  }
  EXPECT_GT(flowed, 100);
  EXPECT_LE(worst, 1e-12);
  std::printf("eq 37 on %d flowing F_e: max |det dFp^-1 - 1| = %.2e\n", flowed, worst);
}

// The plastic keys through the registry's one-line messages: the plastic model requires its yield
// stress, the elastic models refuse both keys, each range is checked, and EoL's implicit
// elasticity refuses a plastic material.
TEST(Plasticity, KeysAreValidated) {
  const auto message = [](const json& scene) -> std::string {
    try {
      make(scene);
    } catch (const SceneError& e) {
      return e.what();
    }
    return "accepted";
  };
  json scene = plastic_disk(30);
  scene["materials"][0].erase("yield_stress");
  EXPECT_EQ(message(scene),
            "plastic-test.json: key 'materials.0.yield_stress': required key is "
            "missing (model plastic)");
  scene["materials"][0]["model"] = "neo-hookean";
  scene["materials"][0]["flow_rate"] = 0.5;
  EXPECT_EQ(message(scene),
            "plastic-test.json: key 'materials.0.flow_rate': only the plastic model reads it");
  for (const auto& [key, value] : {std::pair{"yield_stress", -1.0}, std::pair{"flow_rate", 0.0},
                                   std::pair{"flow_rate", 1.5}}) {
    json bad = plastic_disk(30);
    bad["materials"][0][key] = value;
    EXPECT_NE(message(bad).find(std::string("'materials.0.") + key + "'"), std::string::npos);
    EXPECT_NE(message(bad).find("outside the allowed range"), std::string::npos) << message(bad);
  }
  EXPECT_EQ(message(plastic_disk(30, {{"solver", {{"elasticity", "implicit"}}}})),
            "plastic-test.json: key 'solver.elasticity': the plastic model needs explicit "
            "elasticity under eol");
  EXPECT_EQ(message(plastic_disk(30, {{"solver", {{"method", "mpm"}}}})), "accepted");
}

// Below the yield stress a whole run leaves F_p = I bit for bit, in both families: a disk thrown
// on the ground at 2 m/s, through its impact (0.07 s) and rebound.
TEST(EolPlasticity, BelowYieldFpStaysIdentityForAWholeRun) {
  for (const char* method : {"eol", "mpm"}) {
    SCOPED_TRACE(method);
    auto sim = make(plastic_disk(1e9, {{"solver", {{"method", method}}}}));
    for (int s = 0; sim->time() < 0.3; ++s) {
      ASSERT_FALSE(sim->step(0.3));
      if (std::string(method) == "eol") {
        const auto& o = eol2(*sim).objects()[0];
        ASSERT_EQ(o.plastic.flowed, 0u);
        ASSERT_TRUE(all_identity(o.plastic.fp_inv)) << "step " << s;
      } else {
        ASSERT_EQ(mpm2(*sim).plastic_flowed(), 0u);
        ASSERT_TRUE(all_identity(MpmProbe(mpm2(*sim)).particles().fp_inv)) << "step " << s;
      }
    }
  }
}

// A disk thrown on the ground above its yield stress flows: every update keeps det ΔF_p⁻¹ = 1
// to 1e-12, and det F_p⁻¹ at the end drifts by no more than its updates × ε.
TEST(EolPlasticity, EveryUpdateKeepsTheVolume) {
  for (const char* method : {"eol", "mpm"}) {
    SCOPED_TRACE(method);
    auto sim = make(plastic_disk(30, {{"solver", {{"method", method}}}}));
    std::size_t updates = 0;
    double worst = 0;
    int steps = 0;
    while (sim->time() < 0.3) {
      ASSERT_FALSE(sim->step(0.3));
      ++steps;
      const bool eol = std::string(method) == "eol";
      const double err =
          eol ? eol2(*sim).objects()[0].plastic.det_error : mpm2(*sim).plastic_det_error();
      updates += eol ? eol2(*sim).objects()[0].plastic.flowed : mpm2(*sim).plastic_flowed();
      ASSERT_LE(err, 1e-12) << "step " << steps;
      worst = std::max(worst, err);
    }
    const auto& fp = std::string(method) == "eol" ? eol2(*sim).objects()[0].plastic.fp_inv
                                                  : MpmProbe(mpm2(*sim)).particles().fp_inv;
    double drift = 0;
    for (const auto& m : fp) drift = std::max(drift, std::abs(m.determinant() - 1));
    EXPECT_GT(updates, 100u);
    EXPECT_LE(drift, steps * kEps * 8);
    std::printf(
        "%s: %d steps, %zu updates, max |det dFp^-1 - 1| = %.2e, max |det Fp^-1 - 1| = "
        "%.2e (steps x eps = %.2e)\n",
        method, steps, updates, worst, drift, steps * kEps);
  }
}

// F_p⁻¹ at node y of the object's grid, looked up through its X (the exact material value).
Mat<double, 2> through_X(const eol::EolObject<double, 2>& o, std::size_t i) {
  return o.plastic.at(o.grid.X[i]);
}

// A stripe of plastic stretch F_p⁻¹ = diag(1.1, 1/1.1) across the material at x, as if a rod had
// left it there.
void stripe(eol::PlasticSamples<double, 2>& s, double x) {
  for (std::size_t i = 0; i < s.size(); ++i)
    if (std::abs(s.position(i)[0] - x) < 1.5 * s.h) {
      s.fp_inv[i] = Vec<double, 2>(1.1, 1 / 1.1).asDiagonal();
      s.identity[i] = 0;
    }
}

// Matrices bit-identical to `a` and to `b`, counted; -1 when some matrix is neither.
std::pair<long, long> count_bitwise(const std::vector<Mat<double, 2>>& f, const Mat<double, 2>& a,
                                    const Mat<double, 2>& b) {
  long na = 0, nb = 0;
  for (const auto& m : f) {
    if (std::memcmp(m.data(), a.data(), sizeof(m)) == 0)
      ++na;
    else if (std::memcmp(m.data(), b.data(), sizeof(m)) == 0)
      ++nb;
    else
      return {-1, -1};
  }
  return {na, nb};
}

// A disk with the stripe carried 20 diameters at 0.6 m/s while it spins at π rad/s for 10 s (five
// turns), below yield: EoL's samples keep F_p⁻¹ bit for bit (they are never advected), and so do
// the MPM twin's particles (APIC; it sorts them, so the stripe's and the identity's particles are
// counted).
TEST(EolPlasticity, MaterialSamplesDoNotSmear) {
  const double seconds = 10;
  const Mat<double, 2> I = Mat<double, 2>::Identity(),
                       S = Vec<double, 2>(1.1, 1 / 1.1).asDiagonal();
  for (const char* method : {"eol", "mpm"}) {
    // The stripe, written after set-up, holds elastic energy the blow-up check's reference (the
    // set-up's forces) lacks: at 0.6 m/s it is over 10× the disk's kinetic energy.
    auto sim = make(plastic_disk(
        1e4, {{"solver", {{"method", method}, {"blowup_energy_factor", 1000}}},
              {"domain", {{"max", {8, 1}}, {"dx", 1.0 / 16}, {"boundary", "slip"}}},
              {"gravity", {0, 0}},
              {"objects",
               {{{"shape", {{"type", "ball"}, {"center", {0.5, 0.5}}, {"radius", 0.15}}},
                 {"material", 0},
                 {"velocity", {20 * 0.3 / seconds, 0}},
                 {"angular_velocity", M_PI}}}}}));
    const bool eol = std::string(method) == "eol";
    std::vector<Mat<double, 2>>* fp = nullptr;
    if (eol) {
      stripe(eol2(*sim).objects()[0].plastic, 0.5);
      fp = &eol2(*sim).objects()[0].plastic.fp_inv;
      eol2(*sim).reset_energy_reference();
    } else {
      auto& p = MpmProbe(mpm2(*sim)).particles();
      for (std::size_t q = 0; q < p.size(); ++q)
        if (std::abs(p.x[q][0] - 0.5) < 1.5 / 16) p.fp_inv[q] = S;
      MpmProbe(mpm2(*sim)).particles_written(false);
      fp = &p.fp_inv;
    }
    const auto start = *fp;
    const auto counts = count_bitwise(start, I, S);
    ASSERT_GT(counts.second, 0) << method;
    while (sim->time() < seconds) {
      const auto failure = sim->step(seconds);
      ASSERT_FALSE(failure) << method << ": " << failure->message;
    }
    if (eol) {
      EXPECT_EQ(std::memcmp(start.data(), fp->data(), start.size() * sizeof(start[0])), 0);
      EXPECT_EQ(eol2(*sim).objects()[0].plastic.flowed, 0u);
      const double travelled = eol2(*sim).objects()[0].frame.p[0] - 0.5;
      EXPECT_NEAR(travelled, 20 * 0.3, 0.01 * 0.3);
    } else {
      EXPECT_EQ(count_bitwise(*fp, I, S), counts);
      EXPECT_EQ(mpm2(*sim).plastic_flowed(), 0u);
    }
    std::printf(
        "%s, 20 diameters and %.1f turns in %.0f s: F_p^-1 of %ld stripe and %ld other %s "
        "bit-identical\n",
        method, seconds / 2, seconds, counts.second, counts.first, eol ? "samples" : "particles");
  }
}

// The same stripe under the Eulerian baseline, carried a diameter at 1 m/s while it spins at
// 2 rad/s: the samples keep it bit for bit, while the stripe stored on the baseline's nodes and
// advected by its v* each step (a test-only Eulerian F_p) smears, measured against the exact
// stripe read through X.
TEST(EolPlasticity, AnAdvectedFpSmears) {
  auto sim = make(
      plastic_disk(1e4, {{"solver", {{"method", "eulerian"}}},
                         {"domain", {{"max", {0.9, 0.6}}, {"dx", 0.03}}},
                         {"gravity", {0, 0}},
                         {"objects",
                          {{{"shape", {{"type", "ball"}, {"center", {0.3, 0.3}}, {"radius", 0.15}}},
                            {"material", 0},
                            {"velocity", {1, 0}},
                            {"angular_velocity", 2.0}}}}}));
  auto& e = eol2(*sim);
  stripe(e.objects()[0].plastic, 0.3);
  e.reset_energy_reference();
  const auto& o = e.objects()[0];
  const auto start = o.plastic.fp_inv;
  std::vector<Vec<double, 2>> col[2], out(o.grid.size());
  for (int c = 0; c < 2; ++c)
    for (std::size_t i = 0; i < o.grid.size(); ++i) col[c].push_back(through_X(o, i).col(c));
  while (sim->time() < 0.3) {
    const double t0 = sim->time();
    ASSERT_FALSE(sim->step(10));
    for (int c = 0; c < 2; ++c) {
      eol::advect(o.grid, o.vstar, sim->time() - t0, col[c], out, false);
      col[c] = out;
    }
  }
  EXPECT_EQ(std::memcmp(start.data(), o.plastic.fp_inv.data(), start.size() * sizeof(start[0])), 0);
  double smear = 0, held = 0;
  for (std::size_t i = 0; i < o.grid.size(); ++i) {
    if (!(o.grid.fill[i] >= 0.5)) continue;
    Mat<double, 2> advected;
    advected << col[0][i], col[1][i];
    const Mat<double, 2> exact = through_X(o, i);
    smear = std::max(smear, (advected - exact).norm());
    held = std::max(held, (exact - Mat<double, 2>::Identity()).norm());
  }
  EXPECT_GT(smear, 0.5 * held);  // the advected stripe has spread across cells
  std::printf(
      "eulerian, 0.3 s at 1 m/s and 2 rad/s: samples bit-identical; advected F_p^-1 off "
      "by %.3f (Frobenius, the stripe's own size %.3f)\n",
      smear, held);
}

// A plastic run saved mid-way and loaded into a fresh solver continues bit for bit: EoL's F_p⁻¹,
// its placements and the grid; the MPM twin's F_p⁻¹, F and positions.
TEST(EolPlasticity, ResumeFromACheckpointIsBitIdentical) {
  const auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
  };
  for (const char* method : {"eol", "mpm"}) {
    SCOPED_TRACE(method);
    const json scene = plastic_disk(30, {{"solver", {{"method", method}}}});
    auto a = make(scene);
    for (int s = 0; s < 150; ++s) ASSERT_FALSE(a->step(0.3));
    std::string bytes;
    StateWriter w(bytes);
    a->save_state(w);
    auto b = make(scene);
    StateReader r(bytes.data(), bytes.size());
    b->load_state(r);
    EXPECT_EQ(r.left(), 0u);
    for (int s = 0; s < 150; ++s) {
      ASSERT_FALSE(a->step(0.3));
      ASSERT_FALSE(b->step(0.3));
    }
    if (std::string(method) == "mpm") {
      const auto &pa = MpmProbe(mpm2(*a)).particles(), &pb = MpmProbe(mpm2(*b)).particles();
      EXPECT_FALSE(all_identity(pa.fp_inv));
      EXPECT_TRUE(same(pa.fp_inv, pb.fp_inv));
      EXPECT_TRUE(same(pa.F, pb.F));
      EXPECT_TRUE(same(pa.x, pb.x));
      continue;
    }
    const auto &oa = eol2(*a).objects()[0], &ob = eol2(*b).objects()[0];
    EXPECT_FALSE(all_identity(oa.plastic.fp_inv));
    EXPECT_TRUE(same(oa.plastic.fp_inv, ob.plastic.fp_inv));
    EXPECT_TRUE(same(oa.plastic.y, ob.plastic.y));
    EXPECT_TRUE(same(oa.grid.X, ob.grid.X));
    EXPECT_TRUE(same(oa.grid.v, ob.grid.v));
  }
}

// The permanent displacement of a body's surface points: rest positions `X` against current
// ones `x`, after the best-fit rigid transform (2D Kabsch). The largest within `near` of the
// point the rod pressed (rest coordinates), within `near` of the point the floor pressed back,
// and farther than `far` from both.
struct Dent {
  double dent = 0, floor = 0, elsewhere = 0;
};
Dent permanent_dent(const std::vector<Vec<double, 2>>& X, const std::vector<Vec<double, 2>>& x,
                    const Vec<double, 2>& pressed, const Vec<double, 2>& floor, double near,
                    double far) {
  Vec<double, 2> Xc = Vec<double, 2>::Zero(), xc = Vec<double, 2>::Zero();
  for (std::size_t k = 0; k < X.size(); ++k) {
    Xc += X[k] / double(X.size());
    xc += x[k] / double(X.size());
  }
  double dot = 0, cross = 0;
  for (std::size_t k = 0; k < X.size(); ++k) {
    const Vec<double, 2> a = X[k] - Xc, b = x[k] - xc;
    dot += a.dot(b);
    cross += a[0] * b[1] - a[1] * b[0];
  }
  const Mat<double, 2> R = Eigen::Rotation2Dd(std::atan2(cross, dot)).toRotationMatrix();
  Dent d;
  for (std::size_t k = 0; k < X.size(); ++k) {
    const double moved = (R * (X[k] - Xc) + xc - x[k]).norm();
    const double to_rod = (X[k] - pressed).norm(), to_floor = (X[k] - floor).norm();
    if (to_rod < near) d.dent = std::max(d.dent, moved);
    if (to_floor < near) d.floor = std::max(d.floor, moved);
    if (to_rod > far && to_floor > far) d.elsewhere = std::max(d.elsewhere, moved);
  }
  return d;
}

// Fig 1c (assets/scenes/eol-plastic-cylinders.json, 2 s; about 15 s of wall time, so in the
// extended tier): a rod presses into the top of each of two plastic cylinders on the ground and
// leaves. At the end each keeps a dent of at least 0.5 Δx where the rod pressed, and has moved
// under 0.5 Δx farther than 3/4 of a radius from both the rod's and the floor's contact, under
// EoL and its MPM twin (APIC). Where the floor pressed back is measured, not bounded: the disk is
// squeezed between rod and floor, and flows there too.
TEST(EolSlow, PlasticCylindersKeepADentWhereTheRodPressed) {
  const std::string file =
      std::string(APICLAB_SOURCE_DIR) + "/assets/scenes/eol-plastic-cylinders.json";
  std::printf(
      "| method | cylinder | rod's contact / dx | floor's contact / dx | elsewhere / dx |\n"
      "|---|---|---|---|---|\n");
  for (const char* method : {"eol", "mpm"}) {
    SCOPED_TRACE(method);
    const SceneDesc scene = load_scene(file, {std::string("solver.method=") + method});
    const double dx = scene.domain.dx, r = scene.objects[0].shape.radius;
    auto sim = make_simulation(scene);
    std::vector<std::vector<Vec<double, 2>>> X(2), x(2);
    std::vector<Vec<double, 2>> rest_of_id;
    if (std::string(method) == "mpm") {
      const auto& p = MpmProbe(mpm2(*sim)).particles();
      rest_of_id.resize(p.size());
      for (std::size_t q = 0; q < p.size(); ++q) rest_of_id[std::size_t(p.id[q])] = p.x[q];
    }
    while (sim->time() < scene.time.end - 1e-9) ASSERT_FALSE(sim->step(scene.time.end));
    if (std::string(method) == "eol") {
      auto& e = eol2(*sim);
      e.place_surfaces();
      for (std::size_t k = 0; k < 2; ++k) {
        const auto& o = e.objects()[k];
        for (std::size_t s = 0; s < o.surface.X.size(); ++s) {
          X[k].push_back(o.surface.X[s]);
          x[k].push_back(o.surface_world(s));
        }
      }
    } else {
      const auto& p = MpmProbe(mpm2(*sim)).particles();
      for (std::size_t q = 0; q < p.size(); ++q) {
        const std::size_t k = std::size_t(p.object[q]);
        const Vec<double, 2> X0 = rest_of_id[std::size_t(p.id[q])];
        const auto& c = scene.objects[k].shape.center;
        if ((X0 - Vec<double, 2>(c[0], c[1])).norm() < r - dx) continue;  // the surface layer
        X[k].push_back(X0);
        x[k].push_back(p.x[q]);
      }
    }
    for (std::size_t k = 0; k < 2; ++k) {
      const auto& c = scene.objects[k].shape.center;
      const Dent d = permanent_dent(X[k], x[k], Vec<double, 2>(c[0], c[1] + r),
                                    Vec<double, 2>(c[0], c[1] - r), 2 * dx, 0.75 * r);
      std::printf("| %s | %zu | %.2f | %.2f | %.2f |\n", method, k, d.dent / dx, d.floor / dx,
                  d.elsewhere / dx);
      EXPECT_GE(d.dent, 0.5 * dx) << "cylinder " << k;
      EXPECT_LT(d.elsewhere, 0.5 * dx) << "cylinder " << k;
    }
  }
}

}  // namespace
}  // namespace apiclab
