// Hyperelastic energy densities Ψ(F), first Piola-Kirchhoff stress P = ∂Ψ/∂F (eq 10) and the
// action of ∂P/∂F on a direction dF (eq 35 needs it).
#pragma once
#include <cmath>
#include <limits>

#include "sim/math.hpp"
#include "sim/scene/registry.hpp"

namespace apiclab {

template <class T>
struct Lame {
  T mu, lambda;
};

// Compressible neo-Hookean: Ψ = μ/2 (tr FᵀF − d) − μ log J + λ/2 (log J)².
// Ψ = +∞ for J ≤ 0, so a line search never accepts an inverted F.
template <class T, int D>
struct NeoHookean {
  static T energy(const Mat<T, D>& F, Lame<T> l) {
    T J = F.determinant();
    if (!(J > T(0))) return std::numeric_limits<T>::infinity();
    T logJ = std::log(J);
    return T(0.5) * l.mu * (F.squaredNorm() - T(D)) - l.mu * logJ + T(0.5) * l.lambda * logJ * logJ;
  }
  // P = μ (F − F⁻ᵀ) + λ log J F⁻ᵀ, written with the cofactor J F⁻ᵀ.
  static Mat<T, D> stress(const Mat<T, D>& F, Lame<T> l) {
    T J = F.determinant();
    Mat<T, D> cof = cofactor<T, D>(F);
    if (!(J > T(0))) return l.mu * F;  // inverted: only the deviatoric pull back remains usable
    T logJ = std::log(J);
    return l.mu * F + ((l.lambda * logJ - l.mu) / J) * cof;
  }
  static Mat<T, D> stress_differential(const Mat<T, D>& F, const Mat<T, D>& dF, Lame<T> l) {
    T J = F.determinant();
    if (!(J > T(0))) return l.mu * dF;
    Mat<T, D> cof = cofactor<T, D>(F);
    T logJ = std::log(J);
    T dJ = (cof.array() * dF.array()).sum();  // dJ = J F⁻ᵀ : dF
    T a = (l.lambda * logJ - l.mu) / J;
    T da = (l.lambda / J - a) / J * dJ;  // d[(λ log J − μ)/J]
    return l.mu * dF + da * cof + a * cofactor_derivative<T, D>(F, dF);
  }
};

// Fixed corotated (Stomakhin et al. 2012): Ψ = μ ‖F − R‖² + λ/2 (J − 1)², defined for any F.
template <class T, int D>
struct FixedCorotated {
  static T energy(const Mat<T, D>& F, Lame<T> l) {
    Mat<T, D> R, S;
    polar_decomposition<T, D>(F, R, S);
    T J = F.determinant();
    return l.mu * (F - R).squaredNorm() + T(0.5) * l.lambda * (J - T(1)) * (J - T(1));
  }
  // R of F = R S (2D in closed form).
  static Mat<T, D> rotation(const Mat<T, D>& F) {
    Mat<T, D> R;
    if constexpr (D == 2) {
      R = rotation_2d(F);
    } else {
      Mat<T, D> S;
      polar_decomposition<T, D>(F, R, S);
    }
    return R;
  }
  // P = 2μ (F − R) + λ (J − 1) J F⁻ᵀ.
  static Mat<T, D> stress(const Mat<T, D>& F, Lame<T> l) {
    const Mat<T, D> R = rotation(F);
    T J = F.determinant();
    return T(2) * l.mu * (F - R) + l.lambda * (J - T(1)) * cofactor<T, D>(F);
  }
  // dP = 2μ (dF − dR) + λ (JF⁻ᵀ : dF) JF⁻ᵀ + λ (J − 1) d(JF⁻ᵀ), with dR = R W and W skew
  // solving W S + S W = Rᵀ dF − dFᵀ R.
  static Mat<T, D> stress_differential(const Mat<T, D>& F, const Mat<T, D>& dF, Lame<T> l) {
    Mat<T, D> R, S;
    polar_decomposition<T, D>(F, R, S);
    Mat<T, D> A = R.transpose() * dF;
    A = (A - A.transpose()).eval();  // eval: A aliases A.transpose()
    Mat<T, D> W;
    if constexpr (D == 2) {
      T tr = S.trace();
      T w = std::abs(tr) > T(1e-12) ? A(1, 0) / tr : T(0);
      W << T(0), -w, w, T(0);
    } else {
      Vec<T, 3> a(A(2, 1), A(0, 2), A(1, 0));
      Mat<T, 3> K = S.trace() * Mat<T, 3>::Identity() - S;
      Vec<T, 3> w = K.fullPivLu().solve(a);
      if (!w.allFinite()) w.setZero();
      W << T(0), -w[2], w[1], w[2], T(0), -w[0], -w[1], w[0], T(0);
    }
    Mat<T, D> dR = R * W;
    T J = F.determinant();
    Mat<T, D> cof = cofactor<T, D>(F);
    T dJ = (cof.array() * dF.array()).sum();
    return T(2) * l.mu * (dF - dR) + l.lambda * dJ * cof +
           l.lambda * (J - T(1)) * cofactor_derivative<T, D>(F, dF);
  }
};

// The stress P and the energy density Ψ of one F together, from the same R and J: the explicit
// step's stress pass also yields the diagnostics' elastic energy at no extra decomposition.
template <class T, int D>
Mat<T, D> first_piola_and_energy(MaterialModel m, const Mat<T, D>& F, Lame<T> l, T& psi) {
  const T J = F.determinant();
  switch (m) {
    case MaterialModel::neo_hookean:
    case MaterialModel::plastic: {  // its elastic part, of the F_e the caller passes
      if (!(J > T(0))) {
        psi = std::numeric_limits<T>::infinity();
        return l.mu * F;  // as NeoHookean::stress
      }
      const T logJ = std::log(J);
      psi =
          T(0.5) * l.mu * (F.squaredNorm() - T(D)) - l.mu * logJ + T(0.5) * l.lambda * logJ * logJ;
      return l.mu * F + ((l.lambda * logJ - l.mu) / J) * cofactor<T, D>(F);
    }
    case MaterialModel::fixed_corotated:
      break;
  }
  const Mat<T, D> R = FixedCorotated<T, D>::rotation(F);
  psi = l.mu * (F - R).squaredNorm() + T(0.5) * l.lambda * (J - T(1)) * (J - T(1));
  return T(2) * l.mu * (F - R) + l.lambda * (J - T(1)) * cofactor<T, D>(F);
}

// Runtime dispatch on the registry key. Switches without a default, so a model added to the
// registry and not here is a -Wswitch warning instead of silently becoming another model.
template <class T, int D>
T energy_density(MaterialModel m, const Mat<T, D>& F, Lame<T> l) {
  switch (m) {
    case MaterialModel::neo_hookean:
    case MaterialModel::plastic:  // its elastic part, of the F_e the caller passes
      return NeoHookean<T, D>::energy(F, l);
    case MaterialModel::fixed_corotated:
      break;
  }
  return FixedCorotated<T, D>::energy(F, l);
}
template <class T, int D>
Mat<T, D> first_piola(MaterialModel m, const Mat<T, D>& F, Lame<T> l) {
  switch (m) {
    case MaterialModel::neo_hookean:
    case MaterialModel::plastic:  // its elastic part, of the F_e the caller passes
      return NeoHookean<T, D>::stress(F, l);
    case MaterialModel::fixed_corotated:
      break;
  }
  return FixedCorotated<T, D>::stress(F, l);
}
template <class T, int D>
Mat<T, D> first_piola_differential(MaterialModel m, const Mat<T, D>& F, const Mat<T, D>& dF,
                                   Lame<T> l) {
  switch (m) {
    case MaterialModel::neo_hookean:
    case MaterialModel::plastic:  // its elastic part, of the F_e the caller passes
      return NeoHookean<T, D>::stress_differential(F, dF, l);
    case MaterialModel::fixed_corotated:
      break;
  }
  return FixedCorotated<T, D>::stress_differential(F, dF, l);
}

}  // namespace apiclab
