// The least-squares split (Fan et al. 2013, Sec 3.4, eqs 17-25). The EoL mass matrix
//   M = [M₁ M₁₂; M₁₂ᵀ M₂]   (eq 11)
// is singular: M₁ = M₁₂ M₂⁻¹ M₁₂ᵀ (eq 20), so any momentum can be carried by the Eulerian
// velocities alone and the frame velocity q̇₁ is free (eq 22). The split picks the q̇₁ that
// makes the Eulerian velocities smallest in the 2-norm (eq 23),
//   q̇₁ = argmin ‖M₂⁻¹ p₂ − M₂⁻¹ M₁₂ᵀ q̇₁‖₂ = argmin Σ_i |u_i − J_i q̇₁|²,
// and v*_i = Rᵀ (u_i − J_i q̇₁) (eq 24), the sum over the nodes with mass (where M₂ is defined).
// Nodes keep their spatial velocity u_i = J_i q̇₁ + R v*_i exactly: the split moves velocity
// between the modes, never changes it.
#pragma once
#include <array>
#include <vector>

#include "sim/eol/frame.hpp"
#include "sim/eol/grid/node_blocks.hpp"
#include "sim/math.hpp"

namespace apiclab::eol {

template <int D>
using FrameMatrix = Eigen::Matrix<double, frame_dofs<D>, frame_dofs<D>>;

// The moments a rigid mass matrix needs: Σ m, the first moment c = Σ m r and Σ m r rᵀ (in
// double, whatever T), accumulated node by node.
template <int D>
struct RigidMoments {
  double total = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  template <class T>
  void add(double m, const Vec<T, D>& r) {
    Eigen::Vector3d ri = Eigen::Vector3d::Zero();
    for (int a = 0; a < D; ++a) ri[a] = double(r[a]);
    total += m;
    first += m * ri;
    second.noalias() += (m * ri) * ri.transpose();
  }
  // [M I, −[c]; [c], Σ m (|r|² I − r rᵀ)] (2D: the z row and column of the rotation block).
  FrameMatrix<D> matrix() const {
    const Eigen::Matrix3d inertia = second.trace() * Eigen::Matrix3d::Identity() - second;
    const Eigen::Vector3d& c = first;
    FrameMatrix<D> M1 = FrameMatrix<D>::Zero();
    M1.template topLeftCorner<D, D>() = total * Eigen::Matrix<double, D, D>::Identity();
    if constexpr (D == 2) {
      M1(0, 2) = M1(2, 0) = -c[1];
      M1(1, 2) = M1(2, 1) = c[0];
      M1(2, 2) = inertia(2, 2);
    } else {
      Eigen::Matrix3d cross;  // ω × c = −[c] ω: the ν–ω block is −[c]
      cross << 0, c[2], -c[1], -c[2], 0, c[0], c[1], -c[0], 0;
      M1.template topRightCorner<3, 3>() = cross;
      M1.template bottomLeftCorner<3, 3>() = cross.transpose();
      M1.template bottomRightCorner<3, 3>() = inertia;
    }
    return M1;
  }
};

// M₁ of eq 6 for lumped node masses m_i at world offsets r_i from the frame origin: the rigid
// body's mass matrix [M I, [c]ᵀ-block; ., inertia] from the total mass M, the first moment
// c = Σ m r and the inertia Σ m (|r|² I − r rᵀ) (2D: Σ m |r|²).
template <class T, int D>
FrameMatrix<D> rigid_mass_matrix(const std::vector<T>& mass, const std::vector<Vec<T, D>>& r) {
  RigidMoments<D> moments;
  for (std::size_t i = 0; i < mass.size(); ++i) moments.template add<T>(double(mass[i]), r[i]);
  return moments.matrix();
}

// Eq 23's normal equations Σ Jᵢᵀ Jᵢ q̇₁ = Σ Jᵢᵀ uᵢ over the nodes with mass, for F velocity
// fields at once (the Δt choice splits two, eq 32): Σ Jᵢᵀ Jᵢ is the rigid mass matrix of unit
// masses (the same for every field), Σ Jᵢᵀ uᵢ = (Σ uᵢ, Σ rᵢ × uᵢ). Summed with
// sum_node_blocks, so the same for any thread count.
template <int D, int F>
struct SplitSums {
  RigidMoments<D> moments;
  std::array<Eigen::Vector3d, F> sum_u, sum_moment;
  SplitSums() {
    for (int f = 0; f < F; ++f) sum_u[std::size_t(f)] = sum_moment[std::size_t(f)].setZero();
  }
  template <class T>
  void add(const Vec<T, D>& r, const std::array<Vec<T, D>, F>& u) {
    moments.template add<T>(1.0, r);
    for (std::size_t f = 0; f < std::size_t(F); ++f) {
      for (int a = 0; a < D; ++a) sum_u[f][a] += double(u[f][a]);
      sum_moment[f] += cross_moment<T, D>(r, u[f]);
    }
  }
  void merge(const SplitSums& o) {
    moments.total += o.moments.total;
    moments.first += o.moments.first;
    moments.second += o.moments.second;
    for (std::size_t f = 0; f < std::size_t(F); ++f) {
      sum_u[f] += o.sum_u[f];
      sum_moment[f] += o.sum_moment[f];
    }
  }
  // q̇₁ (ν, ω in world axes) of field f; zero when the nodes cannot fix it.
  template <class T>
  std::array<FrameVec<T, D>, F> solve() const {
    constexpr int K = frame_dofs<D>;
    const FrameMatrix<D> A = moments.matrix();
    Eigen::LDLT<FrameMatrix<D>> ldlt(A);
    std::array<FrameVec<T, D>, F> q;
    for (std::size_t f = 0; f < std::size_t(F); ++f) {
      Eigen::Matrix<double, K, 1> b;
      b.template head<D>() = sum_u[f].template head<D>();
      if constexpr (D == 2)
        b[2] = sum_moment[f][2];
      else
        b.template tail<3>() = sum_moment[f];
      const Eigen::Matrix<double, K, 1> x = ldlt.solve(b);
      q[f] = ldlt.info() != Eigen::Success || !x.allFinite() || A.trace() == 0
                 ? FrameVec<T, D>::Zero()
                 : FrameVec<T, D>(x.template cast<T>());
    }
    return q;
  }
};

// Eq 23: the frame velocity q̇₁ (ν, ω in world axes) closest to the node velocities u_i
// (world axes) at world offsets r_i, over the nodes with mass. Zero when they cannot fix it.
// partial: sum_node_blocks' per-block sums, kept between calls.
template <class T, int D>
FrameVec<T, D> split_frame_velocity(const std::vector<Vec<T, D>>& u,
                                    const std::vector<Vec<T, D>>& r, const std::vector<T>& mass,
                                    bool parallel, std::vector<SplitSums<D, 1>>& partial) {
  const SplitSums<D, 1> sums =
      sum_node_blocks(u.size(), parallel, partial, [&](SplitSums<D, 1>& acc, std::size_t i) {
        if (mass[i] > T(0)) acc.template add<T>(r[i], {u[i]});
      });
  return sums.template solve<T>()[0];
}
template <class T, int D>
FrameVec<T, D> split_frame_velocity(const std::vector<Vec<T, D>>& u,
                                    const std::vector<Vec<T, D>>& r, const std::vector<T>& mass) {
  std::vector<SplitSums<D, 1>> partial;
  return split_frame_velocity(u, r, mass, false, partial);
}

// Eq 24: v*_i = Rᵀ (u_i − J_i q̇₁) = Rᵀ (u_i − ν − ω × r_i), the Eulerian velocity in frame axes.
template <class T, int D>
Vec<T, D> eulerian_velocity(const Vec<T, D>& u, const Vec<T, D>& r, const FrameVec<T, D>& q1,
                            const Mat<T, D>& Rt) {
  const Vec<T, D> nu = q1.template head<D>();
  const Spin<T, D> omega = q1.template tail<spin_dim<D>>();
  return Rt * (u - nu - spin_cross<T, D>(omega, r));
}
template <class T, int D>
void eulerian_remainder(const std::vector<Vec<T, D>>& u, const std::vector<Vec<T, D>>& r,
                        const FrameVec<T, D>& q1, const Mat<T, D>& R, std::vector<Vec<T, D>>& v,
                        bool parallel = false) {
  const Mat<T, D> Rt = R.transpose();
  const std::ptrdiff_t n = std::ptrdiff_t(u.size());
#pragma omp parallel for if (parallel)
  for (std::ptrdiff_t ii = 0; ii < n; ++ii) {
    const std::size_t i = std::size_t(ii);
    v[i] = eulerian_velocity<T, D>(u[i], r[i], q1, Rt);
  }
}

}  // namespace apiclab::eol
