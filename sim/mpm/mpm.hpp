// MPM with interchangeable transfers (Jiang et al. 2017). One step, as the paper orders it
// (step_fixed, sim/mpm/mpm_step.hpp):
//   sort → clear grid → P2G (eqs 24-26) → grid update (eqs 27-34) → boundary
//   → G2P (eqs 37-40) with the particle update.
// The definitions live one concept per file, included by phases.hpp.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sim/geometry/triangle_mesh.hpp"
#include "sim/materials.hpp"
#include "sim/mpm/block_partition.hpp"
#include "sim/mpm/grid.hpp"
#include "sim/mpm/implicit/implicit_state.hpp"
#include "sim/mpm/particle_sums.hpp"
#include "sim/mpm/particles.hpp"
#include "sim/mpm/stage_ledger.hpp"
#include "sim/mpm/stencil.hpp"
#include "sim/plasticity.hpp"
#include "sim/simulation.hpp"

namespace apiclab {

template <class T>
struct MaterialParams {
  MaterialModel model;
  Lame<T> lame;
  PlasticParams<T> plastic;  // the plastic model's yield stress and flow rate (eq 37)
};

template <class T, int D>
class MpmSimulation final : public Simulation, public TransferControls {
 public:
  using Scalar = T;
  static constexpr int Dim = D;
  explicit MpmSimulation(const SceneDesc& scene);
  MpmSimulation(const MpmSimulation&) = default;
  std::unique_ptr<Simulation> clone() const override {
    auto copy = std::make_unique<MpmSimulation>(*this);
    copy->on_solver_iteration_ = nullptr;  // the observer belongs to this run's caller
    return copy;
  }

  // Simulation.
  int dim() const override { return D; }
  Precision precision() const override { return precision_of<T>(); }
  const SceneDesc& scene() const override { return scene_; }
  void step_fixed(double dt) override;
  DiagnosticsRow step_fixed_measured(double dt) override;
  DiagnosticsRow measure() const override;
  double total_mass() const override {
    double m = 0;
    for (T x : p_.mass) m += double(x);
    return m;
  }
  double rest_energy_round_off() const override;
  bool steps_in_parallel() const override { return parallel_worthwhile(); }
  std::shared_ptr<Snapshot> snapshot() const override;
  void on_solver_iteration(SolverIterationObserver observer) override {
    on_solver_iteration_ = std::move(observer);
  }
  std::string model_size() const override { return std::to_string(p_.size()) + " particles"; }
  TransferControls* transfers() override { return this; }
  const TransferControls* transfers() const override { return this; }

  // TransferControls.
  std::size_t particle_count() const override { return p_.size(); }
  void set_scheme(Scheme scheme, double flip_alpha) override;
  void fill_velocity_noise(Snapshot& s) const override;
  void write_particles_csv(std::ostream& out) const override;
  ParticleTable particle_table() const override;
  std::size_t grid_bytes() const override { return grid_.allocated_bytes(); }
  std::unique_ptr<ReferenceRun> reference_run() const override;
  bool checkpoints() const override { return true; }

  // The plastic model (mpm_plasticity.hpp; F_p⁻¹ per particle in Particles::fp_inv): the last
  // step's count of particles that flowed and largest |det ΔF_p⁻¹ − 1| among them.
  std::size_t plastic_flowed() const { return plastic_flowed_; }
  double plastic_det_error() const { return plastic_det_error_; }

 protected:
  void save_family_state(StateWriter& w) const override;  // sim/mpm/mpm_checkpoint.hpp
  void load_family_state(StateReader& r) override;

 private:
  // Tests, the round-trip probe and the implicit tests drive the phases through these
  // (sim/mpm/probe.hpp, sim/mpm/implicit/implicit_probe.hpp).
  template <class Sim>
  friend class MpmProbe;
  template <class Sim>
  friend class ImplicitProbe;

  // Writable access (tests, setup) may change F: the cached stress and energy are dropped.
  Particles<T, D>& particles() {
    stress_of_current_F_ = false;
    ledger_.forget_start();
    return p_;
  }
  const Particles<T, D>& particles() const { return p_; }
  Grid<T, D>& grid() { return grid_; }
  const Grid<T, D>& grid() const { return grid_; }
  SolverDesc& solver() { return scene_.solver; }
  // Bytes held (capacity) by the particles with their sort copy, the grid and the per-scheme
  // arrays (PolyPIC's modes, XPIC's node arrays): what a scheme switch must give back.
  std::size_t state_bytes() const;
  // XPIC(m)'s two node arrays (capacity 0 unless the scheme is xpic with m > 1), for tests.
  std::size_t xpic_capacity() const { return xpic_term_.capacity() + xpic_shift_.capacity(); }
  T inertia_scale() const;  // k Δx² with D_p = k Δx² I (quadratic, cubic)
  // The diagnostics row's particle sums by measure()'s own pass (the readable form of those
  // G2P takes for step() and step_fixed_measured, sim/mpm/particle_sums.hpp), and the row of sums.
  ParticleSums particle_sums() const;
  DiagnosticsRow row_of(const ParticleSums& sums) const;

  // The phases, in step_fixed's order.
  void sort_particles();
  void clear_grid();  // zeroes the P2G accumulator
  void particles_to_grid(
      bool with_forces);            // eqs 24-25: m_i and (m v)_i (+ eq 34 at F^n when with_forces)
  void grid_velocity_update(T dt);  // eq 29 explicit (λ = 0)
  // With ledger, each condition's change into ledger_ (sim/mpm/stage_ledger.hpp).
  void apply_boundary_conditions(bool ledger = false);
  // Eqs 37-40, or the scheme's variant; with sums, also the row's sums over the new particle
  // state (sim/mpm/particle_sums.hpp); with ledger, the ledger's particle sums into ledger_.
  void grid_to_particles(T dt, ParticleSums* sums = nullptr, bool ledger = false);
  // Σ_i m_i v_i, Σ_i x_i × m_i v_i over the grid (after the update: updated = false gives v^n,
  // true gives ṽ).
  void grid_momentum(bool updated, Eigen::Vector3d& p, Eigen::Vector3d& L) const;
  // The parallel P2G's invariant (BlockPartition::conflict): "" or what breaks it.
  std::string partition_conflict() const {
    return blocks_.conflict(p_, grid_, scene_.solver.kernel);
  }
  // Sum of internal forces Σ_i f_i (zero for forces derived from an energy, Sec 5.2).
  Eigen::Vector3d total_force() const;
  double elastic_energy() const;

  // Implicit solve (sim/mpm/implicit/implicit.hpp); the tests drive it through ImplicitProbe.
  template <class K>
  void implicit_velocity_update(T dt);
  template <class K>
  void implicit_begin(T dt);
  template <class K>
  double implicit_energy(const std::vector<Vec<T, D>>& dv, bool gradient);
  void implicit_update_hessian(bool project_definite);
  // 2D folds each particle's ∂P/∂F with b Δt² V_p and Fⁿ (implicit_update_hessian says why).
  static constexpr bool folded_stiffness = D == 2;
  template <class K>
  void implicit_hessian_apply(const std::vector<Vec<T, D>>& in, std::vector<Vec<T, D>>& out);
  void implicit_project(std::vector<Vec<T, D>>& z) const;
  template <class K>
  void implicit_block_jacobi();  // after implicit_update_hessian
  void implicit_precondition(const std::vector<Vec<T, D>>& r, std::vector<Vec<T, D>>& z) const;

  template <class K, bool affine, bool with_forces, bool mls_forces = false>
  void p2g_impl();
  void unpack_accumulator();
  void compute_stress();
  void pack_velocities();
  bool has_mass(std::size_t node) const;
  template <class K, Scheme S>
  void g2p_impl(T dt, ParticleSums* sums, bool ledger);
  // The conservation ledger (sim/mpm/mpm_ledger.hpp): the grid's sums after the update, and the
  // stages' changes into the step's row.
  void ledger_grid();
  void ledger_constraints();  // the implicit solve's walls and colliders
  // Passes of their own beside G2P's loop, which stays as without the ledger (a call in it costs
  // the update's registers even when not taken): before G2P, xⁿ kept and the state at the step's
  // start summed unless the last row is it; after G2P, the particles at the kept xⁿ.
  void ledger_start(LedgerTerms terms);
  void ledger_updated(LedgerTerms terms);
  void ledger_chunk_sums(const Vec<T, D>* xs, LedgerTerms terms,
                         std::vector<ParticleSums>& sums) const;
  ParticleSums ledger_sums(std::ptrdiff_t first, std::ptrdiff_t end, const Vec<T, D>* xs,
                           LedgerTerms terms) const;
  // The row with the step's stages; the row is then the next step's start.
  DiagnosticsRow with_ledger(DiagnosticsRow r);
  // step_fixed; G2P fills sums when given. False when the state was frozen (non-finite) and
  // no step was taken, so the sums were not taken.
  bool step_fixed_summing(double dt, ParticleSums* sums);
  template <class K>
  void xpic_grid_passes();  // sim/mpm/schemes/xpic_passes.hpp
  template <class K>
  void velocity_noise(std::vector<float>& out) const;
  template <class Fn>
  void for_each_box_node(Fn&& fn) {
    blocks_.for_each_box_node(fn, parallel_worthwhile());
  }
  template <class Fn>
  void for_each_particle_coloured(Fn&& fn) {
    blocks_.for_each_particle_coloured(fn, parallel_worthwhile());
  }
  template <class K>
  std::vector<Stencil<T, D, K>>& stencils() {
    if constexpr (K::type == KernelType::linear)
      return stencils_linear_;
    else if constexpr (K::type == KernelType::quadratic)
      return stencils_quadratic_;
    else
      return stencils_cubic_;
  }
  // step()'s hooks (Simulation): the time-step rule (sim/time_step_rules.hpp) and the checks.
  double choose_dt() override;
  std::optional<Failure> check_step(const DiagnosticsRow& r) const override;
  // The grid update is the Newton solve of sim/mpm/implicit/implicit.hpp (backward Euler or λ > 0).
  bool uses_implicit_solve() const {
    return scene_.solver.integrator == Integrator::backward ||
           scene_.solver.integrator_lambda() != 0;
  }
  // P2G keeps every particle's stencil for the steps that read it again.
  bool keeps_stencils() const { return uses_implicit_solve() || !mesh_.empty(); }
  void add_triangulated_object(int object_index);
  void plastic_flow();            // eqs 35-37 per plastic particle, F_e ← F_e ΔF_p⁻¹
  void allocate_polypic_modes();  // Particles::modes for PolyPIC only
                                  // (sim/mpm/schemes/polypic_modes.hpp)
  template <class K>
  void p2g_polypic_modes();  // PolyPIC's higher modes into the P2G momentum
  void rebuild_index_of_id();
  template <class K>
  void add_mesh_forces();
  // Below this many particles an OpenMP region costs more than it saves.
  bool parallel_worthwhile() const { return p_.size() >= scene_.solver.parallel_min_particles; }
  double energy_reference() const;

  SceneDesc scene_;
  Particles<T, D> p_, scratch_;
  std::size_t plastic_flowed_ = 0;
  double plastic_det_error_ = 0;
  Grid<T, D> grid_;
  std::vector<MaterialParams<T>> materials_;
  BoundaryNodes<T, D> boundary_;  // walls and colliders, resolved on the stored box
  double kinetic_grid_ = 0, max_grid_speed_ = 0, energy_ref_ = 0, max_wave_speed_ = 0;
  // The scene's velocity scale, √(2 (K₀ + Ψ₀) / M): the implicit solve's tolerance is relative
  // to it however far the motion decays (sim/mpm/implicit/implicit.hpp).
  double velocity_scale_ = 0;
  bool non_finite_ = false;
  std::vector<float> radius_;  // per particle (by id), for drawing
  BlockPartition<T, D> blocks_;
  // Triangulated objects (Sec 6.7) and the particle index of every id (the sort permutes).
  TriangleMesh<T> mesh_;
  std::vector<std::uint32_t> index_of_id_;
  std::vector<Vec<T, 2>> mesh_x_, mesh_g_, mesh_dx_, mesh_kx_;
  // −V_p P(F_p) F_pᵀ per particle for the explicit forces (compute_stress), and the particles'
  // elastic energy Σ V_p Ψ(F_p) of the same pass. Valid while stress_of_current_F_: any change
  // of F (G2P, setup) or of the particle order (the sort) clears it.
  std::vector<Mat<T, D>> stress_;
  double particle_elastic_energy_ = 0;
  bool stress_of_current_F_ = false;
  // Stencils P2G keeps for the implicit solve and mesh forces (keeps_stencils).
  std::vector<Stencil<T, D, LinearKernel>> stencils_linear_;
  std::vector<Stencil<T, D, QuadraticKernel>> stencils_quadratic_;
  std::vector<Stencil<T, D, CubicKernel>> stencils_cubic_;
  // XPIC(m) only, sized on its first step (sim/mpm/schemes/xpic_passes.hpp): the series term (I − S
  // S⁺)^k vⁿ and the sum e = Σ_{k=1}^{m−1} of those terms, per grid node; freed by set_scheme.
  std::vector<Vec<T, D>> xpic_term_, xpic_shift_;
  ImplicitSolveState<T, D> imp_;
  NewtonCgReport last_solve_;             // the last grid update's (zero iterations when explicit)
  std::vector<ParticleSums> chunk_sums_;  // G2P's row sums per chunk of particles (sim/mpm/g2p.hpp)
  StepLedger<T, D> ledger_;               // the step's conservation ledger (solver.ledger)
  SolverIterationObserver on_solver_iteration_;
};

// Compiled once, in sim/mpm/mpm_{2d,3d}_{float,double}.cpp: a file that uses the solver does not
// instantiate its inline members and virtual functions again.
extern template class MpmSimulation<float, 2>;
extern template class MpmSimulation<double, 2>;
extern template class MpmSimulation<float, 3>;
extern template class MpmSimulation<double, 3>;

}  // namespace apiclab
