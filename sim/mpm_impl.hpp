// Definitions of MpmSimulation<T, D>; included by mpm_2d.cpp and mpm_3d.cpp only.
#pragma once
#include <omp.h>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <ostream>
#include <sstream>
#include <type_traits>

#include "mpm.hpp"
#include "implicit.hpp"
#include "sampling.hpp"

namespace apiclab {

template <class T, int D>
MpmSimulation<T, D>::MpmSimulation(const SceneDesc& scene) : scene_(scene) {
  if (scene.dim != D) throw SceneError(scene.source + ": key 'dim': internal dimension mismatch");
  grid_.init(scene);
  for (auto& m : scene.materials) {
    materials_.push_back({m.model, {T(m.mu()), T(m.lambda())}});
    max_wave_speed_ = std::max(max_wave_speed_, m.wave_speed());
  }
  for (int o = 0; o < int(scene.objects.size()); ++o) {
    if (scene.objects[size_t(o)].sampling.type == SamplingType::triangulated) {
      if constexpr (D == 2) add_triangulated_object(o);
      continue;
    }
    SampledParticles s = sample_object(scene, o);
    const MaterialDesc& mat = scene.materials[size_t(scene.objects[size_t(o)].material)];
    std::size_t start = p_.size();
    p_.resize(start + s.positions.size());
    for (std::size_t k = 0; k < s.positions.size(); ++k) {
      std::size_t q = start + k;
      for (int a = 0; a < D; ++a) { p_.x[q][a] = T(s.positions[k][a]); p_.v[q][a] = T(s.velocities[k][a]); }
      p_.C[q].setZero();
      p_.F[q].setIdentity();
      p_.volume0[q] = T(s.volumes[k]);
      p_.mass[q] = T(s.volumes[k] * mat.rho);
      p_.material[q] = scene.objects[size_t(o)].material;
      p_.object[q] = o;
      p_.id[q] = std::int32_t(q);
      radius_.push_back(float(0.5 * s.spacing));
    }
  }
  // A rigidly rotating object has the affine velocity C = ω* (APIC/RPIC start with it, Sec 6.1).
  if (scene.solver.scheme == Scheme::apic || scene.solver.scheme == Scheme::rpic) {
    for (std::size_t q = 0; q < p_.size(); ++q) {
      const Vec3d& w = scene.objects[size_t(p_.object[q])].angular_velocity;
      if constexpr (D == 2) {
        p_.C[q] << T(0), T(-w[2]), T(w[2]), T(0);
      } else {
        p_.C[q] << T(0), T(-w[2]), T(w[1]), T(w[2]), T(0), T(-w[0]), T(-w[1]), T(w[0]), T(0);
      }
    }
  }
  rebuild_index_of_id();
  build_constraints();
  energy_ref_ = energy_reference();
}

// Particle index of every id (tests may build particles by hand, so ids are not trusted to be
// a permutation: the table is sized by the largest id).
template <class T, int D>
void MpmSimulation<T, D>::rebuild_index_of_id() {
  std::int32_t max_id = -1;
  for (std::int32_t id : p_.id) max_id = std::max(max_id, id);
  index_of_id_.assign(std::size_t(max_id + 1), 0);
  for (std::size_t q = 0; q < p_.size(); ++q)
    if (p_.id[q] >= 0) index_of_id_[std::size_t(p_.id[q])] = std::uint32_t(q);
}

// A 2D box as a regular triangulation (Sec 6.7): a particle per vertex, mass ρ × ⅓ of the
// adjacent triangles' area; elasticity lives on the triangles, so volume0 = 0 on the particles.
template <class T, int D>
void MpmSimulation<T, D>::add_triangulated_object(int o) {
  if constexpr (D == 2) {
  const ObjectDesc& obj = scene_.objects[size_t(o)];
  const MaterialDesc& mat = scene_.materials[size_t(obj.material)];
  const double h = obj.sampling.spacing;
  const int nx = std::max(1, int(std::lround((obj.shape.max[0] - obj.shape.min[0]) / h)));
  const int ny = std::max(1, int(std::lround((obj.shape.max[1] - obj.shape.min[1]) / h)));
  const double hx = (obj.shape.max[0] - obj.shape.min[0]) / nx, hy = (obj.shape.max[1] - obj.shape.min[1]) / ny;
  const std::size_t start = p_.size();
  p_.resize(start + std::size_t(nx + 1) * std::size_t(ny + 1));
  auto vertex = [&](int i, int j) { return start + std::size_t(j) * std::size_t(nx + 1) + std::size_t(i); };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      std::size_t q = vertex(i, j);
      p_.x[q] = Vec<T, D>(T(obj.shape.min[0] + i * hx), T(obj.shape.min[1] + j * hy));
      Eigen::Vector3d r(double(p_.x[q][0]) - obj.shape.center[0], double(p_.x[q][1]) - obj.shape.center[1], 0);
      Eigen::Vector3d v = Eigen::Vector3d(obj.velocity[0], obj.velocity[1], 0) +
                          Eigen::Vector3d(0, 0, obj.angular_velocity[2]).cross(r);
      p_.v[q] = Vec<T, D>(T(v[0]), T(v[1]));
      p_.C[q].setZero();
      p_.F[q].setIdentity();
      p_.volume0[q] = T(0);
      p_.mass[q] = T(0);
      p_.material[q] = obj.material;
      p_.object[q] = o;
      p_.id[q] = std::int32_t(q);
      radius_.push_back(float(0.5 * std::min(hx, hy)));
    }
  const MaterialParams<T>& params = materials_[size_t(obj.material)];
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      std::size_t c[4] = {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)};
      for (auto tri : {std::array<std::size_t, 3>{c[0], c[1], c[2]}, std::array<std::size_t, 3>{c[0], c[2], c[3]}}) {
        mesh_.add_triangle({std::int32_t(tri[0]), std::int32_t(tri[1]), std::int32_t(tri[2])}, p_.x[tri[0]],
                           p_.x[tri[1]], p_.x[tri[2]], params.model, params.lame);
        for (std::size_t q : tri) p_.mass[q] += T(mat.rho * 0.5 * hx * hy / 3.0);
      }
    }
  for (const std::string& row : obj.anchors)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        bool on = (row == "bottom" && j == 0) || (row == "top" && j == ny) || (row == "left" && i == 0) ||
                  (row == "right" && i == nx);
        if (on) mesh_.add_anchor(std::int32_t(vertex(i, j)), p_.x[vertex(i, j)], T(obj.anchor_stiffness));
      }
  }
}

// Forces of the triangle mesh and anchors at x^n, scattered to the grid: f_i −= Σ_p w_ip ∂Φ/∂x_p.
template <class T, int D>
template <class K>
void MpmSimulation<T, D>::add_mesh_forces() {
  if constexpr (D == 2) {
    mesh_g_.assign(p_.size(), Vec<T, 2>::Zero());
    mesh_.energy(p_.x, index_of_id_, &mesh_g_);
    const auto& st = stencils<K>();
    for (std::size_t q = 0; q < p_.size(); ++q) {
      if (mesh_g_[q].isZero()) continue;
      st[q].for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) { grid_.force[i] -= w * mesh_g_[q]; });
    }
  }
}

template <class T, int D>
T MpmSimulation<T, D>::inertia_scale() const {
  return T(inertia_factor(scene_.solver.kernel)) * grid_.dx * grid_.dx;
}

// Walls: nodes on or beyond a non-periodic domain face; colliders: nodes behind the plane.
template <class T, int D>
void MpmSimulation<T, D>::build_constraints() {
  constraints_.clear();
  const auto& dom = scene_.domain;
  for (std::size_t i = 0; i < grid_.size(); ++i) {
    Vec<T, D> x = grid_.node_position(i);
    T eps = T(1e-6) * grid_.dx;
    for (int a = 0; a < D; ++a) {
      if (dom.periodic(a)) continue;
      if (x[a] <= T(dom.min[a]) + eps) {
        Vec<T, D> n = Vec<T, D>::Zero(); n[a] = T(1);
        constraints_.push_back({i, n, dom.walls[2 * a]});
      }
      if (x[a] >= T(dom.max[a]) - eps) {
        Vec<T, D> n = Vec<T, D>::Zero(); n[a] = T(-1);
        constraints_.push_back({i, n, dom.walls[2 * a + 1]});
      }
    }
    for (const auto& c : scene_.colliders) {
      Vec<T, D> n, p0;
      for (int a = 0; a < D; ++a) { n[a] = T(c.normal[a]); p0[a] = T(c.point[a]); }
      if ((x - p0).dot(n) <= eps) constraints_.push_back({i, n, c.condition});
    }
  }
}

// Largest energy the scene can hold without a blow-up: initial kinetic + elastic energy plus
// what gravity can release across the whole domain.
template <class T, int D>
double MpmSimulation<T, D>::energy_reference() const {
  DiagnosticsRow r = measure();
  double g = 0, height = 0;
  for (int a = 0; a < D; ++a) {
    g += scene_.gravity[a] * scene_.gravity[a];
    height += std::pow(scene_.domain.max[a] - scene_.domain.min[a], 2);
  }
  return std::max(r.kinetic + r.elastic + total_mass() * std::sqrt(g) * std::sqrt(height), 1e-300);
}

template <class T, int D>
void MpmSimulation<T, D>::sort_particles() {
  // The colouring stays race-free while no particle has moved a cell away from the block it
  // was sorted into (same-coloured stencils are a block apart); re-sort at half a cell.
  if (drift_since_sort_ < 0.5) return;
  drift_since_sort_ = 0;
  const std::size_t n = p_.size();
  // Block width B: a particle within half a cell of block b reaches nodes [B b − 2, B b + B + 2]
  // (cubic; quadratic and linear one less on the right), so blocks two apart never share a node
  // when B ≥ 4 (quadratic, linear) or B ≥ 5 (cubic). A periodic axis folds its remainder into
  // the last block, so every block is at least B cells wide, also across the wrap.
  const int B = block_cells();
  std::size_t nblocks = 1;
  for (int a = 0; a < D; ++a) {
    blocks_per_axis_[a] = grid_.periodic[a] ? std::max(1, grid_.n[a] / B) : (grid_.n[a] + B - 1) / B;
    nblocks *= std::size_t(blocks_per_axis_[a]);
  }
  keys_.resize(n);
  for (std::size_t q = 0; q < n; ++q) {
    std::size_t key = 0, s = 1;
    for (int a = 0; a < D; ++a) {
      int cell = int(std::floor((p_.x[q][a] - grid_.origin[a]) * grid_.inv_dx));
      cell = grid_.wrap(cell, a);
      key += std::size_t(std::min(cell / B, blocks_per_axis_[a] - 1)) * s;
      s *= std::size_t(blocks_per_axis_[a]);
    }
    keys_[q] = std::uint32_t(key);
  }
  // Counting sort by block (stable, so an already sorted order stays identical).
  block_start_.assign(nblocks + 1, 0);
  for (std::size_t q = 0; q < n; ++q) ++block_start_[keys_[q] + 1];
  for (std::size_t b = 0; b < nblocks; ++b) block_start_[b + 1] += block_start_[b];
  bool sorted = true;
  for (std::size_t q = 1; q < n && sorted; ++q) sorted = keys_[q - 1] <= keys_[q];
  if (!sorted) {
    order_.resize(n);
    std::vector<std::uint32_t>& cursor = keys_;  // reuse: keys are consumed below
    std::vector<std::uint32_t> next(block_start_.begin(), block_start_.end() - 1);
    for (std::size_t q = 0; q < n; ++q) order_[next[cursor[q]]++] = std::uint32_t(q);
    p_.gather_into(order_, scratch_);
    std::swap(p_, scratch_);
    rebuild_index_of_id();
  }
  // Colours: blocks of one colour are at least one block apart, so their stencils never share
  // a node; the last block of a periodic axis gets its own colour (it touches block 0).
  int colors = 1;
  for (int a = 0; a < D; ++a) colors *= 3;
  color_blocks_.resize(std::size_t(colors));
  for (auto& c : color_blocks_) c.clear();
  std::array<int, D> first, last;
  first.fill(std::numeric_limits<int>::max());
  last.fill(-1);
  for (std::size_t b = 0; b < nblocks; ++b) {
    if (block_start_[b] == block_start_[b + 1]) continue;
    std::size_t rest = b;
    int color = 0, scale = 1;
    for (int a = 0; a < D; ++a) {
      int ba = int(rest % std::size_t(blocks_per_axis_[a]));
      rest /= std::size_t(blocks_per_axis_[a]);
      first[a] = std::min(first[a], ba);
      last[a] = std::max(last[a], ba);
      int c = (grid_.periodic[a] && ba == blocks_per_axis_[a] - 1 && ba > 0) ? 2 : ba % 2;
      color += c * scale;
      scale *= 3;
    }
    color_blocks_[std::size_t(color)].push_back(std::uint32_t(b));
  }
  set_active_box(first, last);
}

// The grid passes (clear, unpack, update, pack, walls) run only over the nodes the sorted
// particles can reach until the next sort: scenes whose objects fill a small part of the
// domain stop paying for the empty rest. Nodes leaving the box are zeroed once, here.
template <class T, int D>
void MpmSimulation<T, D>::set_active_box(const std::array<int, D>& first_block, const std::array<int, D>& last_block) {
  std::array<int, D> lo, hi;
  for (int a = 0; a < D; ++a) {
    if (grid_.periodic[a] || last_block[a] < 0) {
      lo[a] = 0;
      hi[a] = last_block[a] < 0 ? 0 : grid_.n[a];
    } else {
      lo[a] = std::max(0, block_cells() * first_block[a] - 2);
      hi[a] = std::min(grid_.n[a], block_cells() * (last_block[a] + 1) + 3);
    }
  }
  if (lo == box_lo_ && hi == box_hi_ && !box_rows_.empty()) return;
  for_each_box_node([&](std::size_t i) {  // the old box
    grid_.accumulator[i] = typename Grid<T, D>::Lanes{};
    grid_.mass[i] = T(0);
    grid_.velocity[i].setZero();
    grid_.velocity_new[i].setZero();
    grid_.force[i].setZero();
  });
  box_lo_ = lo;
  box_hi_ = hi;
  box_rows_.clear();
  if constexpr (D == 2) {
    for (int j = lo[1]; j < hi[1]; ++j)
      box_rows_.push_back({std::size_t(lo[0]) + std::size_t(j) * grid_.stride[1], std::size_t(hi[0] - lo[0])});
  } else {
    for (int k = lo[2]; k < hi[2]; ++k)
      for (int j = lo[1]; j < hi[1]; ++j)
        box_rows_.push_back({std::size_t(lo[0]) + std::size_t(j) * grid_.stride[1] + std::size_t(k) * grid_.stride[2],
                             std::size_t(hi[0] - lo[0])});
  }
  box_constraints_.clear();
  for (const auto& c : constraints_)
    if (in_active_box(c.node)) box_constraints_.push_back(c);
}

template <class T, int D>
std::string MpmSimulation<T, D>::partition_conflict() const {
  std::vector<std::int64_t> owner(grid_.size(), -1);
  std::ostringstream why;
  auto check = [&](auto kernel) {
    using K = decltype(kernel);
    for (std::size_t color = 0; color < color_blocks_.size(); ++color) {
      std::fill(owner.begin(), owner.end(), -1);
      for (std::uint32_t b : color_blocks_[color])
        for (std::uint32_t q = block_start_[b]; q < block_start_[b + 1]; ++q) {
          Stencil<T, D, K> st;
          st.compute(p_.x[q], grid_);
          st.for_each([&](std::size_t node, T, const Vec<T, D>&, const Vec<T, D>&) {
            if (!in_active_box(node) && why.tellp() == 0)
              why << "particle " << q << " reaches node " << node << " outside the active box";
            if (owner[node] >= 0 && owner[node] != std::int64_t(b) && why.tellp() == 0)
              why << "blocks " << owner[node] << " and " << b << " of colour " << color << " share node " << node;
            owner[node] = b;
          });
        }
    }
  };
  switch (scene_.solver.kernel) {
    case KernelType::linear: check(LinearKernel{}); break;
    case KernelType::quadratic: check(QuadraticKernel{}); break;
    case KernelType::cubic: check(CubicKernel{}); break;
  }
  return why.str();
}

template <class T, int D>
template <class Fn>
void MpmSimulation<T, D>::for_each_box_node(Fn&& fn) {
  const std::ptrdiff_t rows = std::ptrdiff_t(box_rows_.size());
#pragma omp parallel for schedule(static) if (parallel_worthwhile())
  for (std::ptrdiff_t r = 0; r < rows; ++r) {
    const auto [start, length] = box_rows_[std::size_t(r)];
    for (std::size_t i = start; i < start + length; ++i) fn(i);
  }
}

template <class T, int D>
void MpmSimulation<T, D>::clear_grid() {
  auto* acc = grid_.accumulator.data();
  for_each_box_node([&](std::size_t i) { acc[i] = typename Grid<T, D>::Lanes{}; });
}

// −V_p P(F_p) F_pᵀ per particle, so that f_i = Σ_p (this) ∇w_ip (eq 34 at λ = 0). A pass of
// its own: without the scatter in the loop, the CPU overlaps the square roots and divisions of
// neighbouring particles instead of waiting on each.
template <class T, int D>
void MpmSimulation<T, D>::compute_stress() {
  stress_.resize(p_.size());
  const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
#pragma omp parallel for schedule(static) if (parallel_worthwhile())
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const MaterialParams<T>& mat = materials_[std::size_t(p_.material[q])];
    const Mat<T, D>& F = p_.F[q];
    stress_[q] = -p_.volume0[q] * first_piola<T, D>(mat.model, F, mat.lame) * F.transpose();
  }
}

template <class T, int D>
template <class K, bool affine, bool with_forces>
void MpmSimulation<T, D>::p2g_impl() {
  // The implicit solve and mesh forces reuse these weights (same x_p^n); G2P recomputes them,
  // which is cheaper than storing and reloading them.
  const bool keep = keeps_stencils();
  auto& cache = stencils<K>();
  if (keep) cache.resize(p_.size());
  constexpr int W = K::width;
  auto* acc = grid_.accumulator.data();
  for (const auto& blocks : color_blocks_) {
    const std::ptrdiff_t nb = std::ptrdiff_t(blocks.size());
// Contiguous chunks: neighbouring same-coloured blocks share cache lines, so they go to one thread.
#pragma omp parallel for schedule(static) if (parallel_worthwhile())
    for (std::ptrdiff_t bi = 0; bi < nb; ++bi) {
      const std::uint32_t b = blocks[std::size_t(bi)];
      for (std::uint32_t q = block_start_[b]; q < block_start_[b + 1]; ++q) {
        Stencil<T, D, K> st;
        st.compute(p_.x[q], grid_);
        if (keep) cache[q] = st;
        const T m = p_.mass[q];
        const Vec<T, D> mv = m * p_.v[q];
        const Mat<T, D> mC = m * p_.C[q];
        Mat<T, D> stress = Mat<T, D>::Zero();
        if constexpr (with_forces) stress = stress_[q];
        // Node i of a row gets w = wx_i row.w and ∇w = (dwx_i row.w, wx_i row.dw[1..]), so with
        // the lanes [m, m v, f]
        //   node_i += row.w (wx_i (mass_mom + r0_i affine[0]) + dwx_i stress_lanes[0])
        //           + wx_i Σ_{a≥1} (row.w row.r_a affine[a] + row.dw_a stress_lanes[a]),
        // where affine[a] = [0, m C col a, 0] and stress_lanes[a] = [0, 0, stress col a]:
        // whole-vector multiply-adds only.
        using Lanes = typename Grid<T, D>::Lanes;
        Lanes mass_mom{}, affine_lanes[D] = {}, stress_lanes[D] = {};
        mass_mom[0] = m;
        for (int a = 0; a < D; ++a) {
          mass_mom[1 + a] = mv[a];
          for (int c = 0; c < D; ++c) {
            if constexpr (affine) affine_lanes[c][1 + a] = mC(a, c);
            stress_lanes[c][1 + D + a] = stress(a, c);
          }
        }
        Lanes per_x[W];
        for (int i = 0; i < W; ++i)
          per_x[i] = st.w[0][i] * (mass_mom + st.r[0][i] * affine_lanes[0]) + st.dw[0][i] * stress_lanes[0];
        st.for_each_row([&](const typename Stencil<T, D, K>::Row& row) {
          Lanes per_row{};
          for (int ax = 1; ax < D; ++ax) {
            if constexpr (affine) per_row += (row.w * row.r[ax]) * affine_lanes[ax];
            if constexpr (with_forces) per_row += row.dw[ax] * stress_lanes[ax];
          }
          const T rw = row.w;
          for (int i = 0; i < W; ++i) acc[st.off[0][i] + row.off] += rw * per_x[i] + st.w[0][i] * per_row;
        });
      }
    }
  }
}

// Accumulator lanes to the grid's arrays: m_i, (m v)_i, f_i.
template <class T, int D>
void MpmSimulation<T, D>::unpack_accumulator() {
  const auto* acc = grid_.accumulator.data();
  for_each_box_node([&](std::size_t i) {
    const auto& node = acc[i];
    grid_.mass[i] = node[0];
    for (int a = 0; a < D; ++a) {
      grid_.velocity[i][a] = node[1 + a];
      grid_.force[i][a] = node[1 + D + a];
    }
  });
}

template <class T, int D>
void MpmSimulation<T, D>::particles_to_grid(bool with_forces) {
  const bool affine = scene_.solver.scheme == Scheme::apic || scene_.solver.scheme == Scheme::rpic;
  if (with_forces) compute_stress();
  auto run = [&](auto kernel) {
    using K = decltype(kernel);
    if (affine) with_forces ? p2g_impl<K, true, true>() : p2g_impl<K, true, false>();
    else with_forces ? p2g_impl<K, false, true>() : p2g_impl<K, false, false>();
  };
  switch (scene_.solver.kernel) {
    case KernelType::linear: run(LinearKernel{}); break;
    case KernelType::quadratic: run(QuadraticKernel{}); break;
    case KernelType::cubic: run(CubicKernel{}); break;
  }
  unpack_accumulator();
}

// The accumulator, free after P2G, holds [ṽ_i, v_i^n] per node for G2P.
template <class T, int D>
void MpmSimulation<T, D>::pack_velocities() {
  auto* acc = grid_.accumulator.data();
  for_each_box_node([&](std::size_t i) {
    typename Grid<T, D>::Lanes node{};
    for (int a = 0; a < D; ++a) {
      node[a] = grid_.velocity_new[i][a];
      node[D + a] = grid_.velocity[i][a];
    }
    acc[i] = node;
  });
}

// v_i^n = (m v)_i / m_i (eq 26), ṽ_i = v_i + Δt (f_i / m_i + g) (eq 29 with λ = 0).
template <class T, int D>
void MpmSimulation<T, D>::grid_velocity_update(T dt) {
  Vec<T, D> g;
  for (int a = 0; a < D; ++a) g[a] = T(scene_.gravity[a]);
  const std::ptrdiff_t rows = std::ptrdiff_t(box_rows_.size());
  double kinetic = 0, vmax2 = 0;
#pragma omp parallel for schedule(static) reduction(+ : kinetic) reduction(max : vmax2) if (parallel_worthwhile())
  for (std::ptrdiff_t r = 0; r < rows; ++r) {
    const auto [start, length] = box_rows_[std::size_t(r)];
    for (std::size_t i = start; i < start + length; ++i) {
      const T m = grid_.mass[i];
      if (m > T(0)) {
        Vec<T, D> v = grid_.velocity[i] / m;
        grid_.velocity[i] = v;
        grid_.velocity_new[i] = v + dt * (grid_.force[i] / m + g);
        kinetic += 0.5 * double(m) * double(v.squaredNorm());
        vmax2 = std::max(vmax2, double(v.squaredNorm()));
      } else {
        grid_.velocity[i].setZero();
        grid_.velocity_new[i].setZero();
      }
    }
  }
  kinetic_grid_ = kinetic;
  max_grid_speed_ = std::sqrt(vmax2);
}

template <class T, int D>
void MpmSimulation<T, D>::apply_boundary_conditions() {
  for (const auto& c : box_constraints_) {  // outside the box ṽ = 0 already satisfies them
    Vec<T, D>& v = grid_.velocity_new[c.node];
    T vn = v.dot(c.normal);
    switch (c.condition) {
      case BoundaryCondition::sticky: v.setZero(); break;
      case BoundaryCondition::slip: v -= vn * c.normal; break;
      case BoundaryCondition::separate: if (vn < T(0)) v -= vn * c.normal; break;
      case BoundaryCondition::periodic: break;
    }
  }
}

// Grid to particles. With u_i = λ v_i + (1 − λ) ṽ_i the moved node is x̃_i = x_i + Δt u_i
// (eq 30), so x_p^{n+1} = Σ w x̃_i = x_p + Δt Σ w u_i (eq 39) and F^{n+1} = (I + Δt Σ u_i ∇wᵀ) F
// (eq 40). APIC's eq 38 expands to B = Σ w ṽ rᵀ + Δt/2 (S − Sᵀ − v_p ūᵀ + ū v_pᵀ) with
// S = Σ w ṽ u_iᵀ and ū = Σ w u_i, which is exact and needs one pass over the stencil.
template <class T, int D>
template <class K, Scheme S>
void MpmSimulation<T, D>::g2p_impl(T dt) {
  const T lambda = T(scene_.solver.integrator_lambda());
  const T alpha = T(scene_.solver.flip_alpha);
  const bool lagged = K::type == KernelType::linear;  // Sec 5.9: lagged C for multilinear
  const T inv_k = lagged ? T(0) : T(1) / inertia_scale();
  const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
  bool bad = false;
  double max_move = 0;
  Vec<T, D> lo, hi;
  for (int a = 0; a < D; ++a) { lo[a] = T(scene_.domain.min[a]); hi[a] = T(scene_.domain.max[a]); }
  using Lanes = typename Grid<T, D>::Lanes;
  const Lanes* packed = grid_.accumulator.data();
  pack_velocities();
  // Lanes of ṽ × vⁿ: c_a = ṽ_{a+1} vⁿ_{a+2} − ṽ_{a+2} vⁿ_{a+1} in 3D, c_0 = ṽ_0 vⁿ_1 − ṽ_1 vⁿ_0 in 2D.
  auto cross = [](const Lanes& n) {
    if constexpr (D == 3)
      return permute<T, 1, 2, 0>(n) * permute<T, 5, 3, 4>(n) - permute<T, 2, 0, 1>(n) * permute<T, 4, 5, 3>(n);
    else
      return permute<T, 0, 0, 0>(n) * permute<T, 3, 3, 3>(n) - permute<T, 1, 1, 1>(n) * permute<T, 2, 2, 2>(n);
  };
#pragma omp parallel for schedule(static) reduction(|| : bad) reduction(max : max_move) if (parallel_worthwhile())
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    Stencil<T, D, K> st;
    st.compute(p_.x[std::size_t(q)], grid_);
    // Gather row by row (see Stencil::for_each_row) on nodes packed as [ṽ (D), vⁿ (D), pad],
    // whole vectors at a time: lanes 0..D−1 give the sums over ṽ, lanes D..2D−1 over vⁿ.
    constexpr int W = K::width;
    const T* wx = st.w[0];
    T wr[W];
    for (int i = 0; i < W; ++i) wr[i] = wx[i] * st.r[0][i];
    Lanes vsum{}, grad_cols[D] = {}, b_cols[D] = {}, twist{};
    auto gather = [&](auto moving_nodes) {  // Σ w (ṽ × vⁿ) only for λ > 0
      st.for_each_row([&](const typename Stencil<T, D, K>::Row& row) {
        Lanes s0{}, s1{}, g0{}, t0{};
        for (int i = 0; i < W; ++i) {
          const Lanes node = packed[st.off[0][i] + row.off];
          s0 += wx[i] * node;
          s1 += wr[i] * node;
          g0 += st.dw[0][i] * node;
          if constexpr (decltype(moving_nodes)::value) t0 += wx[i] * cross(node);
        }
        vsum += row.w * s0;
        if constexpr (decltype(moving_nodes)::value) twist += row.w * t0;
        grad_cols[0] += row.w * g0;
        b_cols[0] += row.w * s1;
        for (int ax = 1; ax < D; ++ax) {
          grad_cols[ax] += row.dw[ax] * s0;
          b_cols[ax] += (row.w * row.r[ax]) * s0;
        }
      });
    };
    if (lambda != T(0)) gather(std::true_type{});
    else gather(std::false_type{});
    // u_i = λ vⁿ_i + (1 − λ) ṽ_i (eq 30): ū = Σ w u, ∇u = Σ u ∇wᵀ.
    Vec<T, D> vpic, vold_p, ubar;
    Mat<T, D> Bsum, gradu, gradv;
    for (int a = 0; a < D; ++a) {
      vpic[a] = vsum[a];
      vold_p[a] = vsum[D + a];
      ubar[a] = lambda * vsum[D + a] + (T(1) - lambda) * vsum[a];
      for (int c = 0; c < D; ++c) {
        gradv(a, c) = grad_cols[c][a];
        gradu(a, c) = lambda * grad_cols[c][D + a] + (T(1) - lambda) * grad_cols[c][a];
        Bsum(a, c) = b_cols[c][a];
      }
    }
    // Velocity and affine matrix per scheme.
    if constexpr (S == Scheme::pic) {
      p_.v[q] = vpic;  // eq 2
    } else if constexpr (S == Scheme::flip) {
      p_.v[q] = alpha * (p_.v[q] + vpic - vold_p) + (T(1) - alpha) * vpic;  // eq 3, PIC blend
    } else {
      p_.v[q] = vpic;  // eq 37
      Mat<T, D> C;
      if (lagged) {
        C = gradv;  // Sec 5.9: C = Σ ṽ_i ∇w_ipᵀ
      } else {
        Mat<T, D> B = Bsum;
        if (lambda != T(0)) {
          // S − Sᵀ with S = Σ w ṽ uᵀ is λ Σ w (ṽ vⁿᵀ − vⁿ ṽᵀ), whose entries are Σ w (ṽ × vⁿ).
          Mat<T, D> skew;
          if constexpr (D == 3) skew << T(0), twist[2], -twist[1], -twist[2], T(0), twist[0], twist[1], -twist[0], T(0);
          else skew << T(0), twist[0], -twist[0], T(0);
          B += T(0.5) * dt * (lambda * skew - vpic * ubar.transpose() + ubar * vpic.transpose());
        }
        C = B * inv_k;  // C = B D⁻¹ with D = k Δx² I
      }
      if constexpr (S == Scheme::rpic) {
        if (lagged) {
          // ω = K_p⁻¹ l_p with K_p = tr(D_p) I − D_p (Sec 2.1): keep only the rigid part.
          Mat<T, D> Dp = st.inertia();
          Mat<T, D> B = C * Dp;
          Mat<T, D> skewB = T(0.5) * (B - B.transpose());
          Mat<T, D> Cr = Mat<T, D>::Zero();
          if constexpr (D == 2) {
            T kk = Dp.trace();
            T w = kk > T(0) ? T(2) * skewB(1, 0) / kk : T(0);
            Cr << T(0), -w, w, T(0);
          } else {
            Vec<T, 3> l(T(2) * skewB(2, 1), T(2) * skewB(0, 2), T(2) * skewB(1, 0));
            Vec<T, 3> w;
            for (int a = 0; a < 3; ++a) {
              T kk = Dp.trace() - Dp(a, a);
              w[a] = kk > T(0) ? l[a] / kk : T(0);
            }
            Cr << T(0), -w[2], w[1], w[2], T(0), -w[0], -w[1], w[0], T(0);
          }
          C = Cr;
        } else {
          C = (T(0.5) * (C - C.transpose())).eval();  // RPIC: the skew part, ω = K⁻¹ l (Sec 5.6.3)
        }
      }
      p_.C[q] = C;
    }
    // Particle update: positions on the moved grid (eq 39), F by eq 40.
    Vec<T, D> x = p_.x[q] + dt * ubar;
    max_move = std::max(max_move, double((dt * ubar).cwiseAbs().maxCoeff()));
    for (int a = 0; a < D; ++a) {
      if (grid_.periodic[a]) {
        const T L = hi[a] - lo[a];
        if (x[a] < lo[a] || x[a] >= hi[a]) x[a] -= L * std::floor((x[a] - lo[a]) / L);
        if (x[a] >= hi[a]) x[a] = lo[a];  // round-off of the line above
      } else {
        x[a] = std::min(std::max(x[a], lo[a]), hi[a]);  // walls: keep the stencil on the grid
      }
    }
    p_.x[q] = x;
    const Mat<T, D> F0 = p_.F[q];
    for (int b = 0; b < D; ++b)
      for (int a = 0; a < D; ++a) {
        T s = F0(a, b);
        for (int k = 0; k < D; ++k) s += dt * gradu(a, k) * F0(k, b);
        p_.F[q](a, b) = s;
      }
    if (!std::isfinite(x.sum() + p_.v[q].sum())) bad = true;
  }
  non_finite_ = non_finite_ || bad;
  drift_since_sort_ += std::isfinite(max_move) ? max_move * double(grid_.inv_dx) : 1e30;
}

template <class T, int D>
void MpmSimulation<T, D>::grid_to_particles(T dt) {
  auto run = [&](auto kernel) {
    using K = decltype(kernel);
    switch (scene_.solver.scheme) {
      case Scheme::pic: g2p_impl<K, Scheme::pic>(dt); break;
      case Scheme::flip: g2p_impl<K, Scheme::flip>(dt); break;
      case Scheme::apic: g2p_impl<K, Scheme::apic>(dt); break;
      case Scheme::rpic: g2p_impl<K, Scheme::rpic>(dt); break;
    }
  };
  switch (scene_.solver.kernel) {
    case KernelType::linear: run(LinearKernel{}); break;
    case KernelType::quadratic: run(QuadraticKernel{}); break;
    case KernelType::cubic: run(CubicKernel{}); break;
  }
}

template <class T, int D>
void MpmSimulation<T, D>::step_fixed(double dt) {
  // A non-finite position would index the grid out of range: the state stays frozen, and
  // step() (or the caller of step_fixed, through measure()) reports it.
  if (non_finite_) return;
  const SolverDesc& sv = scene_.solver;
  sort_particles();
  clear_grid();
  if (!implicit_update()) {
    particles_to_grid(true);  // forces at F^n, fused into the transfer
    if (!mesh_.empty()) {
      switch (sv.kernel) {
        case KernelType::linear: add_mesh_forces<LinearKernel>(); break;
        case KernelType::quadratic: add_mesh_forces<QuadraticKernel>(); break;
        case KernelType::cubic: add_mesh_forces<CubicKernel>(); break;
      }
    }
    grid_velocity_update(T(dt));
    last_newton_iters_ = last_cg_iters_ = 0;
    last_residual_ = 0;
    last_converged_ = true;
  } else {
    particles_to_grid(false);
    switch (sv.kernel) {
      case KernelType::linear: implicit_velocity_update<LinearKernel>(T(dt)); break;
      case KernelType::quadratic: implicit_velocity_update<QuadraticKernel>(T(dt)); break;
      case KernelType::cubic: implicit_velocity_update<CubicKernel>(T(dt)); break;
    }
  }
  apply_boundary_conditions();
  grid_to_particles(T(dt));
  time_ += dt;
  ++steps_;
}

// Time-step rules (registry `dt_rule_choices`), then the Sec 6.7 landing rule on t_limit.
template <class T, int D>
double MpmSimulation<T, D>::choose_dt(double t_limit) const {
  const TimeDesc& tm = scene_.time;
  const double dx = scene_.domain.dx;
  double dt_star = tm.dt;
  if (tm.rule != DtRule::fixed) {
    double vmax = 0, cterm = 0;
    const double k6 = 6.0 * std::sqrt(double(D)) * std::max(inertia_factor(scene_.solver.kernel), 0.25) * dx;
    const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
#pragma omp parallel for reduction(max : vmax, cterm) if (parallel_worthwhile())
    for (std::ptrdiff_t q = 0; q < n; ++q) {
      double v = double(p_.v[q].norm());
      vmax = std::max(vmax, v);
      cterm = std::max(cterm, v + k6 * double(p_.C[q].norm()));  // Sec 4.3: |v_p| + (κ/k)Δx‖B_p‖
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
  dt_star = std::min(dt_star, 1.0 / tm.fps);
  double to_frame = t_limit - time_;
  if (to_frame < 1.001 * dt_star) return to_frame;  // land on the frame time
  if (to_frame < 2.0 * dt_star) return 0.5 * to_frame;  // avoid a sliver step
  return dt_star;
}

template <class T, int D>
std::optional<Failure> MpmSimulation<T, D>::step(double t_limit, DiagnosticsRow* row) {
  if (failure_) return failure_;
  if (!(t_limit > time_)) return std::nullopt;
  auto start = std::chrono::steady_clock::now();
  double dt = choose_dt(t_limit);
  step_fixed(dt);
  if (t_limit - time_ < 1e-12 * std::max(1.0, std::abs(t_limit))) time_ = t_limit;  // exact landing
  DiagnosticsRow r = measure();
  r.dt = dt;
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (row) *row = r;
  auto fail = [&](const std::string& quantity, const std::string& detail) {
    std::ostringstream msg;
    msg << "simulation blew up at step " << steps_ << ", t = " << time_ << ": " << quantity << " " << detail;
    failure_ = Failure{steps_, time_, quantity, msg.str()};
  };
  if (!last_converged_ && scene_.solver.stop_on_nonconvergence) {
    std::ostringstream d;
    d << "did not converge in " << last_newton_iters_ << " Newton iterations (residual " << last_residual_ << ")";
    fail("implicit solve", d.str());
  } else if (non_finite_ || !std::isfinite(r.total) || !std::isfinite(r.kinetic)) {
    fail("particle state", "became non-finite (NaN or Inf)");
  } else if (r.kinetic + r.elastic > scene_.solver.blowup_energy_factor * energy_ref_) {
    std::ostringstream d;
    d << "grew to " << r.kinetic + r.elastic << ", more than " << scene_.solver.blowup_energy_factor
      << " x the energy available (" << energy_ref_ << ")";
    fail("kinetic + elastic energy", d.str());
  }
  return failure_;
}

template <class T, int D>
double MpmSimulation<T, D>::elastic_energy() const {
  double e = 0;
  const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
#pragma omp parallel for reduction(+ : e) if (parallel_worthwhile())
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    if (p_.volume0[q] == T(0)) continue;  // mesh vertices: their elasticity is on the triangles
    const MaterialParams<T>& mat = materials_[std::size_t(p_.material[q])];
    e += double(p_.volume0[q]) * double(energy_density<T, D>(mat.model, p_.F[q], mat.lame));
  }
  if constexpr (D == 2)
    if (!mesh_.empty()) e += mesh_.energy(p_.x, index_of_id_, nullptr);
  return e;
}

// Energies and momenta of the particle state, with the affine terms ½ m tr(C D Cᵀ) and
// m (Bᵀ : ε), B = C D_p (DESIGN.md, Diagnostics CSV).
template <class T, int D>
DiagnosticsRow MpmSimulation<T, D>::measure() const {
  DiagnosticsRow r;
  r.step = steps_;
  r.t = time_;
  r.kinetic_grid = kinetic_grid_;
  r.newton_iters = last_newton_iters_;
  r.cg_iters = last_cg_iters_;
  r.residual = last_residual_;
  r.converged = last_converged_;
  const bool affine = scene_.solver.scheme == Scheme::apic || scene_.solver.scheme == Scheme::rpic;
  double kin = 0, grav = 0, px = 0, py = 0, pz = 0, Lx = 0, Ly = 0, Lz = 0;
  const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
  const KernelType kernel = scene_.solver.kernel;
  const Vec3d g = scene_.gravity;
#pragma omp parallel for reduction(+ : kin, grav, px, py, pz, Lx, Ly, Lz) if (parallel_worthwhile())
  for (std::ptrdiff_t q = 0; q < n; ++q) {
    const double m = double(p_.mass[q]);
    const Vec<T, D>& v = p_.v[q];
    kin += 0.5 * m * double(v.squaredNorm());
    Vec<T, D> mv = p_.mass[q] * v;
    px += double(mv[0]);
    py += double(mv[1]);
    if constexpr (D == 3) pz += double(mv[2]);
    Eigen::Vector3d L = cross_moment<T, D>(p_.x[q], mv);
    for (int a = 0; a < D; ++a) grav -= m * g[a] * double(p_.x[q][a]);
    if (affine) {
      Mat<T, D> Dp;
      if (kernel == KernelType::linear) {
        Stencil<T, D, LinearKernel> st;
        st.compute(p_.x[q], grid_);
        Dp = st.inertia();
      } else {
        Dp = inertia_scale() * Mat<T, D>::Identity();
      }
      const Mat<T, D>& C = p_.C[q];
      kin += 0.5 * m * double((C * Dp * C.transpose()).trace());
      L += m * permutation_contract<T, D>(Mat<T, D>((C * Dp).transpose()));
    }
    Lx += L[0]; Ly += L[1]; Lz += L[2];
  }
  r.kinetic = kin;
  r.elastic = elastic_energy();
  r.potential = r.elastic + grav;
  r.total = r.kinetic + r.potential;
  r.p = {px, py, pz};
  r.L = {Lx, Ly, Lz};
  return r;
}

template <class T, int D>
void MpmSimulation<T, D>::grid_momentum(bool updated, Eigen::Vector3d& p, Eigen::Vector3d& L) const {
  p.setZero();
  L.setZero();
  const auto& vel = updated ? grid_.velocity_new : grid_.velocity;
  for (std::size_t i = 0; i < grid_.size(); ++i) {
    if (grid_.mass[i] <= T(0)) continue;
    Vec<T, D> mv = grid_.mass[i] * vel[i];
    for (int a = 0; a < D; ++a) p[a] += double(mv[a]);
    L += cross_moment<T, D>(grid_.node_position(i), mv);
  }
}

template <class T, int D>
Eigen::Vector3d MpmSimulation<T, D>::total_force() const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < grid_.size(); ++i)
    for (int a = 0; a < D; ++a) f[a] += double(grid_.force[i][a]);
  return f;
}

template <class T, int D>
void MpmSimulation<T, D>::set_scheme(Scheme scheme, double flip_alpha) {
  const bool was_affine = scene_.solver.scheme == Scheme::apic || scene_.solver.scheme == Scheme::rpic;
  scene_.solver.scheme = scheme;
  scene_.solver.flip_alpha = flip_alpha;
  if (scheme == Scheme::pic || scheme == Scheme::flip) {
    for (auto& C : p_.C) C.setZero();
  } else if (scheme == Scheme::rpic && was_affine) {
    for (auto& C : p_.C) C = (T(0.5) * (C - C.transpose())).eval();  // eval: C aliases Cᵀ
  }
}

// |v_p − Σ w_ip v_i| with v_i from a fresh P2G of the current particles (this scheme's own
// transfer, so an affine field gives zero): velocity modes the grid cannot see.
template <class T, int D>
template <class K>
void MpmSimulation<T, D>::velocity_noise(std::vector<float>& out) const {
  const bool affine = scene_.solver.scheme == Scheme::apic || scene_.solver.scheme == Scheme::rpic;
  std::vector<T> mass(grid_.size(), T(0));
  std::vector<Vec<T, D>> mom(grid_.size(), Vec<T, D>::Zero());
  Stencil<T, D, K> st;
  for (std::size_t q = 0; q < p_.size(); ++q) {
    st.compute(p_.x[q], grid_);
    const T m = p_.mass[q];
    st.for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>& r) {
      mass[i] += w * m;
      mom[i] += w * m * (affine ? Vec<T, D>(p_.v[q] + p_.C[q] * r) : p_.v[q]);
    });
  }
  out.assign(p_.size(), 0.f);
  for (std::size_t q = 0; q < p_.size(); ++q) {
    st.compute(p_.x[q], grid_);
    Vec<T, D> v = Vec<T, D>::Zero();
    st.for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) {
      if (mass[i] > T(0)) v += w * mom[i] / mass[i];
    });
    out[std::size_t(p_.id[q])] = float((p_.v[q] - v).norm());
  }
}

template <class T, int D>
std::shared_ptr<Snapshot> MpmSimulation<T, D>::snapshot(bool with_noise) const {
  auto s = std::make_shared<Snapshot>();
  s->dim = D;
  s->step = steps_;
  s->time = time_;
  s->scene_name = scene_.name;
  s->scheme = key_of(scene_.solver.scheme);
  s->kernel = key_of(scene_.solver.kernel);
  s->integrator = key_of(scene_.solver.integrator);
  s->flip_alpha = scene_.solver.flip_alpha;
  const std::size_t n = p_.size();
  s->positions.resize(n * D);
  s->velocities.resize(n * D);
  s->material.resize(n);
  s->object.resize(n);
  for (std::size_t q = 0; q < n; ++q) {
    std::size_t k = std::size_t(p_.id[q]);
    for (int a = 0; a < D; ++a) {
      s->positions[k * D + a] = float(p_.x[q][a]);
      s->velocities[k * D + a] = float(p_.v[q][a]);
    }
    s->material[k] = p_.material[q];
    s->object[k] = p_.object[q];
  }
  s->radius = radius_;
  if (with_noise) {
    switch (scene_.solver.kernel) {
      case KernelType::linear: velocity_noise<LinearKernel>(s->noise); break;
      case KernelType::quadratic: velocity_noise<QuadraticKernel>(s->noise); break;
      case KernelType::cubic: velocity_noise<CubicKernel>(s->noise); break;
    }
  }
  s->domain_min = scene_.domain.min;
  s->domain_max = scene_.domain.max;
  s->dx = scene_.domain.dx;
  s->colliders = scene_.colliders;
  for (auto& m : scene_.materials) s->material_names.push_back(m.name);
  s->failure = failure_;
  return s;
}

template <class T, int D>
void MpmSimulation<T, D>::write_particles_csv(std::ostream& out) const {
  out << "id,object,x,y" << (D == 3 ? ",z" : "") << ",vx,vy" << (D == 3 ? ",vz" : "") << ",mass,volume0";
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) out << ",F" << i << j;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) out << ",C" << i << j;
  out << "\n";
  std::vector<std::size_t> by_id(p_.size());
  for (std::size_t q = 0; q < p_.size(); ++q) by_id[std::size_t(p_.id[q])] = q;
  out << std::setprecision(std::numeric_limits<T>::max_digits10);
  for (std::size_t q : by_id) {
    out << p_.id[q] << ',' << p_.object[q];
    for (int a = 0; a < D; ++a) out << ',' << p_.x[q][a];
    for (int a = 0; a < D; ++a) out << ',' << p_.v[q][a];
    out << ',' << p_.mass[q] << ',' << p_.volume0[q];
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) out << ',' << p_.F[q](i, j);
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) out << ',' << p_.C[q](i, j);
    out << '\n';
  }
}

}  // namespace apiclab
