// MPM with interchangeable transfers (Jiang et al. 2017). One step, as the paper orders it:
//   clear grid → P2G (eqs 24-26) → grid update (eqs 27-34) → boundary → G2P (eqs 37-40)
//   → particle update.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "grid.hpp"
#include "materials.hpp"
#include "particles.hpp"
#include "simulation.hpp"
#include "stencil.hpp"
#include "triangle_mesh.hpp"

namespace apiclab {

template <class T>
struct MaterialParams {
  MaterialModel model;
  Lame<T> lame;
};

// A grid node with a boundary condition: a domain wall or a collider plane.
template <class T, int D>
struct ConstrainedNode {
  std::size_t node;
  Vec<T, D> normal;  // into the free side
  BoundaryCondition condition;
};

template <class T, int D>
class MpmSimulation final : public Simulation {
 public:
  explicit MpmSimulation(const SceneDesc& scene);
  std::unique_ptr<Simulation> clone() const override { return std::make_unique<MpmSimulation>(*this); }

  int dim() const override { return D; }
  Precision precision() const override { return sizeof(T) == 4 ? Precision::single : Precision::dbl; }
  const SceneDesc& scene() const override { return scene_; }
  std::size_t particle_count() const override { return p_.size(); }
  double time() const override { return time_; }
  long steps() const override { return steps_; }

  std::optional<Failure> step(double t_limit, DiagnosticsRow* row) override;
  void step_fixed(double dt) override;
  DiagnosticsRow measure() const override;
  double total_mass() const override {
    double m = 0;
    for (T x : p_.mass) m += double(x);
    return m;
  }
  const std::optional<Failure>& failure() const override { return failure_; }
  void set_scheme(Scheme scheme, double flip_alpha) override;
  std::shared_ptr<Snapshot> snapshot(bool with_noise) const override;
  void write_particles_csv(std::ostream& out) const override;

  // Direct access for tests and the round-trip probe.
  Particles<T, D>& particles() { return p_; }
  const Particles<T, D>& particles() const { return p_; }
  Grid<T, D>& grid() { return grid_; }
  const Grid<T, D>& grid() const { return grid_; }
  SolverDesc& solver() { return scene_.solver; }
  T inertia_scale() const;  // k Δx² with D_p = k Δx² I (quadratic, cubic)

  // The phases, public so tests can check each one's conservation.
  void sort_particles();
  void clear_grid();  // zeroes the P2G accumulator
  void particles_to_grid(bool with_forces);  // eqs 24, 26 (+ eq 34 at F^n when with_forces)
  void grid_velocity_update(T dt);           // eq 29, explicit (λ = 0)
  void apply_boundary_conditions();
  void grid_to_particles(T dt);               // eqs 37-40, or the scheme's variant
  // Σ_i m_i v_i, Σ_i x_i × m_i v_i over the grid (after P2G: v = velocity; after update: ṽ).
  void grid_momentum(bool updated, Eigen::Vector3d& p, Eigen::Vector3d& L) const;
  // The parallel P2G's invariant, checked for tests against the current positions (which may
  // have drifted since the sort): blocks of one colour touch disjoint nodes, and every touched
  // node lies in the active box. Returns "" or what breaks it.
  std::string partition_conflict() const;
  // Sum of internal forces Σ_i f_i (zero for forces derived from an energy, Sec 5.2).
  Eigen::Vector3d total_force() const;
  double elastic_energy() const;

  // Implicit solve (sim/implicit.hpp), public so tests can check E, ∇E and H against finite
  // differences: implicit_begin after particles_to_grid(false), then energy/Hessian at Δv.
  template <class K> void implicit_velocity_update(T dt);
  template <class K> void implicit_begin(T dt);
  template <class K> double implicit_energy(const std::vector<Vec<T, D>>& dv, bool gradient);
  void implicit_update_hessian(bool project_definite);
  template <class K> void implicit_hessian_apply(const std::vector<Vec<T, D>>& in, std::vector<Vec<T, D>>& out);
  void implicit_project(std::vector<Vec<T, D>>& z) const;
  const std::vector<std::uint32_t>& active_nodes() const { return active_; }
  const std::vector<Vec<T, D>>& implicit_gradient() const { return grad_; }
  const std::vector<Vec<T, D>>& implicit_dv() const { return dv_; }

 private:
  template <class K, bool affine, bool with_forces> void p2g_impl();
  void unpack_accumulator();
  void compute_stress();
  void pack_velocities();
  void set_active_box(const std::array<int, D>& first_block, const std::array<int, D>& last_block);
  template <class Fn> void for_each_box_node(Fn&& fn);
  template <class K, Scheme S> void g2p_impl(T dt);
  template <class K> void velocity_noise(std::vector<float>& out) const;
  template <class Fn> void for_each_particle_coloured(Fn&& fn);
  template <class K> std::vector<Stencil<T, D, K>>& stencils() {
    if constexpr (K::type == KernelType::linear) return stencils_linear_;
    else if constexpr (K::type == KernelType::quadratic) return stencils_quadratic_;
    else return stencils_cubic_;
  }
  double choose_dt(double t_limit) const;
  // The grid update is the Newton solve of sim/implicit.hpp (backward Euler or λ > 0).
  bool implicit_update() const {
    return scene_.solver.integrator == Integrator::backward || scene_.solver.integrator_lambda() != 0;
  }
  // Width in cells of the sorting blocks (see sort_particles).
  int block_cells() const { return scene_.solver.kernel == KernelType::cubic ? 5 : 4; }
  bool in_active_box(std::size_t node) const {
    for (int a = 0; a < D; ++a) {
      const int i = grid_.node_coordinate(node, a);
      if (i < box_lo_[a] || i >= box_hi_[a]) return false;
    }
    return true;
  }
  // P2G keeps every particle's stencil for the steps that read it again.
  bool keeps_stencils() const { return implicit_update() || !mesh_.empty(); }
  void add_triangulated_object(int object_index);
  void rebuild_index_of_id();
  template <class K> void add_mesh_forces();
  // Below this many particles an OpenMP region costs more than it saves.
  bool parallel_worthwhile() const { return p_.size() >= parallel_min_particles(); }
  void build_constraints();
  double energy_reference() const;

  SceneDesc scene_;
  Particles<T, D> p_, scratch_;
  Grid<T, D> grid_;
  std::vector<MaterialParams<T>> materials_;
  std::vector<ConstrainedNode<T, D>> constraints_;
  double time_ = 0, kinetic_grid_ = 0, max_grid_speed_ = 0, energy_ref_ = 0, max_wave_speed_ = 0;
  long steps_ = 0;
  std::optional<Failure> failure_;
  std::vector<float> radius_;  // per particle (by id), for drawing
  // Block sort for coloured parallel P2G: particles of block b are [block_start_[b], block_start_[b+1]).
  std::vector<std::uint32_t> keys_, order_, block_start_;
  std::vector<std::vector<std::uint32_t>> color_blocks_;
  std::array<int, D> blocks_per_axis_{};
  // Nodes the particles can reach until the next sort: [box_lo_, box_hi_) per axis, as runs
  // of consecutive nodes (start, length) along axis 0, and the wall/collider nodes inside it.
  std::array<int, D> box_lo_{}, box_hi_{};
  std::vector<std::pair<std::size_t, std::size_t>> box_rows_;
  std::vector<ConstrainedNode<T, D>> box_constraints_;
  bool non_finite_ = false;
  // Triangulated objects (Sec 6.7) and the particle index of every id (the sort permutes).
  TriangleMesh<T> mesh_;
  std::vector<std::uint32_t> index_of_id_;
  std::vector<Vec<T, 2>> mesh_x_, mesh_g_, mesh_dx_, mesh_kx_;
  // Implicit solve state, allocated once and reused every step.
  std::vector<Stencil<T, D, LinearKernel>> stencils_linear_;
  std::vector<Stencil<T, D, QuadraticKernel>> stencils_quadratic_;
  std::vector<Stencil<T, D, CubicKernel>> stencils_cubic_;
  std::vector<std::uint32_t> active_;
  std::vector<ConstrainedNode<T, D>> active_constraints_;
  std::vector<Vec<T, D>> dv_, grad_, dir_, cg_r_, cg_p_, cg_s_, work_;
  std::vector<Mat<T, D>> Fy_, stress_;
  std::vector<Eigen::Matrix<T, D * D, D * D>> hess_;
  int last_newton_iters_ = 0, last_cg_iters_ = 0;
  double last_residual_ = 0;
  T imp_dt_ = 0, imp_a_ = 0, imp_b_ = 0;
  Vec<T, D> imp_gravity_ = Vec<T, D>::Zero();
  double imp_msum_ = 0, imp_vref_ = 0;
  bool last_converged_ = true;

 public:
  // Newton residuals (mass-weighted RMS of M⁻¹g) of the last implicit step, in order.
  std::vector<double> residuals_;

 private:
  double drift_since_sort_ = 1e30;  // cells moved since the last block sort
};

}  // namespace apiclab
