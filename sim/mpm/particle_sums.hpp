// The diagnostics row's sums over particles: kinetic energy with the affine term, the
// gravitational potential, linear and angular momentum (docs/architecture.md, Diagnostics CSV).
// measure() sums them in a pass of its own (the readable oracle, sim/mpm/mpm_measure.hpp); a step
// asked for its row takes them from G2P instead (sim/mpm/g2p.hpp): after each chunk of particles,
// ChunkTerms::sum reads their new state from the particle arrays, forms each particle's terms in
// T, several particles per vector, and adds them in double. The chunks are fixed and their sums
// added in chunk order, so that the row does not depend on the thread count.
#pragma once
#include <array>
#include <cstring>

#include "sim/math.hpp"
#include "sim/mpm/simd/lanes.hpp"
#include "sim/mpm/simd/soa_transpose.hpp"

namespace apiclab {

// One cache line (8 doubles): neighbouring chunks' sums, written by different threads in G2P,
// never share a line.
struct alignas(64) ParticleSums {
  double kinetic = 0;  // ½ Σ m |v|² (+ ½ m tr(C D Cᵀ) affine, + PolyPIC's higher modes)
  double gravity = 0;  // −Σ m g·x
  std::array<double, 3> p{0, 0, 0}, L{0, 0, 0};

  void add(const ParticleSums& o) {
    kinetic += o.kinetic;
    gravity += o.gravity;
    for (int a = 0; a < 3; ++a) {
      p[a] += o.p[a];
      L[a] += o.L[a];
    }
  }
};

// A chunk of G2P's particles at their new state, summed after G2P has stored them (x, v and C
// are then in L1): sum() reads x, v and, where D_p = k Δx² I (quadratic, cubic), C from the
// particle arrays; else (the multilinear kernel's D_p, PolyPIC's higher modes) G2P sets each
// particle's ½ m tr(C D_p Cᵀ) (+ modes) and m (Bᵀ : ε), B = C D_p (Jiang et al. 2017, Sec 5.3),
// in this chunk's columns. sum() forms each particle's terms in T, as measure()'s oracle does, P
// particles per vector, and adds them in double; x, v and C are read from the particle arrays
// several particles a register (sim/mpm/simd/soa_transpose.hpp), and float terms of two vectors of
// particles are added in float before their conversion (G below). Why: added one particle at a
// time in G2P, the chains of dependent double adds and the conversions made the diagnostics row
// a large share of a 2D float step; this way it is a few % (docs/performance.md).
template <class T, int D, int N>
struct ChunkTerms {
  // Particles per vector of terms: 8 float or 4 double, one AVX2 register. Not 16 floats (one
  // AVX-512 register): the step's other loops use no AVX-512 register, and this one alone would
  // lower the core's clock (docs/performance.md). Their double values are added 4 at a time: the
  // same order, so the same row, in every build.
  static constexpr int P = 32 / int(sizeof(T));
  static constexpr int Q = 4;
  static_assert(N % P == 0 && P % Q == 0);
  static_assert(sizeof(Vec<T, D>) == D * sizeof(T) && sizeof(Mat<T, D>) == D * D * sizeof(T));
  static constexpr int moments = D == 2 ? 1 : 3;  // 2D: only the z component
  alignas(64) T extra_kinetic[N], affine_moment[moments][N];
  T isotropic_k = 0;    // k Δx² where C is read, else 0
  bool extras = false;  // whether extra_kinetic and affine_moment are set (else not read)

  // With any D_p (the multilinear kernel's diagonal one, Sec 5.9).
  void set_affine(int j, T m, const Mat<T, D>& C, const Mat<T, D>& Dp, T modes_kinetic) {
    const Mat<T, D> CD = C * Dp;
    extra_kinetic[j] = T(0.5) * m * (CD * C.transpose()).trace() + modes_kinetic;
    const Eigen::Vector3d moment =
        double(m) * permutation_contract<T, D>(Mat<T, D>(CD.transpose()));
    for (int a = 0; a < moments; ++a) affine_moment[a][j] = T(moment[D == 2 ? 2 : a]);
  }

  // The chunk's first `count` particles (mass, x, v, and C where isotropic_k is set: `count`
  // of each, not read past), gravity g. Per particle in T, as measure() forms them:
  // ½ m (|v|² + k |C|²) (+ the extra kinetic terms), m v, m x (gravity −g·Σ m x is formed in
  // double at the end), x × m v + m k (C_ba − C_ab) ε_abγ (+ the extra moments).
  ParticleSums sum(const T* mass, const Vec<T, D>* x, const Vec<T, D>* v, const Mat<T, D>* C,
                   int count, const std::array<double, 3>& g) {
    if (isotropic_k != T(0))
      return extras ? sum_as<true, true>(mass, x, v, C, count, g)
                    : sum_as<true, false>(mass, x, v, C, count, g);
    return extras ? sum_as<false, true>(mass, x, v, C, count, g)
                  : sum_as<false, false>(mass, x, v, C, count, g);
  }

 private:
  using VT = typename SimdVector<T, P>::type;
  using VD = typename SimdVector<double, Q>::type;
  // Float terms of G vectors of particles are added in float before their conversion: one more
  // rounding a term (ε_T of the pair), half the conversions, which were the row's bottleneck
  // (each a lane-crossing move on the one shuffle port). Double terms are added as they come.
  static constexpr int G = sizeof(T) == 4 ? 2 : 1;
  // 2D float: the lanes of a vector hold particles (0 1 4 5 2 3 6 7) of its 8, the order in which
  // one in-half shuffle of two loads splits x and y (for sums the order is free); else in order.
  static constexpr bool shuffled = D == 2 && P == 8;
  static_assert(N % (G * P) == 0);

  struct Terms {
    VT kinetic, mx[D], p[D], L[moments];
    void add(const Terms& o) {
      kinetic += o.kinetic;
      for (int a = 0; a < D; ++a) {
        mx[a] += o.mx[a];
        p[a] += o.p[a];
      }
      for (int a = 0; a < moments; ++a) L[a] += o.L[a];
    }
  };

  // P consecutive scalars in the lanes' particle order.
  static VT load_scalars(const T* from) {
    const VT in = load_register<VT>(from);
    if constexpr (shuffled) return shuffle_lanes<0, 1, 4, 5, 2, 3, 6, 7>(in, in);
    return in;
  }
  // Entries of P consecutive 2-vectors or matrices, one register per entry, in the lanes' order.
  template <int n>
  static void load_items(const T* from, VT (&out)[n]) {
    if constexpr (shuffled && n == 2) {
      const VT low = load_register<VT>(from), high = load_register<VT>(from + 8);
      out[0] = shuffle_lanes<0, 2, 8, 10, 4, 6, 12, 14>(low, high);
      out[1] = shuffle_lanes<1, 3, 9, 11, 5, 7, 13, 15>(low, high);
    } else if constexpr (shuffled && n == 4) {  // items (0 2) (1 3) (4 6) (5 7), transposed
      using Half = typename SimdVector<T, 4>::type;
      for (int j = 0; j < 4; ++j) {
        const int first = j / 2 * 4 + j % 2;
        out[j] = join_halves<VT>(load_register<Half>(from + 4 * first),
                                 load_register<Half>(from + 4 * (first + 2)));
      }
      soa_transpose_detail::transpose_within_halves(out);
    } else {
      load_entries<n>(from, out);
    }
  }

  // The terms of P particles from (ms, xp, vp, cp): the arrays from particle j on, or a copy of
  // the last, partial group's particles, zero after them.
  template <bool isotropic, bool with_extras>
  Terms terms_of(int j, const T* ms, const T* xp, const T* vp, const T* cp) const {
    Terms t;
    const VT m = load_scalars(ms);
    VT xs[D], vs[D], v2{};
    load_items<D>(xp, xs);
    load_items<D>(vp, vs);
    for (int a = 0; a < D; ++a) {
      v2 += vs[a] * vs[a];
      t.p[a] = m * vs[a];
      t.mx[a] = m * xs[a];
    }
    if constexpr (D == 2) {
      t.L[0] = xs[0] * t.p[1] - xs[1] * t.p[0];
    } else {
      for (int a = 0; a < 3; ++a)
        t.L[a] = xs[(a + 1) % 3] * t.p[(a + 2) % 3] - xs[(a + 2) % 3] * t.p[(a + 1) % 3];
    }
    VT kin = v2;
    if constexpr (isotropic) {  // m k |C|² and m k (C_ba − C_ab) ε_abγ, Sec 5.3
      const T k = isotropic_k;
      VT cs[D * D], c2{};
      load_items<D * D>(cp, cs);
      for (int e = 0; e < D * D; ++e) c2 += cs[e] * cs[e];
      kin += k * c2;
      const VT mk = k * m;
      auto skew = [&](int a, int b) { return mk * (cs[b + D * a] - cs[a + D * b]); };
      if constexpr (D == 2) {
        t.L[0] += skew(0, 1);
      } else {
        t.L[0] += skew(1, 2);
        t.L[1] += skew(2, 0);
        t.L[2] += skew(0, 1);
      }
    }
    t.kinetic = kin * (T(0.5) * m);
    if constexpr (with_extras) {
      t.kinetic += load_scalars(&extra_kinetic[j]);
      for (int a = 0; a < moments; ++a) t.L[a] += load_scalars(&affine_moment[a][j]);
    }
    return t;
  }

  // The terms of `count` · P particles added pairwise (count a power of 2): log₂ count roundings.
  template <int count, bool isotropic, bool with_extras>
  Terms terms_tree(int j, const T* ms, const T* xp, const T* vp, const T* cp) const {
    if constexpr (count == 1) {
      return terms_of<isotropic, with_extras>(j, ms, xp, vp, cp);
    } else {
      constexpr int half = count / 2 * P;  // particles in each half
      Terms t = terms_tree<count / 2, isotropic, with_extras>(j, ms, xp, vp, cp);
      t.add(terms_tree<count / 2, isotropic, with_extras>(
          j + half, ms + half, xp + half * D, vp + half * D, isotropic ? cp + half * D * D : cp));
      return t;
    }
  }

  template <bool isotropic, bool with_extras>
  ParticleSums sum_as(const T* mass, const Vec<T, D>* x, const Vec<T, D>* v, const Mat<T, D>* C,
                      int count, const std::array<double, 3>& g) {
    constexpr int group = G * P;  // particles a conversion to double
    const int padded = (count + group - 1) / group * group;
    if constexpr (with_extras)  // the last group's unused lanes
      for (int j = count; j < padded; ++j) {
        extra_kinetic[j] = T(0);
        for (int a = 0; a < moments; ++a) affine_moment[a][j] = T(0);
      }
    // P terms into Q double lanes, Q at a time in lane order. Lane by lane, which GCC 12 turns
    // into one conversion per Q lanes; __builtin_convertvector took three instructions for 4.
    auto add = [](VD& sum, const VT& terms) {
      for (int k = 0; k < P; k += Q) {
        VD part;
        for (int l = 0; l < Q; ++l) part[l] = double(terms[k + l]);
        sum += part;
      }
    };
    VD kinetic{}, mx[D] = {}, p[D] = {}, L[moments] = {};
    // G·P particles from the arrays (particle j on), or from zero-padded copies.
    auto group_of = [&](int j, const T* ms, const T* xp, const T* vp, const T* cp) {
      const Terms t = terms_tree<G, isotropic, with_extras>(j, ms, xp, vp, cp);
      add(kinetic, t.kinetic);
      for (int a = 0; a < D; ++a) {
        add(mx[a], t.mx[a]);
        add(p[a], t.p[a]);
      }
      for (int a = 0; a < moments; ++a) add(L[a], t.L[a]);
    };
    // The arrays' scalars (Eigen's fixed-size vectors and matrices are their scalars alone).
    const T* x_entries = reinterpret_cast<const T*>(x);
    const T* v_entries = reinterpret_cast<const T*>(v);
    const T* c_entries = isotropic ? reinterpret_cast<const T*>(C) : nullptr;
    const int whole = count / group * group;
    for (int j = 0; j < whole; j += group)
      group_of(j, mass + j, x_entries + D * j, v_entries + D * j,
               isotropic ? c_entries + D * D * j : nullptr);
    if (whole < count) {
      T ms[group] = {}, xs[group * D] = {}, vs[group * D] = {},
        cs[isotropic ? group * D * D : 1] = {};
      for (int l = 0; l < count - whole; ++l) {
        ms[l] = mass[whole + l];
        for (int a = 0; a < D; ++a) {
          xs[D * l + a] = x_entries[D * (whole + l) + a];
          vs[D * l + a] = v_entries[D * (whole + l) + a];
        }
        if constexpr (isotropic)
          for (int e = 0; e < D * D; ++e) cs[D * D * l + e] = c_entries[D * D * (whole + l) + e];
      }
      group_of(whole, ms, xs, vs, cs);
    }
    auto total = [](const VD& lanes) {
      double s = 0;
      for (int l = 0; l < Q; ++l) s += lanes[l];
      return s;
    };
    ParticleSums s;
    s.kinetic = total(kinetic);
    for (int a = 0; a < D; ++a) {
      s.gravity -= g[std::size_t(a)] * total(mx[a]);
      s.p[std::size_t(a)] = total(p[a]);
    }
    // In 2D only L_z: the oracle adds exact zeros to L_x and L_y, which leaves them 0.
    for (int a = 0; a < moments; ++a) s.L[D == 2 ? 2 : std::size_t(a)] = total(L[a]);
    return s;
  }
};

}  // namespace apiclab
