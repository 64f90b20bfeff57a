// The Lagrangian frame q₁ of one object (Fan et al. 2013, Sec 3.1, eq 1): φ₁: x = R y + p maps
// the intermediate domain y (where the object's Eulerian grid lives) rigidly into space. Its
// velocities are kept in world axes: ν = ṗ and ω, so a point fixed in the grid moves at
// ν + ω × R y (eq 2 with v = 0). 2D keeps the angle, 3D a unit quaternion.
#pragma once
#include <Eigen/Geometry>
#include <cmath>

#include "sim/math.hpp"

namespace apiclab::eol {

template <int D>
constexpr int spin_dim = D == 2 ? 1 : 3;  // angular velocity components
template <int D>
constexpr int frame_dofs = D + spin_dim<D>;  // Lagrangian DOFs: ν then ω

template <class T, int D>
using Spin = Eigen::Matrix<T, spin_dim<D>, 1>;
template <class T, int D>
using FrameVec = Eigen::Matrix<T, frame_dofs<D>, 1>;

// ω × r (2D: ω is the z component).
template <class T, int D>
Vec<T, D> spin_cross(const Spin<T, D>& w, const Vec<T, D>& r) {
  if constexpr (D == 2) {
    return Vec<T, 2>(-w[0] * r[1], w[0] * r[0]);
  } else {
    return w.cross(r);
  }
}

// The rigid velocity of a point at world offset r from p, as a linear map of q̇₁ = (ν, ω):
// J q̇₁ = ν + ω × r, J = [I  [r]ᵀ] (eq 2; M₂⁻¹ M₁₂ᵀ of eq 22 for one node).
template <class T, int D>
Eigen::Matrix<T, D, frame_dofs<D>> rigid_jacobian(const Vec<T, D>& r) {
  Eigen::Matrix<T, D, frame_dofs<D>> J;
  J.template leftCols<D>().setIdentity();
  if constexpr (D == 2) {
    J(0, 2) = -r[1];
    J(1, 2) = r[0];
  } else {
    J.template rightCols<3>() << T(0), r[2], -r[1], -r[2], T(0), r[0], r[1], -r[0], T(0);
  }
  return J;
}

template <class T, int D>
struct RigidFrame {
  Vec<T, D> p = Vec<T, D>::Zero();   // world position of the intermediate origin
  Vec<T, D> nu = Vec<T, D>::Zero();  // linear velocity ν = ṗ (world)
  Spin<T, D> omega = Spin<T, D>::Zero();
  T angle = T(0);                                             // 2D
  Eigen::Quaternion<T> q = Eigen::Quaternion<T>::Identity();  // 3D

  Mat<T, D> rotation() const {
    if constexpr (D == 2) {
      Mat<T, 2> R;
      const T c = std::cos(angle), s = std::sin(angle);
      R << c, -s, s, c;
      return R;
    } else {
      return q.toRotationMatrix();
    }
  }
  FrameVec<T, D> velocity() const {
    FrameVec<T, D> v;
    v << nu, omega;
    return v;
  }
  void set_velocity(const FrameVec<T, D>& v) {
    nu = v.template head<D>();
    omega = v.template tail<spin_dim<D>>();
  }
  // q₁ ← q₁ + Δt q̇₁: p by ν, R by the exponential map of Δt ω (exact for constant ω).
  void advance(T dt) {
    p += dt * nu;
    if constexpr (D == 2) {
      angle += dt * omega[0];
    } else {
      const T a = omega.norm() * dt;
      if (a > T(0))
        q = (Eigen::Quaternion<T>(Eigen::AngleAxis<T>(a, omega.normalized())) * q).normalized();
    }
  }
};

}  // namespace apiclab::eol
