// The diagnostics row's sums over particles: kinetic energy with the affine term, the
// gravitational potential, linear and angular momentum (docs/architecture.md, Diagnostics CSV).
// measure() sums them in a pass of its own (the readable oracle, sim/mpm_measure.hpp); a step
// asked for its row sums them inside G2P instead (sim/g2p.hpp), where x, v and C are in
// registers: in fixed chunks of particles, the chunks' sums added in chunk order, so that the
// row does not depend on the thread count.
#pragma once
#include <array>

#include "math.hpp"

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

  // A particle's affine terms (Jiang et al. 2017, Sec 5.3): ½ m tr(C D_p Cᵀ) and m (Bᵀ : ε) with
  // B = C D_p; zero for a scheme without C.
  struct Affine {
    double kinetic = 0;
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  };
  // With D_p = k Δx² I (quadratic, cubic).
  template <class T, int D>
  static Affine affine_isotropic(T m, const Mat<T, D>& C, T k) {
    return {0.5 * double(m) * double(k * C.squaredNorm()),
            double(m) * permutation_contract<T, D>(Mat<T, D>(k * C.transpose()))};
  }
  // With any D_p (the multilinear kernel's diagonal one, Sec 5.9).
  template <class T, int D>
  static Affine affine_of(T m, const Mat<T, D>& C, const Mat<T, D>& Dp) {
    const Mat<T, D> CD = C * Dp;
    return {0.5 * double(m) * double((CD * C.transpose()).trace()),
            double(m) * permutation_contract<T, D>(Mat<T, D>(CD.transpose()))};
  }

  // One particle's share: its products in T, the sums in double, added in the order
  // MpmSimulation::particle_sums adds them (½ m |v|², affine, modes; x × m v + affine moment), so
  // that the two differ only by the round-off of each particle's terms.
  template <class T, int D>
  void add_particle(T m, const Vec<T, D>& x, const Vec<T, D>& v, const std::array<double, 3>& g,
                    const Affine& affine, double modes_kinetic) {
    const double md = double(m);
    kinetic += 0.5 * md * double(v.squaredNorm());
    kinetic += affine.kinetic;
    kinetic += modes_kinetic;
    const Vec<T, D> mv = m * v;
    for (int a = 0; a < D; ++a) p[a] += double(mv[a]);
    const Eigen::Vector3d moment = cross_moment<T, D>(x, mv) + affine.moment;
    for (int a = 0; a < D; ++a) gravity -= md * g[a] * double(x[a]);
    // In 2D only L_z: the oracle adds exact zeros to L_x and L_y, which leaves them 0.
    for (int a = D == 2 ? 2 : 0; a < 3; ++a) L[a] += moment[a];
  }
};

}  // namespace apiclab
