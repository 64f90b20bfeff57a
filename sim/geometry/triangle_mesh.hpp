// Lagrangian triangle-mesh elasticity for "triangulated" 2D objects (Jiang et al. 2017,
// Sec 6.7): each triangle's F = Ds Dm⁻¹ comes from its current vertex (particle) positions, the
// CPDI-equivalent update the ringing test uses instead of eq 40, plus zero-length penalty
// springs f = −c (x_p − x_p⁰). Vertices are particle ids; positions are passed by particle index.
#pragma once
#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/materials.hpp"

namespace apiclab {

template <class T>
class TriangleMesh {
 public:
  using V = Vec<T, 2>;
  using M = Mat<T, 2>;
  struct Triangle {
    std::array<std::int32_t, 3> v;  // particle ids
    M Dm_inv;                       // inverse rest edge matrix
    T area;                         // rest area
    MaterialModel model;
    Lame<T> lame;
  };
  struct Anchor {
    std::int32_t id;
    V x0;
    T c;
  };

  bool empty() const { return tris_.empty() && anchors_.empty(); }
  void add_triangle(std::array<std::int32_t, 3> v, const V& x0, const V& x1, const V& x2,
                    MaterialModel model, Lame<T> lame) {
    M Dm;
    Dm.col(0) = x1 - x0;
    Dm.col(1) = x2 - x0;
    tris_.push_back({v, Dm.inverse(), T(0.5) * std::abs(Dm.determinant()), model, lame});
  }
  void add_anchor(std::int32_t id, const V& x0, T c) { anchors_.push_back({id, x0, c}); }

  // Φ = Σ_t A_t Ψ(F_t) + Σ ½ c |x − x⁰|² at positions x (by particle index, idx maps id → index);
  // adds ∂Φ/∂x_p into g (by index) when g is given. +∞ for an inverted neo-Hookean triangle.
  // `terms`, when given, gains the size of the terms Φ sums (its round-off over ε, as for the
  // particles in sim/mpm/implicit/implicit.hpp): A (λ + 2μ)(|F|² + 1) + A|Ψ| a triangle, c |d| (|d|
  // + |x⁰|) a spring (d = x − x⁰ cancels to ε |x⁰|).
  double energy(const std::vector<V>& x, const std::vector<std::uint32_t>& idx, std::vector<V>* g,
                double* terms = nullptr) const {
    double e = 0;
    for (const Triangle& t : tris_) {
      const V& a = x[idx[t.v[0]]];
      M Ds;
      Ds.col(0) = x[idx[t.v[1]]] - a;
      Ds.col(1) = x[idx[t.v[2]]] - a;
      M F = Ds * t.Dm_inv;
      const double psi = double(energy_density<T, 2>(t.model, F, t.lame));
      e += double(t.area) * psi;
      if (terms)
        *terms +=
            double(t.area) *
            (double(t.lame.lambda + 2 * t.lame.mu) * double(F.squaredNorm() + 1) + std::abs(psi));
      if (g) {
        M H = t.area * first_piola<T, 2>(t.model, F, t.lame) * t.Dm_inv.transpose();  // ∂Φ/∂Ds
        (*g)[idx[t.v[1]]] += H.col(0);
        (*g)[idx[t.v[2]]] += H.col(1);
        (*g)[idx[t.v[0]]] -= H.col(0) + H.col(1);
      }
    }
    for (const Anchor& s : anchors_) {
      V d = x[idx[s.id]] - s.x0;
      e += 0.5 * double(s.c) * double(d.squaredNorm());
      if (terms) *terms += double(s.c) * double(d.norm()) * double(d.norm() + s.x0.norm());
      if (g) (*g)[idx[s.id]] += s.c * d;
    }
    return e;
  }

  // Per-triangle ∂P/∂F at x, PSD-projected when asked (as for the particles' Hessian).
  void update_hessian(const std::vector<V>& x, const std::vector<std::uint32_t>& idx,
                      bool project) {
    hess_.resize(tris_.size());
    for (std::size_t k = 0; k < tris_.size(); ++k) {
      const Triangle& t = tris_[k];
      const V& a = x[idx[t.v[0]]];
      M Ds;
      Ds.col(0) = x[idx[t.v[1]]] - a;
      Ds.col(1) = x[idx[t.v[2]]] - a;
      M F = Ds * t.Dm_inv;
      Eigen::Matrix<T, 4, 4> H;
      for (int c = 0; c < 4; ++c) {
        M E = M::Zero();
        E(c % 2, c / 2) = T(1);
        M dP = first_piola_differential<T, 2>(t.model, F, E, t.lame);
        H.col(c) = Eigen::Map<const Eigen::Matrix<T, 4, 1>>(dP.data());
      }
      H = (T(0.5) * (H + H.transpose())).eval();
      if (project) {
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix<T, 4, 4>> eig(H);
        if (eig.eigenvalues().minCoeff() < T(0))
          H = eig.eigenvectors() * eig.eigenvalues().cwiseMax(T(0)).asDiagonal() *
              eig.eigenvectors().transpose();
      }
      hess_[k] = H;
    }
  }
  // kx += K dx, K = ∂²Φ/∂x² with the stored per-triangle ∂P/∂F.
  void apply_hessian(const std::vector<V>& dx, const std::vector<std::uint32_t>& idx,
                     std::vector<V>& kx) const {
    for (std::size_t k = 0; k < tris_.size(); ++k) {
      const Triangle& t = tris_[k];
      const V& a = dx[idx[t.v[0]]];
      M dDs;
      dDs.col(0) = dx[idx[t.v[1]]] - a;
      dDs.col(1) = dx[idx[t.v[2]]] - a;
      M dF = dDs * t.Dm_inv, dP;
      Eigen::Map<Eigen::Matrix<T, 4, 1>>(dP.data()) =
          hess_[k] * Eigen::Map<const Eigen::Matrix<T, 4, 1>>(dF.data());
      M H = t.area * dP * t.Dm_inv.transpose();
      kx[idx[t.v[1]]] += H.col(0);
      kx[idx[t.v[2]]] += H.col(1);
      kx[idx[t.v[0]]] -= H.col(0) + H.col(1);
    }
    for (const Anchor& s : anchors_) kx[idx[s.id]] += s.c * dx[idx[s.id]];
  }

 private:
  std::vector<Triangle> tris_;
  std::vector<Anchor> anchors_;
  std::vector<Eigen::Matrix<T, 4, 4>> hess_;
};

}  // namespace apiclab
