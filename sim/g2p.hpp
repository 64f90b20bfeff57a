// Grid to particles: the gather of eqs 37-40 and the particle update (eqs 39-40).
#pragma once
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "deformation_update.hpp"
#include "gather_paired.hpp"
#include "kernel_dispatch.hpp"
#include "mpm.hpp"
#include "particle_tail.hpp"
#include "stencil_batch.hpp"
#include "transfer_polypic.hpp"
#include "transfer_schemes.hpp"

namespace apiclab {

// Grid to particles. With u_i = λ v_i + (1 − λ) ṽ_i the moved node is x̃_i = x_i + Δt u_i
// (eq 30), so x_p^{n+1} = Σ w x̃_i = x_p + Δt Σ w u_i (eq 39) and F^{n+1} = (I + Δt Σ u_i ∇wᵀ) F
// (eq 40). APIC's eq 38 expands to B = Σ w ṽ rᵀ + Δt/2 (S − Sᵀ − v_p ūᵀ + ū v_pᵀ) with
// S = Σ w ṽ u_iᵀ and ū = Σ w u_i, which is exact and needs one pass over the stencil.
//
// With sums, each particle also adds its share of the diagnostics row at its new state (x, v,
// C, modes), which this loop has in registers: measure()'s own pass over the particles saved
// (sim/particle_sums.hpp).
template <class T, int D>
template <class K, Scheme S>
void MpmSimulation<T, D>::g2p_impl(T dt, ParticleSums* sums) {
  const T lambda = T(scene_.solver.integrator_lambda());
  const T alpha = T(scene_.solver.flip_alpha);
  const T beta = T(scene_.solver.asflip_beta);
  // XPIC(m > 1) gathers Σ w e_i of its grid field (sim/transfer_xpic.hpp).
  const bool xpic_gather = S == Scheme::xpic && scene_.solver.xpic_order > 1;
  const Vec<T, D>* xpic_shift = xpic_shift_.data();
  // Sec 5.9: the multilinear kernel's D_p is not k Δx² I. Its lagged C (default) is stable;
  // `bform` keeps C = B D_p⁻¹ with D_p at the particle's next position (unstable).
  const bool multilinear = K::type == KernelType::linear;
  const bool lagged = multilinear && scene_.solver.apic_linear_form == ApicLinearForm::lagged;
  const bool bform_multilinear = multilinear && !lagged;
  const T inv_k = multilinear ? T(0) : T(1) / inertia_scale();
  const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
  const int polypic_kept = polypic::kept_modes(scene_.solver.polypic_modes, D);
  const int polypic_extra = int(p_.modes.size());
  const bool polypic_g = polypic::keeps_g_modes(1 + D + polypic_extra, D);
  bool bad = false;
  double max_move = 0;
  Vec<T, D> lo, hi;
  for (int a = 0; a < D; ++a) {
    lo[a] = T(scene_.domain.min[a]);
    hi[a] = T(scene_.domain.max[a]);
  }
  const bool any_periodic =
      std::find(grid_.periodic.begin(), grid_.periodic.end(), true) != grid_.periodic.end();
  // The gather reads the first 2D lanes of each node: one register per node in 2D double
  // (256-bit lanes, sim/lanes.hpp) instead of two.
  using Lanes = typename Grid<T, D>::GatherLanes;
  // At λ = 0 a scheme that does not read Σ w vⁿ (all but FLIP and ASFLIP) gathers ṽ alone, in
  // fewer registers where D lanes take fewer than 2D (3D double: one instead of two).
  // Only there: the same gather through the generic path cost 4 % in 2D float (native).
  constexpr bool narrow_exists = lane_parts<T>(D) < Lanes::parts;
  using NewLanes = std::conditional_t<narrow_exists, apiclab::Lanes<T, D>, Lanes>;
  const bool narrow = narrow_exists && S != Scheme::flip && S != Scheme::asflip && lambda == T(0);
  const auto* packed = grid_.accumulator.data();
  pack_velocities();
  // Lanes of ṽ × vⁿ: c_a = ṽ_{a+1} vⁿ_{a+2} − ṽ_{a+2} vⁿ_{a+1} in 3D, c_0 = ṽ_0 vⁿ_1 − ṽ_1 vⁿ_0 in
  // 2D.
  auto cross = [](const Lanes& n) {
    if constexpr (D == 3)
      return n.template front3<1, 2, 0>() * n.template front3<5, 3, 4>() -
             n.template front3<2, 0, 1>() * n.template front3<4, 5, 3>();
    else
      return n.template front3<0, 0, 0>() * n.template front3<3, 3, 3>() -
             n.template front3<1, 1, 1>() * n.template front3<2, 2, 2>();
  };
  const Vec3d gravity = scene_.gravity;
  const T k_inertia = inertia_scale();
  // With sums: the particles in fixed chunks, each summed in index order, the chunks' sums then
  // added in chunk order, so that the row does not depend on the thread count. 1024 a chunk:
  // each chunk's sum costs G2P a fixed overhead beyond its own work (docs/performance.md).
  constexpr std::ptrdiff_t chunk = 1024;
  const std::ptrdiff_t chunks = (n + chunk - 1) / chunk;
  if (sums) chunk_sums_.resize(std::size_t(chunks));
#pragma omp parallel for schedule(static) reduction(||     \
                                                    : bad) \
    reduction(max                                          \
              : max_move) if (parallel_worthwhile())
  for (std::ptrdiff_t c = 0; c < chunks; ++c) {
    ChunkTerms<T, D, chunk> terms;
    // APIC-like schemes with an isotropic D_p: C, read with x and v; the linear kernel's D_p and
    // PolyPIC's modes: each particle's terms.
    if constexpr (is_affine(S) && K::type != KernelType::linear) terms.isotropic_k = k_inertia;
    terms.extras = (is_affine(S) && K::type == KernelType::linear) ||
                   (S == Scheme::polypic && polypic_extra > 0);
    const std::ptrdiff_t end = std::min(n, (c + 1) * chunk);
    // The chunk's own largest move and finiteness, in registers: the reduction's variables live
    // on the stack, and max_move updated per particle was a chain through memory (perf annotate).
    T chunk_move = 0;
    bool chunk_bad = false;
    StencilBatch<T, D, K> batch;  // x^n's stencils, read before this loop moves the particles
    // 2D: the F and x updates of the batch's particles once its last is gathered, unless a
    // particle's own later work reads them (ASFLIP's move reads F^{n+1}, the row's extra terms
    // x^{n+1}) or an axis wraps.
    ParticleTail2d<T, StencilBatch<T, D, K>::L> tail;
    const bool tail_batched = D == 2 && S != Scheme::asflip && !terms.extras && !any_periodic;
    for (std::ptrdiff_t q = c * chunk; q < end; ++q) {
      const int lane = int((q - c * chunk) % batch.L);
      if (lane == 0)
        batch.compute(&p_.x[std::size_t(q)], int(std::min<std::ptrdiff_t>(batch.L, end - q)),
                      grid_);
      // The rare readers of the whole stencil (RPIC's D_p, XPIC's and PolyPIC's gathers) copy it;
      // the gather reads the batch in place.
      auto stencil = [&] {
        Stencil<T, D, K> st;
        batch.get(lane, st);
        return st;
      };
      // Gather row by row (see Stencil::for_each_row) on nodes packed as [ṽ (D), vⁿ (D), pad],
      // whole vectors at a time: lanes 0..D−1 give the sums over ṽ, lanes D..2D−1 over vⁿ.
      constexpr int W = K::width;
      T wr[W];
      for (int i = 0; i < W; ++i) wr[i] = batch.w[0][i][lane] * batch.r[0][i][lane];
      Lanes vsum{}, grad_cols[D] = {}, b_cols[D] = {}, twist{};
      // Σ w (ṽ × vⁿ) only for λ > 0, into the given sums (of lane type L).
      auto gather = [&](auto moving_nodes, auto& vsum, auto& grad_cols, auto& b_cols, auto& twist) {
        using L = std::remove_reference_t<decltype(vsum)>;
        if constexpr (paired_halves<L>(decltype(moving_nodes)::value)) {  // 2D float
          gather_2d_paired(batch, lane, wr, packed, vsum, grad_cols, b_cols);
          return;
        }
        // Each x-node's address once a particle, as in P2G (sim/p2g.hpp).
        const typename Grid<T, D>::NodeLanes* packed_x[W];
        for (int i = 0; i < W; ++i) packed_x[i] = packed + batch.off[0][i][lane];
        // Forced inline: GCC 12 keeps this row body out of line on x86-64-v3 in 3D double, and
        // the sums it adds to, taken by reference, then go through memory at every row.
        auto row_sums = [&](const typename StencilBatch<T, D, K>::Row& row)
            __attribute__((always_inline)) {
          L s0{}, s1{}, g0{}, t0{};
          for (int i = 0; i < W; ++i) {
            const L node = L::prefix_of(packed_x[i][row.off]);
            const T wx = batch.w[0][i][lane];
            s0 += wx * node;
            s1 += wr[i] * node;
            g0 += batch.dw[0][i][lane] * node;
            if constexpr (decltype(moving_nodes)::value) t0 += wx * cross(node);
          }
          vsum += row.w * s0;
          if constexpr (decltype(moving_nodes)::value) twist += row.w * t0;
          grad_cols[0] += row.w * g0;
          b_cols[0] += row.w * s1;
          for (int ax = 1; ax < D; ++ax) {
            grad_cols[ax] += row.dw[ax] * s0;
            b_cols[ax] += row.wr(ax) * s0;
          }
        };
        batch.for_each_row(lane, row_sums);
      };
      // u_i = λ vⁿ_i + (1 − λ) ṽ_i (eq 30): ū = Σ w u, ∇u = Σ u ∇wᵀ.
      Vec<T, D> vpic, vold_p, ubar;
      Mat<T, D> Bsum, gradu, gradv;
      // In 3D at λ = 0, ∇u's columns as the gather's lanes for the deformation update (∇u as a
      // matrix is then not formed); otherwise from ∇u below.
      using GradColumn = std::conditional_t<D == 3, apiclab::Lanes<T, 3>, Vec<T, D>>;
      GradColumn gradu_lanes[D] = {};  // zeroed: GCC cannot tie the λ = 0 branches together
      if constexpr (narrow_exists) {
        if (narrow) {  // λ = 0: u = ṽ, and Σ w vⁿ is not read
          NewLanes nsum{}, ngrad[D] = {}, nb[D] = {}, nturn{};
          gather(std::false_type{}, nsum, ngrad, nb, nturn);
          for (int a = 0; a < D; ++a) {
            vpic[a] = nsum[a];
            for (int c = 0; c < D; ++c) {
              gradv(a, c) = ngrad[c][a];
              Bsum(a, c) = nb[c][a];
            }
          }
          vold_p = ubar = vpic;
          if constexpr (D == 3)
            for (int c = 0; c < D; ++c) gradu_lanes[c] = GradColumn::prefix_of(ngrad[c]);
          else
            gradu = gradv;
        }
      }
      if (!narrow) {
        if (lambda != T(0))
          gather(std::true_type{}, vsum, grad_cols, b_cols, twist);
        else
          gather(std::false_type{}, vsum, grad_cols, b_cols, twist);
        for (int a = 0; a < D; ++a) {
          vpic[a] = vsum[a];
          vold_p[a] = vsum[D + a];
          for (int c = 0; c < D; ++c) {
            gradv(a, c) = grad_cols[c][a];
            Bsum(a, c) = b_cols[c][a];
          }
        }
        // λ = 0 on its own branch: u = ṽ, and the vⁿ lanes of ∇u (the upper half of a 3D float
        // group) are neither extracted nor blended.
        if (lambda == T(0)) {
          ubar = vpic;
          if constexpr (D == 3)
            for (int c = 0; c < D; ++c) gradu_lanes[c] = GradColumn::prefix_of(grad_cols[c]);
          else
            gradu = gradv;
        } else {
          for (int a = 0; a < D; ++a) {
            ubar[a] = lambda * vsum[D + a] + (T(1) - lambda) * vsum[a];
            for (int c = 0; c < D; ++c)
              gradu(a, c) = lambda * grad_cols[c][D + a] + (T(1) - lambda) * grad_cols[c][a];
          }
        }
      }
      // Velocity and affine matrix per scheme (sim/transfer_schemes.hpp).
      GatheredVelocity<T, D> gathered{vpic, vold_p, Mat<T, D>::Zero()};
      if constexpr (is_affine(S)) {
        if (lagged || S == Scheme::tpic) {
          // Sec 5.9: C = Σ ṽ_i ∇w_ipᵀ; TPIC (Nakamura et al. 2023) takes this velocity gradient
          // for every kernel: P2G's v_p + ∇v_p (x_i − x_p) is the first-order Taylor expansion.
          gathered.apic_C = gradv;
        } else {
          Mat<T, D> B = Bsum;
          if (lambda != T(0)) {
            // S − Sᵀ with S = Σ w ṽ uᵀ is λ Σ w (ṽ vⁿᵀ − vⁿ ṽᵀ), whose entries are Σ w (ṽ × vⁿ).
            Mat<T, D> skew;
            if constexpr (D == 3)
              skew << T(0), twist[2], -twist[1], -twist[2], T(0), twist[0], twist[1], -twist[0],
                  T(0);
            else
              skew << T(0), twist[0], -twist[0], T(0);
            B += T(0.5) * dt * (lambda * skew - vpic * ubar.transpose() + ubar * vpic.transpose());
          }
          if (bform_multilinear) {
            // Sec 5.9's B form: B^{n+1} is inverted with D_p at the start of the next step, at
            // x_p^{n+1}, where f(1 − f) Δx² per axis vanishes as a particle nears a grid line.
            Vec<T, D> x_next = p_.x[q] + dt * ubar;
            for (int a = 0; a < D; ++a) x_next[a] = std::min(std::max(x_next[a], lo[a]), hi[a]);
            Stencil<T, D, K> next;
            next.compute(x_next, grid_);
            const Mat<T, D> Dp = next.inertia();  // diagonal
            for (int c = 0; c < D; ++c) B.col(c) /= Dp(c, c);
            gathered.apic_C = B;
          } else {
            gathered.apic_C = B * inv_k;  // C = B D⁻¹ with D = k Δx² I
          }
        }
      }
      if constexpr (S == Scheme::xpic) {
        if (xpic_gather) {
          Vec<T, D> shift = Vec<T, D>::Zero();
          const Stencil<T, D, K> st = stencil();
          st.for_each_row([&](const typename Stencil<T, D, K>::Row& row) {
            Vec<T, D> s = Vec<T, D>::Zero();
            for (int i = 0; i < W; ++i) s += st.w[0][i] * xpic_shift[st.off[0][i] + row.off];
            shift += row.w * s;
          });
          gathered.xpic_shift = shift;
        }
      }
      // ASFLIP's position correction reads the FLIP difference before v_p is overwritten.
      Vec<T, D> flip_difference;
      if constexpr (S == Scheme::asflip) flip_difference = p_.v[q] - vold_p;
      update_particle_velocity<S>(
          gathered, alpha, multilinear, [&] { return Mat<T, D>(stencil().inertia()); }, p_.v[q],
          p_.C[q]);
      if constexpr (S == Scheme::polypic) {  // Fu et al. 2017: the kept modes, by projection
        polypic::keep_linear_modes<T, D>(p_.C[q], polypic_kept);
        if constexpr (K::type == KernelType::quadratic) {
          if (polypic_extra > 0) {  // the row form of polypic::gather_modes, on the packed ṽ
            auto node = [&](std::size_t i) { return Lanes::prefix_of(packed[i]); };
            const Stencil<T, D, K> st = stencil();
            if (polypic_g)
              polypic::gather_modes_rows<T, D, 3, Lanes>(st, grid_.inv_dx, node, polypic_extra,
                                                         p_.modes, std::size_t(q));
            else
              polypic::gather_modes_rows<T, D, 2, Lanes>(st, grid_.inv_dx, node, polypic_extra,
                                                         p_.modes, std::size_t(q));
          }
        }
      }
      // MLS-MPM (Hu et al. 2018): the new C is the velocity gradient, F^{n+1} = (I + Δt C) F.
      if constexpr (S == Scheme::mls) gradu = p_.C[q];
      if (tail_batched) {  // F and x a batch at a time (sim/particle_tail.hpp)
        if constexpr (D == 2) {
          tail.set_scaled(lane, gradu, ubar, dt);
          if (lane == batch.L - 1 || q == end - 1) {
            const std::ptrdiff_t first = q - lane;
            if (!tail.apply(lane + 1, &p_.F[first], &p_.x[first], &p_.v[first], lo, hi, chunk_move))
              chunk_bad = true;
          }
        }
      } else {
        if constexpr (D == 3) {                    // sim/deformation_update.hpp
          if (S == Scheme::mls || lambda != T(0))  // ∇u as a matrix (λ = 0 left it in lanes)
            for (int c = 0; c < D; ++c)
              gradu_lanes[c] = GradColumn::of(gradu(0, c), gradu(1, c), gradu(2, c));
          for (int c = 0; c < D; ++c) gradu_lanes[c] = dt * gradu_lanes[c];
          update_deformation_3d(p_.F[q].data(), gradu_lanes);
        } else {
          // The loop here, not shared with deformation_update.hpp's scalar one: inlined from a
          // function, GCC vectorised it into shuffles and a 256-bit store, slower on x86-64-v3.
          const Mat<T, D> F0 = p_.F[q];
          // Δt ∇u before the stores: Δt is the parallel region's shared variable, which a store
          // to F may alias, so reading it inside the loop reloaded it at every entry (perf
          // annotate).
          const Mat<T, D> dt_gradu = dt * gradu;
          for (int b = 0; b < D; ++b)
            for (int a = 0; a < D; ++a) {
              T s = F0(a, b);
              for (int k = 0; k < D; ++k) s += dt_gradu(a, k) * F0(k, b);
              p_.F[q](a, b) = s;
            }
        }
        // Particle update: positions on the moved grid (eq 39), F by eq 40 (above).
        Vec<T, D> move = dt * ubar;
        // ASFLIP (Fei et al. 2021): separating particles also move by β α (v_p^n − v_old);
        // a particle whose volume shrinks this step (ln J^{n+1} < −10⁻³, the threshold of the
        // authors' pyasflip demo) keeps the grid's motion (β_min = 0).
        if constexpr (S == Scheme::asflip)
          if (beta != T(0) && std::log(std::max(p_.F[q].determinant(), T(1e-15))) >= T(-1e-3))
            move += (dt * beta * alpha) * flip_difference;
        Vec<T, D> x = p_.x[q] + move;
        chunk_move = std::max(chunk_move, move.cwiseAbs().maxCoeff());
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
        if (!std::isfinite(x.sum() + p_.v[q].sum())) chunk_bad = true;
      }
      // The row's terms at the new state, as particle_sums() adds them: x, v and C are read
      // from the particle arrays after the chunk; the extra terms are set here.
      if (sums && terms.extras) {
        const int j = int(q - c * chunk);
        const T m = p_.mass[q];
        T modes_kinetic = 0;  // PolyPIC's higher modes (sim/transfer_polypic.hpp)
        if constexpr (S == Scheme::polypic) {
          if (polypic_extra > 0) {
            Stencil<T, D, QuadraticKernel> at_x;
            at_x.compute(p_.x[q], grid_);
            modes_kinetic =
                T(0.5) * m *
                polypic::modes_energy_density<T, D>(at_x, grid_.inv_dx, p_.modes, std::size_t(q));
          }
        }
        if constexpr (K::type == KernelType::linear) {
          Stencil<T, D, LinearKernel> at_x;
          at_x.compute(p_.x[q], grid_);
          terms.set_affine(j, m, p_.C[q], Mat<T, D>(at_x.inertia()), modes_kinetic);
        } else {  // PolyPIC's higher modes; its C is read with x and v
          terms.extra_kinetic[j] = modes_kinetic;
          for (int a = 0; a < terms.moments; ++a) terms.affine_moment[a][j] = T(0);
        }
      }
    }
    max_move = std::max(max_move, double(chunk_move));
    bad = bad || chunk_bad;
    if (sums) {
      const std::size_t first = std::size_t(c * chunk);
      chunk_sums_[std::size_t(c)] = terms.sum(&p_.mass[first], &p_.x[first], &p_.v[first],
                                              p_.C.data() + first, int(end - c * chunk), gravity);
    }
  }
  if (sums) {
    *sums = ParticleSums{};
    for (const ParticleSums& own : chunk_sums_) sums->add(own);
  }
  non_finite_ = non_finite_ || bad;
  blocks_.add_drift(std::isfinite(max_move) ? max_move * double(grid_.inv_dx) : 1e30);
}

template <class T, int D>
void MpmSimulation<T, D>::grid_to_particles(T dt, ParticleSums* sums) {
  with_kernel(scene_.solver.kernel, [&](auto kernel) {
    using K = decltype(kernel);
    switch (scene_.solver.scheme) {
      case Scheme::pic:
        g2p_impl<K, Scheme::pic>(dt, sums);
        break;
      case Scheme::flip:
        g2p_impl<K, Scheme::flip>(dt, sums);
        break;
      case Scheme::apic:
        g2p_impl<K, Scheme::apic>(dt, sums);
        break;
      case Scheme::rpic:
        g2p_impl<K, Scheme::rpic>(dt, sums);
        break;
      case Scheme::mls:
        g2p_impl<K, Scheme::mls>(dt, sums);
        break;
      case Scheme::asflip:
        g2p_impl<K, Scheme::asflip>(dt, sums);
        break;
      case Scheme::xpic:
        xpic_grid_passes<K>();
        g2p_impl<K, Scheme::xpic>(dt, sums);
        break;
      case Scheme::tpic:
        g2p_impl<K, Scheme::tpic>(dt, sums);
        break;
      case Scheme::polypic:
        g2p_impl<K, Scheme::polypic>(dt, sums);
        break;
    }
  });
}

}  // namespace apiclab
