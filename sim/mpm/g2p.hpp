// Grid to particles (eqs 37-40) in the reference step's G2P blocks
// (sim/reference/reference_step.hpp): gather → the gathered sums → the particle update (velocity,
// affine matrix) → move the particle (F, x) → the diagnostics terms; g2p_impl runs them over fixed
// chunks of particles.
//
// With u_i = λ v_i + (1 − λ) ṽ_i the moved node is x̃_i = x_i + Δt u_i (eq 30), so
// x_p^{n+1} = Σ w x̃_i = x_p + Δt Σ w u_i (eq 39) and F^{n+1} = (I + Δt Σ u_i ∇wᵀ) F (eq 40).
// APIC's eq 38 expands to B = Σ w ṽ rᵀ + Δt/2 (S − Sᵀ − v_p ūᵀ + ū v_pᵀ) with S = Σ w ṽ u_iᵀ and
// ū = Σ w u_i, which is exact and needs one pass over the stencil.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "sim/mpm/kernel_dispatch.hpp"
#include "sim/mpm/mpm.hpp"
#include "sim/mpm/schemes/particle_update.hpp"
#include "sim/mpm/schemes/polypic_modes.hpp"
#include "sim/mpm/simd/deformation_update.hpp"
#include "sim/mpm/simd/stencil_batch.hpp"

namespace apiclab {

// ∇u as the move reads it: in 2D a matrix, in 3D its columns as lanes, as the gather leaves them
// (sim/mpm/simd/deformation_update.hpp).
template <class T, int D>
using VelocityGradient = std::conditional_t<D == 3, std::array<Lanes<T, 3>, 3>, Mat<T, D>>;

// What the gather leaves at one particle: the reference step's sums over for_each_node.
template <class T, int D>
struct GatheredSums {
  Vec<T, D> pic, old, ubar;       // Σ w ṽ (eq 37), Σ w vⁿ (eq 3), ū = Σ w u (eq 39)
  Mat<T, D> grad_v, B;            // Σ ṽ ∇wᵀ, Σ w ṽ rᵀ
  VelocityGradient<T, D> grad_u;  // Σ u ∇wᵀ (eq 40)
  Lanes<T, 2 * D> twist;          // Σ w (ṽ × vⁿ) in its first lanes where λ > 0, else 0
};

// One G2P pass of scheme S with kernel K: what it reads of the scene, fixed for the step.
template <class T, int D, class K, Scheme S>
struct G2pPass {
  using Sch = scheme_t<S>;  // the scheme's file (sim/mpm/schemes/)
  static constexpr int W = K::width;
  static constexpr std::ptrdiff_t chunk = 1024;  // particles a row sum (g2p_impl)
  using Batch = StencilBatch<T, D, K>;
  using Node = typename Grid<T, D>::NodeLanes;
  // The gather reads the first 2D lanes of each node, [ṽ (D), vⁿ (D)]: one register per node in
  // 2D double (256-bit lanes, sim/mpm/simd/lanes.hpp) instead of two.
  using GatherLanes = typename Grid<T, D>::GatherLanes;
  // At λ = 0 a scheme that does not read Σ w vⁿ (Sch::reads_old) gathers ṽ alone, in
  // fewer registers where D lanes take fewer than 2D (3D double: one instead of two).
  // Only there: elsewhere the generic gather is the faster (docs/performance.md).
  static constexpr bool narrow_exists = lane_parts<T>(D) < GatherLanes::parts;
  using NarrowLanes = std::conditional_t<narrow_exists, Lanes<T, D>, GatherLanes>;
  static constexpr bool multilinear = K::type == KernelType::linear;

  Particles<T, D>& p;
  const Grid<T, D>& grid;
  const Node* packed;           // [ṽ (D), vⁿ (D), pad] per node (pack_velocities)
  const Vec<T, D>* xpic_shift;  // XPIC(m > 1)'s grid field e (sim/mpm/schemes/xpic_passes.hpp)
  T dt, lambda, alpha, beta;
  T inv_k;           // 1 / (k Δx²), D_p = k Δx² I (quadratic, cubic)
  Vec<T, D> lo, hi;  // the domain
  bool lagged;       // Sec 5.9: the multilinear kernel's C = Σ ṽ ∇wᵀ (else its B form)
  bool narrow;       // λ = 0 and Σ w vⁿ not read: the narrow gather
  bool eq38;         // the scheme reads eq 38's B
  bool xpic_gather;
  int polypic_kept, polypic_extra;
  bool polypic_g;
  bool extras;  // the row's terms per particle (the multilinear D_p, PolyPIC's modes)
  T k_inertia;  // k Δx²
  Vec3d gravity;

  G2pPass(const SceneDesc& scene, const Grid<T, D>& g, Particles<T, D>& particles,
          const Vec<T, D>* xpic, T k, T step)
      : p(particles), grid(g), packed(g.node_lanes.data()), xpic_shift(xpic), dt(step) {
    const SolverDesc& s = scene.solver;
    lambda = T(s.integrator_lambda());
    alpha = T(s.flip_alpha);
    beta = T(s.asflip_beta);
    inv_k = multilinear ? T(0) : T(1) / k;
    k_inertia = k;
    gravity = scene.gravity;
    for (int a = 0; a < D; ++a) {
      lo[a] = T(scene.domain.min[a]);
      hi[a] = T(scene.domain.max[a]);
    }
    lagged = multilinear && s.apic_linear_form == ApicLinearForm::lagged;
    narrow = narrow_exists && !Sch::reads_old && lambda == T(0);
    eq38 = Sch::affine && !lagged && !Sch::c_from_gradient;
    xpic_gather = Sch::grid_field && s.xpic_order > 1;
    polypic_kept = polypic::kept_modes(s.polypic_modes, D);
    polypic_extra = int(p.modes.size());
    polypic_g = polypic::keeps_g_modes(1 + D + polypic_extra, D);
    extras = (Sch::affine && multilinear) || (Sch::higher_modes && polypic_extra > 0);
  }

  // Particle `lane`'s stencil as Stencil::compute makes it, for the rare readers of the whole
  // stencil (RPIC's D_p, XPIC's and PolyPIC's gathers); the gather reads the batch in place.
  static Stencil<T, D, K> stencil(const Batch& batch, int lane) {
    Stencil<T, D, K> st;
    batch.get(lane, st);
    return st;
  }

  // Lanes of ṽ × vⁿ: c_a = ṽ_{a+1} vⁿ_{a+2} − ṽ_{a+2} vⁿ_{a+1} in 3D, c_0 = ṽ_0 vⁿ_1 − ṽ_1 vⁿ_0 in
  // 2D.
  static GatherLanes cross(const GatherLanes& n) {
    if constexpr (D == 3)
      return n.template front3<1, 2, 0>() * n.template front3<5, 3, 4>() -
             n.template front3<2, 0, 1>() * n.template front3<4, 5, 3>();
    else
      return n.template front3<0, 0, 0>() * n.template front3<3, 3, 3>() -
             n.template front3<1, 1, 1>() * n.template front3<2, 2, 2>();
  }

  // Gather: row by row (Stencil::for_each_row), whole node vectors at a time, into sums of lane
  // type L: Σ w n, Σ ∂_c w n, Σ w r_c n over the node lanes n, and with moving nodes (λ > 0)
  // Σ w (ṽ × vⁿ).
  template <bool moving, class L>
  __attribute__((always_inline)) void gather(const Batch& batch, int lane, L& vsum,
                                             L (&grad_cols)[D], L (&b_cols)[D], L& twist) const {
    T wr[W];
    for (int i = 0; i < W; ++i) wr[i] = batch.w[0][i][lane] * batch.r[0][i][lane];
    // Each x-node's address once a particle, as in P2G (sim/mpm/p2g.hpp).
    const Node* packed_x[W];
    for (int i = 0; i < W; ++i) packed_x[i] = packed + batch.off[0][i][lane];
    // Forced inline: GCC 12 keeps this row body out of line on x86-64-v3 in 3D double, and
    // the sums it adds to, taken by reference, then go through memory at every row.
    auto row_sums = [&](const typename Batch::Row& row) __attribute__((always_inline)) {
      L s0{}, s1{}, g0{}, t0{};
      for (int i = 0; i < W; ++i) {
        const L node = L::prefix_of(packed_x[i][row.off]);
        const T wx = batch.w[0][i][lane];
        s0 += wx * node;
        s1 += wr[i] * node;
        g0 += batch.dw[0][i][lane] * node;
        if constexpr (moving) t0 += wx * cross(node);
      }
      vsum += row.w * s0;
      if constexpr (moving) twist += row.w * t0;
      grad_cols[0] += row.w * g0;
      b_cols[0] += row.w * s1;
      for (int ax = 1; ax < D; ++ax) {
        grad_cols[ax] += row.dw[ax] * s0;
        b_cols[ax] += row.wr(ax) * s0;
      }
    };
    batch.for_each_row(lane, row_sums);
  }

  // The gathered sums at λ = 0 from ṽ alone: u = ṽ, and Σ w vⁿ is not read.
  __attribute__((always_inline)) GatheredSums<T, D> narrow_sums(const Batch& batch,
                                                                int lane) const {
    NarrowLanes vsum{}, grad_cols[D] = {}, b_cols[D] = {}, unused{};
    gather<false>(batch, lane, vsum, grad_cols, b_cols, unused);
    GatheredSums<T, D> g;
    g.twist = {};
    for (int a = 0; a < D; ++a) {
      g.pic[a] = vsum[a];
      for (int c = 0; c < D; ++c) {
        g.grad_v(a, c) = grad_cols[c][a];
        g.B(a, c) = b_cols[c][a];
      }
    }
    g.old = g.ubar = g.pic;
    if constexpr (D == 3)
      for (int c = 0; c < D; ++c) g.grad_u[c] = Lanes<T, 3>::prefix_of(grad_cols[c]);
    else
      g.grad_u = g.grad_v;
    return g;
  }

  // The gathered sums from [ṽ, vⁿ]: u_i = λ vⁿ_i + (1 − λ) ṽ_i (eq 30), ū = Σ w u and
  // ∇u = Σ u ∇wᵀ, and where λ > 0 Σ w (ṽ × vⁿ) for eq 38.
  __attribute__((always_inline)) GatheredSums<T, D> wide_sums(const Batch& batch, int lane) const {
    GatheredSums<T, D> g;
    GatherLanes vsum{}, grad_cols[D] = {}, b_cols[D] = {};
    g.twist = {};
    if (lambda != T(0))
      gather<true>(batch, lane, vsum, grad_cols, b_cols, g.twist);
    else
      gather<false>(batch, lane, vsum, grad_cols, b_cols, g.twist);
    for (int a = 0; a < D; ++a) {
      g.pic[a] = vsum[a];
      g.old[a] = vsum[D + a];
      for (int c = 0; c < D; ++c) {
        g.grad_v(a, c) = grad_cols[c][a];
        g.B(a, c) = b_cols[c][a];
      }
    }
    // λ = 0 on its own branch: u = ṽ, and the vⁿ lanes of ∇u (the upper half of a 3D float
    // group) are neither extracted nor blended.
    if (lambda == T(0)) {
      g.ubar = g.pic;
      if constexpr (D == 3)
        for (int c = 0; c < D; ++c) g.grad_u[c] = Lanes<T, 3>::prefix_of(grad_cols[c]);
      else
        g.grad_u = g.grad_v;
      return g;
    }
    Mat<T, D> grad_u;
    for (int a = 0; a < D; ++a) {
      g.ubar[a] = lambda * vsum[D + a] + (T(1) - lambda) * vsum[a];
      for (int c = 0; c < D; ++c)
        grad_u(a, c) = lambda * grad_cols[c][D + a] + (T(1) - lambda) * grad_cols[c][a];
    }
    if constexpr (D == 3)
      for (int c = 0; c < D; ++c)
        g.grad_u[c] = Lanes<T, 3>::of(grad_u(0, c), grad_u(1, c), grad_u(2, c));
    else
      g.grad_u = grad_u;
    return g;
  }

  __attribute__((always_inline)) GatheredSums<T, D> gathered_sums(const Batch& batch,
                                                                  int lane) const {
    if constexpr (narrow_exists)
      if (narrow) return narrow_sums(batch, lane);
    return wide_sums(batch, lane);
  }

  // APIC's C (eq 26): B D⁻¹ with D = k Δx² I; Sec 5.9's lagged C = Σ ṽ ∇wᵀ, which TPIC (Nakamura
  // et al. 2023) takes for every kernel (P2G's v_p + ∇v_p (x_i − x_p) is the first-order Taylor
  // expansion); or Sec 5.9's B form, B^{n+1} inverted with the multilinear D_p at x_p^{n+1},
  // where f(1 − f) Δx² per axis vanishes as a particle nears a grid line (unstable).
  __attribute__((always_inline)) Mat<T, D> apic_C(std::ptrdiff_t q,
                                                  const GatheredSums<T, D>& g) const {
    if (!eq38) return g.grad_v;
    Mat<T, D> B = g.B;
    if (lambda != T(0)) {
      // S − Sᵀ with S = Σ w ṽ uᵀ is λ Σ w (ṽ vⁿᵀ − vⁿ ṽᵀ), whose entries are Σ w (ṽ × vⁿ).
      const Lanes<T, 2 * D>& t = g.twist;
      Mat<T, D> skew;
      if constexpr (D == 3)
        skew << T(0), t[2], -t[1], -t[2], T(0), t[0], t[1], -t[0], T(0);
      else
        skew << T(0), t[0], -t[0], T(0);
      B += T(0.5) * dt * (lambda * skew - g.pic * g.ubar.transpose() + g.ubar * g.pic.transpose());
    }
    if (!multilinear) return B * inv_k;  // C = B D⁻¹ with D = k Δx² I
    Vec<T, D> x_next = p.x[q] + dt * g.ubar;
    for (int a = 0; a < D; ++a) x_next[a] = std::min(std::max(x_next[a], lo[a]), hi[a]);
    Stencil<T, D, K> next;
    next.compute(x_next, grid);
    const Mat<T, D> Dp = next.inertia();  // diagonal
    for (int c = 0; c < D; ++c) B.col(c) /= Dp(c, c);
    return B;
  }

  // XPIC(m > 1): Σ w e_i of its grid field (sim/mpm/schemes/xpic_passes.hpp).
  __attribute__((always_inline)) Vec<T, D> xpic_sum(const Batch& batch, int lane) const {
    Vec<T, D> shift = Vec<T, D>::Zero();
    const Stencil<T, D, K> st = stencil(batch, lane);
    st.for_each_row([&](const typename Stencil<T, D, K>::Row& row) {
      Vec<T, D> s = Vec<T, D>::Zero();
      for (int i = 0; i < W; ++i) s += st.w[0][i] * xpic_shift[st.off[0][i] + row.off];
      shift += row.w * s;
    });
    return shift;
  }

  // PolyPIC (Fu et al. 2017): the kept linear modes, by projection, and the higher modes by
  // polypic::gather_modes' row form on the packed ṽ.
  __attribute__((always_inline)) void polypic_modes(std::ptrdiff_t q, const Batch& batch,
                                                    int lane) const {
    polypic::keep_linear_modes<T, D>(p.C[q], polypic_kept);
    if constexpr (K::type == KernelType::quadratic) {
      if (polypic_extra == 0) return;
      auto node = [&](std::size_t i) { return GatherLanes::prefix_of(packed[i]); };
      const Stencil<T, D, K> st = stencil(batch, lane);
      if (polypic_g)
        polypic::gather_modes_rows<T, D, 3, GatherLanes>(st, grid.inv_dx, node, polypic_extra,
                                                         p.modes, std::size_t(q));
      else
        polypic::gather_modes_rows<T, D, 2, GatherLanes>(st, grid.inv_dx, node, polypic_extra,
                                                         p.modes, std::size_t(q));
    }
  }

  // The particle update: v_p and C_p by the scheme's own file (Sch::update). MLS-MPM (Hu et al.
  // 2018) moves F by its new C: ∇u is replaced.
  __attribute__((always_inline)) void update_particle(std::ptrdiff_t q, const Batch& batch,
                                                      int lane, GatheredSums<T, D>& g) const {
    GatheredVelocity<T, D> gathered{g.pic, g.old, Mat<T, D>::Zero()};
    if constexpr (Sch::affine) gathered.apic_C = apic_C(q, g);
    if constexpr (Sch::grid_field)
      if (xpic_gather) gathered.xpic_shift = xpic_sum(batch, lane);
    Sch::update(
        gathered, alpha, multilinear, [&] { return Mat<T, D>(stencil(batch, lane).inertia()); },
        p.v[q], p.C[q]);
    if constexpr (Sch::higher_modes) polypic_modes(q, batch, lane);
    if constexpr (Sch::moves_f_by_c) {
      const Mat<T, D>& C = p.C[q];
      if constexpr (D == 3)
        for (int c = 0; c < D; ++c) g.grad_u[c] = Lanes<T, 3>::of(C(0, c), C(1, c), C(2, c));
      else
        g.grad_u = C;
    }
  }

  // F ← (I + Δt ∇u) F (eq 40).
  __attribute__((always_inline)) void update_deformation(Mat<T, D>& F,
                                                         VelocityGradient<T, D> grad_u) const {
    if constexpr (D == 3) {  // from ∇u's columns in lanes (sim/mpm/simd/deformation_update.hpp)
      for (int c = 0; c < D; ++c) grad_u[c] = dt * grad_u[c];
      update_deformation_3d(F.data(), grad_u.data());
    } else {
      // The loop here, not shared with deformation_update.hpp's scalar one: inlined from a
      // function, GCC vectorised it into shuffles and a 256-bit store, slower on x86-64-v3.
      const Mat<T, D> F0 = F;
      // Δt ∇u before the stores, which may alias Δt: read inside the loop, it was reloaded at
      // every entry (perf annotate).
      const Mat<T, D> dt_grad_u = dt * grad_u;
      for (int b = 0; b < D; ++b)
        for (int a = 0; a < D; ++a) {
          T s = F0(a, b);
          for (int k = 0; k < D; ++k) s += dt_grad_u(a, k) * F0(k, b);
          F(a, b) = s;
        }
    }
  }

  // Move the particle: F by eq 40, x on the moved grid (eq 39), a wall's clamp or a periodic
  // axis's wrap. v_n is v_p before the update (ASFLIP's correction). Returns whether x and v are
  // finite; raises `largest` to the move's largest entry.
  __attribute__((always_inline)) bool move_particle(std::ptrdiff_t q, const GatheredSums<T, D>& g,
                                                    const Vec<T, D>& v_n, T& largest) const {
    update_deformation(p.F[q], g.grad_u);
    Vec<T, D> move = dt * g.ubar;
    // ASFLIP (Fei et al. 2021): separating particles also move by β α (v_p^n − v_old).
    if constexpr (Sch::corrects_move) Sch::correct_move(move, p.F[q], v_n, g.old, dt, alpha, beta);
    Vec<T, D> x = p.x[q] + move;
    largest = std::max(largest, move.cwiseAbs().maxCoeff());
    for (int a = 0; a < D; ++a) {
      if (grid.periodic[a]) {
        const T L = hi[a] - lo[a];
        if (x[a] < lo[a] || x[a] >= hi[a]) x[a] -= L * std::floor((x[a] - lo[a]) / L);
        if (x[a] >= hi[a]) x[a] = lo[a];  // round-off of the line above
      } else {
        x[a] = std::min(std::max(x[a], lo[a]), hi[a]);  // walls: keep the stencil on the grid
      }
    }
    p.x[q] = x;
    return std::isfinite(x.sum() + p.v[q].sum());
  }

  // The diagnostics terms that ChunkTerms::sum cannot form from x, v and C
  // (sim/mpm/particle_sums.hpp): with the multilinear kernel ½ m tr(C D_p Cᵀ) and m (Bᵀ : ε) at
  // x^{n+1}, and PolyPIC's higher modes' kinetic energy (sim/mpm/schemes/polypic_modes.hpp);
  // particle q is the chunk's j-th.
  __attribute__((always_inline)) void diagnostics_terms(ChunkTerms<T, D, chunk>& terms, int j,
                                                        std::ptrdiff_t q) const {
    const T m = p.mass[q];
    T modes_kinetic = 0;
    if constexpr (Sch::higher_modes) {
      if (polypic_extra > 0) {
        Stencil<T, D, QuadraticKernel> at_x;
        at_x.compute(p.x[q], grid);
        modes_kinetic =
            T(0.5) * m *
            polypic::modes_energy_density<T, D>(at_x, grid.inv_dx, p.modes, std::size_t(q));
      }
    }
    if constexpr (multilinear) {
      Stencil<T, D, LinearKernel> at_x;
      at_x.compute(p.x[q], grid);
      terms.set_affine(j, m, p.C[q], Mat<T, D>(at_x.inertia()), modes_kinetic);
    } else {  // PolyPIC's higher modes; its C is read with x and v
      terms.extra_kinetic[j] = modes_kinetic;
      for (int a = 0; a < terms.moments; ++a) terms.affine_moment[a][j] = T(0);
    }
  }

  // The largest move of a chunk and whether any particle left it non-finite.
  struct ChunkMoves {
    T largest = 0;
    bool bad = false;
  };

  // Particles [first, end) of one chunk, each through gather → sums → update → move (→ its
  // diagnostics terms); with sums, the chunk's share of the row into *sums.
  __attribute__((always_inline)) ChunkMoves run_chunk(std::ptrdiff_t first, std::ptrdiff_t end,
                                                      ParticleSums* sums) const {
    ChunkTerms<T, D, chunk> terms;
    // APIC-like schemes with an isotropic D_p: C, read with x and v.
    if constexpr (Sch::affine && !multilinear) terms.isotropic_k = k_inertia;
    terms.extras = extras;
    // The chunk's own largest move and finiteness, in registers: the reduction's variables live
    // on the stack, and max_move updated per particle was a chain through memory (perf annotate).
    ChunkMoves moves;
    Batch batch;  // x^n's stencils, read before this loop moves the particles
    for (std::ptrdiff_t q = first; q < end; ++q) {
      const int lane = int((q - first) % Batch::L);
      if (lane == 0)
        batch.compute(&p.x[std::size_t(q)], int(std::min<std::ptrdiff_t>(Batch::L, end - q)), grid);
      GatheredSums<T, D> g = gathered_sums(batch, lane);
      const Vec<T, D> v_n = p.v[q];
      update_particle(q, batch, lane, g);
      if (!move_particle(q, g, v_n, moves.largest)) moves.bad = true;
      if (sums && terms.extras) diagnostics_terms(terms, int(q - first), q);
    }
    if (sums)
      *sums = terms.sum(&p.mass[std::size_t(first)], &p.x[std::size_t(first)],
                        &p.v[std::size_t(first)], p.C.data() + first, int(end - first), gravity);
    return moves;
  }
};

template <class T, int D>
template <class K, Scheme S>
void MpmSimulation<T, D>::g2p_impl(T dt, ParticleSums* sums, bool ledger) {
  pack_velocities();
  const G2pPass<T, D, K, S> pass(scene_, grid_, p_, xpic_shift_.data(), inertia_scale(), dt);
  // With sums: the particles in fixed chunks, each summed in index order, the chunks' sums then
  // added in chunk order, so that the row does not depend on the thread count. 1024 a chunk:
  // each chunk's sum costs G2P a fixed overhead beyond its own work (docs/performance.md).
  constexpr std::ptrdiff_t chunk = G2pPass<T, D, K, S>::chunk;
  const std::ptrdiff_t n = std::ptrdiff_t(p_.size());
  const std::ptrdiff_t chunks = (n + chunk - 1) / chunk;
  if (sums) chunk_sums_.resize(std::size_t(chunks));
  // The ledger's particle sums (sim/mpm/mpm_ledger.hpp), once per precision and dimension: the
  // scheme and kernel as runtime flags.
  static_assert(chunk == StepLedger<T, D>::chunk);
  const LedgerTerms ledger_terms{scheme_t<S>::affine, G2pPass<T, D, K, S>::multilinear,
                                 scheme_t<S>::higher_modes && pass.polypic_extra > 0};
  if (ledger) ledger_start(ledger_terms);
  bool bad = false;
  double max_move = 0;
#pragma omp parallel for schedule(static) reduction(||     \
                                                    : bad) \
    reduction(max                                          \
              : max_move) if (parallel_worthwhile())
  for (std::ptrdiff_t c = 0; c < chunks; ++c) {
    // A copy of the pass in the chunk's own frame, which no store to the particles may alias.
    const G2pPass<T, D, K, S> own = pass;
    const auto moves = own.run_chunk(c * chunk, std::min(n, (c + 1) * chunk),
                                     sums ? &chunk_sums_[std::size_t(c)] : nullptr);
    max_move = std::max(max_move, double(moves.largest));
    bad = bad || moves.bad;
  }
  if (sums) {
    *sums = ParticleSums{};
    for (const ParticleSums& own : chunk_sums_) sums->add(own);
  }
  if (ledger) ledger_updated(ledger_terms);
  non_finite_ = non_finite_ || bad;
  blocks_.add_drift(std::isfinite(max_move) ? max_move * double(grid_.inv_dx) : 1e30);
}

template <class T, int D>
void MpmSimulation<T, D>::grid_to_particles(T dt, ParticleSums* sums, bool ledger) {
  with_kernel(scene_.solver.kernel, [&](auto kernel) {
    with_scheme(scene_.solver.scheme, [&](auto scheme) {
      using K = decltype(kernel);
      constexpr Scheme S = decltype(scheme)::value;
      if constexpr (scheme_t<S>::grid_field) xpic_grid_passes<K>();
      g2p_impl<K, S>(dt, sums, ledger);
    });
  });
}

}  // namespace apiclab
