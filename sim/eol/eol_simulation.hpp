// The Eulerian-on-Lagrangian solver (Fan et al. 2013), Algorithm 1 per object:
//   forces (eq 12: elasticity, gravity, f_qvv) → dynamic Δt (Sec 3.6, eq 33)
//   → impulse solve with the surface or node–plane contact rows (eqs 16, 27-29) → least-squares
//   split (eqs 23-24) → frame update q₁ += Δt q̇₁ → advection of v and X by v* (eq 15) →
//   extrapolation.
// Each object has its own rigid frame and grid (eol). The pure-Eulerian baseline (eulerian) is
// the same code with the frame locked to the world and each object's grid over the whole
// domain. Objects that meet share one contact QP (eq 29) over their pair and plane rows.
#pragma once
#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/eol/contact/body_contact.hpp"
#include "sim/eol/contact/contact_qp.hpp"
#include "sim/eol/contact/global_contact.hpp"
#include "sim/eol/contact/impulse_solve.hpp"
#include "sim/eol/energy_ledger.hpp"
#include "sim/eol/frame.hpp"
#include "sim/eol/grid/eulerian_grid.hpp"
#include "sim/eol/grid/extrapolation.hpp"
#include "sim/eol/grid/forces.hpp"
#include "sim/eol/grid/implicit_elasticity.hpp"
#include "sim/eol/grid/viscosity.hpp"
#include "sim/eol/least_squares_split.hpp"
#include "sim/eol/surface/rest_surface.hpp"
#include "sim/eol/time_step.hpp"
#include "sim/simulation.hpp"

namespace apiclab::eol {

template <class T, int D>
struct EolObject {
  RigidFrame<T, D> frame;
  EulerianGrid<T, D> grid;
  std::vector<int> shapes;          // scene objects whose rest shapes live in this grid
  std::vector<std::int32_t> owner;  // per node: the scene object its X falls in (-1: none)
  // Per node, world axes: offset r = R y from the frame origin, position x, velocity u, force.
  std::vector<Vec<T, D>> r, x, u, force, scratch, vstar;
  ElasticForces<T, D> elastic;
  ImplicitElasticity<T, D> implicit;  // solver.elasticity implicit: the backward Euler solve
  ViscousForces<T, D> viscous;        // materials.*.viscosity > 0: Kelvin–Voigt damping
  PlasticSamples<T, D> plastic;       // F_p⁻¹ in material space (Sec 3.7); empty: none plastic
  Extrapolation<T, D> extrapolation;
  // The surface (Sec 3.8): built once in material space; Algorithm 2 places it at frame times
  // (EolSimulation::place_surfaces) at intermediate positions surface_y (world: R y + p), each
  // placement starting from the last one. surface_misses: vertices not found in the last
  // placement (kept where they were).
  RestSurface<D> surface;
  std::vector<Vec<T, D>> surface_y;
  int surface_misses = 0;
  // eulerian: Σ m at set-up; every update_mass scales the node masses back to it (eol_mass.hpp).
  double rest_mass = 0;
  // Grid storage held (Fig 6): every per-node and per-cell array of this object's grid.
  std::size_t grid_bytes() const {
    std::size_t b = grid.bytes() + elastic.bytes() + implicit.bytes() + viscous.bytes() +
                    extrapolation.bytes() + plastic.bytes() + held_bytes(owner);
    for (const auto* f : {&r, &x, &u, &force, &scratch, &vstar}) b += held_bytes(*f);
    return b;
  }
  Vec<T, D> surface_world(std::size_t s) const { return world(surface_y[s]); }
  Vec<T, D> surface_velocity(std::size_t s) const { return grid.interpolate(u, surface_y[s]); }
  Vec<T, D> world(const Vec<T, D>& y) const { return frame.rotation() * y + frame.p; }
};

// Backward Euler with the contact rows as its constraints (contact/implicit_contact.hpp): the
// rows, the alternations of Newton solve and dual LCP, their CG solves for A = J R H⁻¹ Rᵀ Jᵀ,
// and the largest row violation (relative to Σ|j| max|u|) before the first and after the last.
struct ImplicitContactStats {
  int rows = 0, iterations = 0, cg_iterations = 0;
  double first_violation = 0, violation = 0;
  void merge(const ImplicitContactStats& o) {
    rows += o.rows;
    iterations = std::max(iterations, o.iterations);
    cg_iterations += o.cg_iterations;
    first_violation = std::max(first_violation, o.first_violation);
    violation = std::max(violation, o.violation);
  }
};
// The alternations stop once every row holds to this relative violation, or after this many.
inline constexpr double kImplicitContactTolerance = 1e-4;
inline constexpr int kImplicitContactIterations = 20;

template <class T, int D>
class EolSimulation final : public Simulation {
 public:
  // lagrangian = false: the pure-Eulerian baseline.
  EolSimulation(const SceneDesc& scene, bool lagrangian);
  EolSimulation(const EolSimulation&) = default;
  std::unique_ptr<Simulation> clone() const override {
    return std::make_unique<EolSimulation>(*this);
  }

  int dim() const override { return D; }
  Precision precision() const override { return precision_of<T>(); }
  const SceneDesc& scene() const override { return scene_; }
  std::string model_size() const override {
    std::size_t nodes = 0;
    for (const auto& o : objects_) nodes += o.grid.size();
    return std::to_string(nodes) + " grid nodes";
  }
  // Forces (unless step() computed them ahead), then finish_step, then the next step's forces.
  void step_fixed(double dt) override;
  // With solver.ledger, the row's stages are the step's energy ledger's (energy_ledger.hpp).
  DiagnosticsRow step_fixed_measured(double dt) override {
    step_fixed(dt);
    DiagnosticsRow r = measure();
    if (r.ledger) r.stages = last_ledger_.stages();
    return r;
  }
  DiagnosticsRow measure() const override;
  double total_mass() const override;
  double rest_energy_round_off() const override;
  bool steps_in_parallel() const override { return parallel_; }
  std::shared_ptr<Snapshot> snapshot() const override;
  bool checkpoints() const override { return true; }

  // The phases, public for tests.
  void update_mass(EolObject<T, D>& o);     // fill, owner, material, mass from X
  void spatial_state(EolObject<T, D>& o);   // r, x, u from the frame and v
  void compute_forces(EolObject<T, D>& o);  // f_e + f_b + f_qvv, world axes
  void finish_step(double dt);  // impulse, planes, split, frame, advection, extrapolation
  void place_surface(EolObject<T, D>& o);  // Algorithm 2, now
  // Algorithm 2 for every object unless already placed since the last step. step() calls it
  // when a step reaches its t_limit, a frame time (reached_frame_time); steps in between do not.
  void place_surfaces();
  bool surfaces_placed() const { return surfaces_placed_; }
  // Eqs 35-37 at every object's plastic samples, from the state now (eol_plasticity.hpp);
  // step_fixed runs it after the transport.
  void plastic_flow();

  bool lagrangian() const { return lagrangian_; }
  // Mutable access: the state may change, so the forces computed ahead are recomputed.
  std::vector<EolObject<T, D>>& objects() {
    forces_ready_ = false;
    surfaces_placed_ = false;
    return objects_;
  }
  const std::vector<EolObject<T, D>>& objects() const { return objects_; }
  const std::vector<ElasticMaterial<T>>& materials() const { return materials_; }
  double elastic_energy() const;
  // Area (2D) or volume (3D) the material occupies: Σ H Δx^d over the nodes.
  double occupied_volume() const;
  DtLimit last_limit() const { return last_limit_; }
  // solver.elasticity implicit: the last step's backward Euler solves, summed over the objects
  // (the residual and tolerance of the one furthest from its tolerance).
  const NewtonCgReport& last_implicit_solve() const { return implicit_report_; }
  const ImplicitContactStats& last_implicit_contact() const { return implicit_contact_; }
  bool implicit_elasticity() const {
    return scene_.solver.eol.elasticity == EolSolverDesc::Elasticity::backward_euler;
  }
  // The blow-up check's energy scale, again from the current state (tests that set a state).
  void reset_energy_reference() { energy_ref_ = energy_reference(); }
  // Time spent in each phase (seconds, summed over steps): forces, collision (the box test and
  // the contact rows of eq 28, between objects and against planes), assembly (the impulse, in one
  // pass with the split's sums), the QP of eq 29, split (its solve and remainder, with the Δt
  // choice's projections), advection (eq 15), extrapolation with the mass passes, and the
  // surface placements (Algorithm 2, at frames and for the contact rows).
  struct StageSeconds {
    double forces = 0, collision = 0, assembly = 0, qp = 0, split = 0, advection = 0,
           extrapolation = 0, surface = 0;
  };
  const StageSeconds& stage_seconds() const { return stages_; }
  // The energy ledger (energy_ledger.hpp): on, every step adds its stages' energy changes to
  // energy_ledger() (cleared when turned on) and leaves them in last_step_ledger().
  void record_energy_ledger(bool on) {
    ledger_on_ = on;
    ledger_ = last_ledger_ = EnergyLedger{};
  }
  const EnergyLedger& energy_ledger() const { return ledger_; }
  // solver.contact surface: the last step's rows (eq 28: the last object that had any, or the
  // objects' one QP) and its solve (eq 29), for tests.
  const ContactRows<T, D>& last_contact_rows() const { return contact_rows_; }
  const ContactSolveStats& last_contact_solve() const { return contact_stats_; }
  // The pairs of objects whose placed surfaces overlapped at the start of the last step, with
  // |Ω| and their rows in last_contact_rows() (empty when no pair overlapped).
  const std::vector<OverlapPair<T>>& last_object_pairs() const { return object_pairs_; }
  const EnergyLedger& last_step_ledger() const { return last_ledger_; }

 private:
  // Setup (eol_setup.hpp).
  void add_materials();
  void add_object_grids();
  void add_object_grid(const std::vector<int>& shapes, const Vec3d& lo, const Vec3d& hi, double dx,
                       int padding);
  void place_object_grid(EolObject<T, D>& o, const Vec3d& lo, const Vec3d& hi, double dx,
                         int padding) const;
  std::pair<Vec<T, D>, Spin<T, D>> initial_velocity(int shape, const Vec<T, D>& x) const;
  void set_initial_velocity(EolObject<T, D>& o) const;
  void add_plastic_samples(EolObject<T, D>& o) const;  // eol_plasticity.hpp
  double energy_reference() const;
  // Mass and spatial state (eol_mass.hpp), forces (eol_forces.hpp).
  void update_mass(EolObject<T, D>& o, bool after_extrapolation);
  void update_spatial(EolObject<T, D>& o) const;
  void keep_rest_mass(EolObject<T, D>& o);
  void drop_sliver_masses(EolObject<T, D>& o) const;
  void forces(EolObject<T, D>& o);
  void forces_ahead();  // every object's, for the state now (forces_ready_)
  // solver.elasticity implicit: each object's forces replaced by backward Euler's for the step.
  void implicit_forces(double dt);
  // Its contact: the step's rows built first, then held by the solves (implicit_contact.hpp).
  void implicit_contact();
  void constrained_solve(const std::vector<ObjectVelocities<T, D>>& views,
                         const std::vector<EolObject<T, D>*>& group);
  // step()'s hooks (Simulation::step; eol_time_step.hpp, eol_step.hpp).
  double choose_dt() override;
  void dt_set_by_frame() override { last_limit_ = DtLimit::frame; }
  void reached_frame_time() override { place_surfaces(); }
  std::optional<Failure> check_step(const DiagnosticsRow& r) const override;
  void save_family_state(StateWriter& w) const override;  // sim/eol/eol_checkpoint.hpp
  void load_family_state(StateReader& r) override;
  // finish_step's stages for one object (eol_step.hpp, eol_contact.hpp).
  void finish_object(EolObject<T, D>& o, double dt, EnergyLedger& ledger);
  SplitSums<D, 1> impulse(EolObject<T, D>& o, T dt);
  // The pass after the contact solve: eq 16 node by node unless `impulse_done`, and the split's
  // sums (eq 23) in the same pass.
  SplitSums<D, 1> impulse_pass(EolObject<T, D>& o, T dt, bool impulse_done);
  void impulse_nodes(EolObject<T, D>& o, T dt);  // eq 16 for every node with mass, no rows
  // Object–object contact (surface rows; eol_contact.hpp): per object, whether its material box
  // meets another's (all false: none can touch, the per-object step runs as it is).
  std::vector<char> meeting_objects() const;
  // The step's stages for the meeting objects together: impulse → one QP → split → transport.
  void finish_together(const std::vector<char>& meeting, double dt, EnergyLedger& ledger);
  void object_contact(const std::vector<char>& meeting);
  // The rows into contact_rows_: the meeting objects' (pairs and planes, nodes side by side) and
  // one object's against the planes and bodies, each with its surfaces placed now.
  std::vector<ObjectVelocities<T, D>> object_rows(const std::vector<char>& meeting);
  void plane_rows(EolObject<T, D>& o);
  void split(EolObject<T, D>& o, const SplitSums<D, 1>& sums, T dt);
  void advect(EolObject<T, D>& o, T dt);
  void impulse_surface_contact(EolObject<T, D>& o, T dt);
  bool may_touch_planes(const EolObject<T, D>& o) const;  // or a body
  std::vector<Vec<T, D>> placed_surface(const EolObject<T, D>& o) const;
  bool parallel() const { return parallel_; }
  // The energy ledger's terms (eol_ledger.hpp).
  struct LedgerEnergies {
    double kinetic = 0, gravity = 0;
    ConservedSums moments;  // mass and momenta (energy unused)
  };
  LedgerEnergies ledger_energies(const EolObject<T, D>& o) const;
  void ledger_work(const EolObject<T, D>& o, double dt, EnergyLedger& step) const;
  LedgerEnergies ledger_before(const EolObject<T, D>& o, EnergyLedger& step) const;
  LedgerEnergies ledger_impulse(const EolObject<T, D>& o, double dt, const LedgerEnergies& before,
                                EnergyLedger& step) const;
  void ledger_transport(const EolObject<T, D>& o, const LedgerEnergies& before,
                        const LedgerEnergies& pushed, EnergyLedger& step) const;
  // Adds the seconds of its scope to one of stages_.
  struct StageTimer {
    explicit StageTimer(double& into) : total(into) {}  // std::optional::emplace needs it (clang)
    double& total;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    ~StageTimer() {
      total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
  };

  SceneDesc scene_;
  bool lagrangian_ = true, parallel_ = false;
  // step() computed the forces (and their Ψ) for the current state at its end: the next step
  // and measure() use them. Cleared by every public way to change the state.
  bool forces_ready_ = false;
  // Every surface_y is Algorithm 2's placement for the current state (set by place_surfaces,
  // cleared by a step and by mutable access). snapshot() places a copy when it is not.
  bool surfaces_placed_ = true;
  std::vector<EolObject<T, D>> objects_;
  std::vector<RestShape> rest_;  // per scene object: φ₀ (shape/rest_shape.hpp)
  std::vector<ElasticMaterial<T>> materials_;
  std::vector<T> density_;  // ρ₀ per material
  std::vector<PlaneConstraint<T, D>> planes_;
  std::vector<ColliderDesc> bodies_;      // boxes, rods, turning planes (body_contact.hpp)
  std::vector<ColliderPose> body_poses_;  // where they are at the step's start
  ContactRows<T, D> contact_rows_;
  ContactSolver<T, D> contact_solver_;
  ContactSolveStats contact_stats_;
  GlobalContactSolver<T, D> global_solver_;
  ContactRows<T, D> plane_scratch_;
  std::vector<OverlapPair<T>> object_pairs_;
  double energy_ref_ = 0, max_wave_speed_ = 0;
  double max_kinematic_viscosity_ = 0;  // max η/ρ over the materials: the viscous step limit
  DtLimit last_limit_ = DtLimit::fixed;
  NewtonCgReport implicit_report_;
  ImplicitContactStats implicit_contact_;
  StageSeconds stages_;
  bool ledger_on_ = false;
  EnergyLedger ledger_, last_ledger_;
  // choose_dt's one pass over the nodes (sum_node_blocks): max|u|, and eq 32's two fields'
  // split sums (eol) or advection rates (eulerian).
  struct DtSums {
    SplitSums<D, 2> split;
    double umax = 0, gamma0 = 0, gamma1 = 0;
    void merge(const DtSums& o) {
      split.merge(o.split);
      umax = std::max(umax, o.umax);
      gamma0 = std::max(gamma0, o.gamma0);
      gamma1 = std::max(gamma1, o.gamma1);
    }
  };
  std::vector<DtSums> dt_partial_;  // per node block, kept between steps
  DtSums dt_sums(const EolObject<T, D>& o);
  // Eq 33's γ₀, γ₁ and max|v₀*|: the rates of v* = v₀* + Δt v₁* through the object's grid.
  std::array<double, 3> split_rates(const EolObject<T, D>& o, const DtSums& sums) const;
  double object_dt(const EolObject<T, D>& o, double dt, DtLimit& limit);
  double approach_limit(const EolObject<T, D>& o) const;
  double objects_approach_limit() const;        // between objects, under implicit elasticity
  std::vector<SplitSums<D, 1>> split_partial_;  // the same for finish_step's split
};

// Compiled once, in sim/eol/eol_{2d,3d}.cpp (see sim/mpm/mpm.hpp).
extern template class EolSimulation<double, 2>;
extern template class EolSimulation<double, 3>;

}  // namespace apiclab::eol
