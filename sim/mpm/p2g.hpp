// Particles to grid (Jiang et al. 2017, eqs 24-25 and the explicit forces of eq 34).
#pragma once
#include <type_traits>

#include "sim/mpm/kernel_dispatch.hpp"
#include "sim/mpm/mpm.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"
#include "sim/mpm/simd/stencil_batch.hpp"
#include "sim/mpm/simd/stress_lanes.hpp"

namespace apiclab {

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
      st[q].for_each([&](std::size_t i, T w, const Vec<T, D>&, const Vec<T, D>&) {
        grid_.force[i] -= w * mesh_g_[q];
      });
    }
  }
}
template <class T, int D>
void MpmSimulation<T, D>::clear_grid() {
  auto* acc = grid_.node_lanes.data();
  for_each_box_node([&](std::size_t i) { acc[i] = typename Grid<T, D>::NodeLanes{}; });
}

// −V_p P(F_p) F_pᵀ per particle, so that f_i = Σ_p (this) ∇w_ip (eq 34 at λ = 0). A pass of
// its own: without the scatter in the loop, the CPU overlaps the square roots and divisions of
// neighbouring particles instead of waiting on each. The same pass sums the elastic energy
// Σ V_p Ψ(F_p) for measure() (run at the end of an explicit step, see step_fixed).
template <class T, int D>
void MpmSimulation<T, D>::compute_stress() {
  stress_.resize(p_.size());
  const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
  auto one = [&](std::ptrdiff_t q) {
    const MaterialParams<T>& mat = materials_[std::size_t(p_.material[q])];
    const Mat<T, D>& F = p_.F[q];
    T psi;
    stress_[q] =
        -p_.volume0[q] * first_piola_and_energy<T, D>(mat.model, F, mat.lame, psi) * F.transpose();
    // Mesh vertices (volume 0) carry no elasticity: theirs is on the triangles.
    return p_.volume0[q] != T(0) ? double(p_.volume0[q]) * double(psi) : 0.0;
  };
  double energy = 0;
  std::ptrdiff_t lanes_end = 0;  // particles before this went through StressLanes
  {
    const bool all_corotated = std::all_of(
        materials_.begin(), materials_.end(),
        [](const MaterialParams<T>& m) { return m.model == MaterialModel::fixed_corotated; });
    using Lanes = StressLanes<T, D>;
    constexpr int L = Lanes::count;
    if (all_corotated) lanes_end = n / L * L;
#pragma omp parallel for schedule(static) reduction(+ : energy) if (parallel_worthwhile())
    for (std::ptrdiff_t b = 0; b < lanes_end; b += L) {
      T mu[L], lambda[L], psi[L];
      for (int l = 0; l < L; ++l) {
        const Lame<T>& lame = materials_[std::size_t(p_.material[b + l])].lame;
        mu[l] = lame.mu;
        lambda[l] = lame.lambda;
      }
      unsigned scalar = 0;  // lanes that StressLanes hands back (3D only)
      if constexpr (D == 3)
        scalar = Lanes::fixed_corotated(&p_.F[b], mu, lambda, &p_.volume0[b], &stress_[b], psi);
      else
        Lanes::fixed_corotated_2d(&p_.F[b], mu, lambda, &p_.volume0[b], &stress_[b], psi);
      for (int l = 0; l < L; ++l) {
        if (scalar >> l & 1u)
          energy += one(b + l);
        else if (p_.volume0[b + l] != T(0))
          energy += double(p_.volume0[b + l]) * double(psi[l]);
      }
    }
  }
#pragma omp parallel for schedule(static) reduction(+ : energy) if (parallel_worthwhile())
  for (std::ptrdiff_t q = lanes_end; q < n; ++q) energy += one(q);
  stress_of_current_F_ = true;
  particle_elastic_energy_ = energy;
}

template <class T, int D>
template <class K, bool affine, bool with_forces, bool mls_forces>
void MpmSimulation<T, D>::p2g_impl() {
  // The implicit solve and mesh forces reuse these weights (same x_p^n); G2P recomputes them,
  // which is cheaper than storing and reloading them.
  const bool keep = keeps_stencils();
  auto& cache = stencils<K>();
  if (keep) cache.resize(p_.size());
  constexpr int W = K::width;
  auto* acc = grid_.node_lanes.data();
  // MLS-MPM: f_i = −Σ V P Fᵀ D⁻¹ w (x_i − x_p), the stress riding the affine weights.
  const T inv_k = mls_forces ? T(1) / inertia_scale() : T(0);
  // Keeping the stencils compiled apart: the copy in the loop, even untaken, let GCC hoist the
  // stencil's loads above the scatter and spill them (x86-64-v3; see StencilBatch::for_each_row).
  auto scatter = [&](auto keeping) {
    blocks_.for_each_block_coloured(
        [&](std::uint32_t begin, std::uint32_t end) {
          StencilBatch<T, D, K> batch;
          for (std::uint32_t q = begin; q < end; ++q) {
            const int lane = int((q - begin) % batch.L);
            if (lane == 0)
              batch.compute(&p_.x[q], int(std::min<std::uint32_t>(batch.L, end - q)), grid_);
            const T m = p_.mass[q];
            const Vec<T, D> mv = m * p_.v[q];
            const Mat<T, D> mC = m * p_.C[q];
            Mat<T, D> stress = Mat<T, D>::Zero(), mls = Mat<T, D>::Zero();
            if constexpr (with_forces) stress = stress_[q];
            if constexpr (mls_forces) mls = inv_k * stress_[q];
            // Node i of a row gets w = wx_i row.w and ∇w = (dwx_i row.w, wx_i row.dw[1..]), so with
            // the lanes [m, m v, f]
            //   node_i += row.w (wx_i (mass_mom + r0_i affine[0]) + dwx_i stress_lanes[0])
            //           + wx_i Σ_{a≥1} (row.w row.r_a affine[a] + row.dw_a stress_lanes[a]),
            // where affine[a] = [0, m C col a, 0] and stress_lanes[a] = [0, 0, stress col a]:
            // whole-vector multiply-adds only.
            // Each group built whole in registers (Lanes::of), not lane by lane.
            using Lanes = typename Grid<T, D>::NodeLanes;
            Lanes mass_mom, affine_lanes[D], stress_lanes[D];
            if constexpr (D == 2) {
              mass_mom = Lanes::of(m, mv[0], mv[1]);
              for (int c = 0; c < D; ++c) {
                affine_lanes[c] =
                    affine ? Lanes::of(T(0), mC(0, c), mC(1, c), mls(0, c), mls(1, c)) : Lanes{};
                stress_lanes[c] = Lanes::of(T(0), T(0), T(0), stress(0, c), stress(1, c));
              }
            } else {
              mass_mom = Lanes::of(m, mv[0], mv[1], mv[2]);
              for (int c = 0; c < D; ++c) {
                affine_lanes[c] = affine ? Lanes::of(T(0), mC(0, c), mC(1, c), mC(2, c), mls(0, c),
                                                     mls(1, c), mls(2, c))
                                         : Lanes{};
                stress_lanes[c] =
                    Lanes::of(T(0), T(0), T(0), T(0), stress(0, c), stress(1, c), stress(2, c));
              }
            }
            Lanes per_x[W];
            for (int i = 0; i < W; ++i)
              per_x[i] = batch.w[0][i][lane] * (mass_mom + batch.r[0][i][lane] * affine_lanes[0]) +
                         batch.dw[0][i][lane] * stress_lanes[0];
            // Each x-node's address once a particle: acc[off_i + row.off] spelled as one index
            // cost a shift and two adds a node (a node is 32 bytes, beyond x86's address scales).
            Lanes* acc_x[W];
            for (int i = 0; i < W; ++i) acc_x[i] = acc + batch.off[0][i][lane];
            batch.for_each_row(lane, [&](const typename StencilBatch<T, D, K>::Row& row) {
              Lanes per_row{};
              for (int ax = 1; ax < D; ++ax) {
                if constexpr (affine) per_row += row.wr(ax) * affine_lanes[ax];
                if constexpr (with_forces) per_row += row.dw[ax] * stress_lanes[ax];
              }
              const T rw = row.w;
              for (int i = 0; i < W; ++i) {
                // Two multiply-adds onto the node, not a multiply, a multiply-add and an add: one
                // instruction a node fewer. This order of the sums sets their round-off, which
                // Fig 6's FLIP drift and PolyPIC's blow-up time show.
                Lanes& node = acc_x[i][row.off];
                node = node + rw * per_x[i];
                node = node + batch.w[0][i][lane] * per_row;
              }
            });
            if constexpr (decltype(keeping)::value) batch.get(lane, cache[q]);
          }
        },
        parallel_worthwhile());
  };
  if (keep)
    scatter(std::true_type{});
  else
    scatter(std::false_type{});
}

// Accumulator lanes to the grid's arrays: m_i, v_i = (m v)_i / m_i (eq 26) and f_i.
template <class T, int D>
void MpmSimulation<T, D>::unpack_accumulator() {
  const auto* acc = grid_.node_lanes.data();
  for_each_box_node([&](std::size_t i) {
    const auto& node = acc[i];
    const T m = node[0];
    grid_.mass[i] = m;
    for (int a = 0; a < D; ++a) {
      grid_.velocity[i][a] = m > T(0) ? node[1 + a] / m : T(0);  // eq 26: v_i = (m v)_i / m_i
      grid_.force[i][a] = node[1 + D + a];
    }
  });
}

// Eqs 24-25: m_i = Σ w m_p and (m v)_i = Σ w m_p (v_p + C_p (x_i − x_p)) (C_p = 0 for PIC
// and FLIP), with f_i = Σ (−V_p P F_pᵀ) ∇w (eq 34 at λ = 0) when with_forces; then the
// velocity v_i = (m v)_i / m_i (eq 26) as the accumulator is unpacked, zero at nodes without mass.
template <class T, int D>
void MpmSimulation<T, D>::particles_to_grid(bool with_forces) {
  const bool affine = is_affine(scene_.solver.scheme);
  const bool mls = scheme_info(scene_.solver.scheme).force_in_affine;
  if (with_forces && !stress_of_current_F_) compute_stress();
  with_kernel(scene_.solver.kernel, [&](auto kernel) {
    using K = decltype(kernel);
    if (mls && with_forces)
      p2g_impl<K, true, false, true>();  // the force in the affine term, no ∇w term
    else if (affine)
      with_forces ? p2g_impl<K, true, true>() : p2g_impl<K, true, false>();
    else
      with_forces ? p2g_impl<K, false, true>() : p2g_impl<K, false, false>();
    if constexpr (K::type == KernelType::quadratic)
      if (!p_.modes.empty()) p2g_polypic_modes<K>();
  });
  unpack_accumulator();
}

// PolyPIC (Fu et al. 2017): (m v)_i += Σ_p w_ip m_p Σ_j c_pj s_j(x_i − x_p) for the modes
// beyond the affine ones (which p2g_impl transferred as C_p); mass and forces are unchanged.
// A pass of its own over the same coloured blocks, so the affine path stays as fast as APIC's.
template <class T, int D>
template <class K>
void MpmSimulation<T, D>::p2g_polypic_modes() {
  using Lanes = typename Grid<T, D>::NodeLanes;
  auto* acc = grid_.node_lanes.data();
  const T inv_dx = grid_.inv_dx;
  auto pass = [&](auto functions) {  // per-axis functions reached: 2, or 3 with the G modes
    constexpr int F = decltype(functions)::value;
    blocks_.for_each_block_coloured(
        [&](std::uint32_t begin, std::uint32_t end) {
          for (std::uint32_t q = begin; q < end; ++q) {
            Stencil<T, D, K> st;
            st.compute(p_.x[q], grid_);
            polypic::scatter_modes_rows<T, D, F, Lanes>(
                st, inv_dx, p_.modes, q, p_.mass[q],
                [&](std::size_t i, const Lanes& v) { acc[i] += v; });
          }
        },
        parallel_worthwhile());
  };
  if (polypic::keeps_g_modes(1 + D + int(p_.modes.size()), D))
    pass(std::integral_constant<int, 3>{});
  else
    pass(std::integral_constant<int, 2>{});
}

}  // namespace apiclab
