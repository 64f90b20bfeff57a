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
#include <vector>

#include "sim/eol/frame.hpp"
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

// Eq 23: the frame velocity q̇₁ (ν, ω in world axes) closest to the node velocities u_i
// (world axes) at world offsets r_i, over the nodes with mass. Zero when they cannot fix it.
// The normal equations Σ Jᵢᵀ Jᵢ q̇₁ = Σ Jᵢᵀ uᵢ in closed form: Σ Jᵢᵀ Jᵢ is the rigid mass
// matrix of unit masses, Σ Jᵢᵀ uᵢ = (Σ uᵢ, Σ rᵢ × uᵢ).
template <class T, int D>
FrameVec<T, D> split_frame_velocity(const std::vector<Vec<T, D>>& u,
                                    const std::vector<Vec<T, D>>& r, const std::vector<T>& mass) {
  constexpr int K = frame_dofs<D>;
  RigidMoments<D> moments;
  Eigen::Vector3d sum_u = Eigen::Vector3d::Zero(), sum_moment = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < u.size(); ++i) {
    if (!(mass[i] > T(0))) continue;
    moments.template add<T>(1.0, r[i]);
    for (int a = 0; a < D; ++a) sum_u[a] += double(u[i][a]);
    sum_moment += cross_moment<T, D>(r[i], u[i]);
  }
  const FrameMatrix<D> A = moments.matrix();
  Eigen::Matrix<double, K, 1> b;
  b.template head<D>() = sum_u.template head<D>();
  if constexpr (D == 2)
    b[2] = sum_moment[2];
  else
    b.template tail<3>() = sum_moment;
  Eigen::LDLT<FrameMatrix<D>> ldlt(A);
  Eigen::Matrix<double, K, 1> q = ldlt.solve(b);
  if (ldlt.info() != Eigen::Success || !q.allFinite() || A.trace() == 0)
    return FrameVec<T, D>::Zero();
  return q.template cast<T>();
}

// Eq 24: v*_i = Rᵀ (u_i − J_i q̇₁) = Rᵀ (u_i − ν − ω × r_i), the Eulerian velocity in frame axes.
template <class T, int D>
void eulerian_remainder(const std::vector<Vec<T, D>>& u, const std::vector<Vec<T, D>>& r,
                        const FrameVec<T, D>& q1, const Mat<T, D>& R, std::vector<Vec<T, D>>& v) {
  const Vec<T, D> nu = q1.template head<D>();
  const Spin<T, D> omega = q1.template tail<spin_dim<D>>();
  const Mat<T, D> Rt = R.transpose();
  for (std::size_t i = 0; i < u.size(); ++i)
    v[i] = Rt * (u[i] - nu - spin_cross<T, D>(omega, r[i]));
}

}  // namespace apiclab::eol
