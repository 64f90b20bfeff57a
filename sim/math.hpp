// Small fixed-size linear algebra on top of Eigen, shared by the whole solver.
#pragma once
#include <Eigen/Dense>
#include <cmath>
#include <limits>

namespace apiclab {

template <class T, int D>
using Vec = Eigen::Matrix<T, D, 1>;
template <class T, int D>
using Mat = Eigen::Matrix<T, D, D>;

// Angular momentum of a point mass about the origin: x × m v (3 components; 2D fills only z).
template <class T, int D>
Eigen::Vector3d cross_moment(const Vec<T, D>& x, const Vec<T, D>& mv) {
  if constexpr (D == 2) {
    return {0.0, 0.0, double(x[0]) * double(mv[1]) - double(x[1]) * double(mv[0])};
  } else {
    return x.template cast<double>().cross(mv.template cast<double>());
  }
}

// A : ε with A_αβ ε_αβγ (Jiang et al. 2017, Sec 5.3): the angular momentum carried by m B.
template <class T, int D>
Eigen::Vector3d permutation_contract(const Mat<T, D>& A) {
  if constexpr (D == 2) {
    return {0.0, 0.0, double(A(0, 1)) - double(A(1, 0))};
  } else {
    return {double(A(1, 2)) - double(A(2, 1)), double(A(2, 0)) - double(A(0, 2)),
            double(A(0, 1)) - double(A(1, 0))};
  }
}

template <class T, int D>
Mat<T, D> cofactor(const Mat<T, D>& F);

// R of F = R S for det F > 0 by Higham's (1986) Newton iteration X ← ½(γX + X⁻ᵀ/γ), scaled by
// γ = (‖X⁻¹‖_F / ‖X‖_F)^½ while far from converged: a few 3×3 inverses instead of a JacobiSVD
// (Eigen has no polar decomposition). Returns false for an inverted or nearly singular F.
template <class T>
bool polar_newton_3d(const Mat<T, 3>& F, Mat<T, 3>& R) {
  const T scale = F.norm();
  T det = F.determinant();
  if (!(det > T(1e-6) * scale * scale * scale)) return false;
  const T tolerance = T(8) * std::numeric_limits<T>::epsilon();
  Mat<T, 3> X = F;
  T step = T(1);
  for (int it = 0; it < 30; ++it) {
    const Mat<T, 3> cof = cofactor<T, 3>(X);  // X⁻ᵀ = cof(X) / det X
    // Frobenius scaling γ = (‖X⁻¹‖ / ‖X‖)^½ (Higham 1986, Sec 3): a square root, which SIMD
    // lanes have, where |det X|^(-1/3) needs a scalar cbrt per lane
    // (sim/mpm/simd/stress_lanes.hpp).
    const T gamma = step > T(1e-2)
                        ? std::sqrt(std::sqrt(cof.squaredNorm() / (det * det * X.squaredNorm())))
                        : T(1);
    Mat<T, 3> next = T(0.5) * (gamma * X + cof / (gamma * det));
    const T previous = step;
    step = (next - X).norm();
    X = next;
    // Converged, or round-off stops the quadratic decrease just above the tolerance.
    if (step <= tolerance || (step < T(1e-3) && step >= previous)) {
      R = X;
      return true;
    }
    det = X.determinant();
  }
  return false;
}

// Rotation R of the polar decomposition F = R S with det R = +1 (fixed corotated needs it
// also for inverted F, Stomakhin et al. 2012). S is returned symmetric.
template <class T, int D>
void polar_decomposition(const Mat<T, D>& F, Mat<T, D>& R, Mat<T, D>& S) {
  if constexpr (D == 2) {
    // Closed form: R is the rotation closest to F.
    T a = F(0, 0) + F(1, 1), b = F(1, 0) - F(0, 1);
    T n = std::sqrt(a * a + b * b);
    T c = T(1), s = T(0);
    if (n > T(0)) {
      c = a / n;
      s = b / n;
    }
    R << c, -s, s, c;
    S = R.transpose() * F;
    S(0, 1) = S(1, 0) = T(0.5) * (S(0, 1) + S(1, 0));
  } else {
    if (polar_newton_3d(F, R)) {
      S = R.transpose() * F;
      S = (T(0.5) * (S + S.transpose())).eval();  // eval: S aliases Sᵀ
      return;
    }
    Eigen::JacobiSVD<Mat<T, D>> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat<T, D> U = svd.matrixU(), V = svd.matrixV();
    Vec<T, D> sigma = svd.singularValues();
    if (U.determinant() < 0) {
      U.col(D - 1) *= -1;
      sigma[D - 1] *= -1;
    }
    if (V.determinant() < 0) {
      V.col(D - 1) *= -1;
      sigma[D - 1] *= -1;
    }
    R = U * V.transpose();
    S = V * sigma.asDiagonal() * V.transpose();
  }
}

// The rotation of the 2D polar decomposition alone (the stress needs no S).
template <class T>
inline Mat<T, 2> rotation_2d(const Mat<T, 2>& F) {
  T a = F(0, 0) + F(1, 1), b = F(1, 0) - F(0, 1);
  T n2 = a * a + b * b;
  T c = T(1), s = T(0);
  if (n2 > T(0)) {
    T inv = T(1) / std::sqrt(n2);
    c = a * inv;
    s = b * inv;
  }
  Mat<T, 2> R;
  R << c, -s, s, c;
  return R;
}

// Cofactor matrix J F^{-T}, and its directional derivative; both exist for singular F.
template <class T, int D>
Mat<T, D> cofactor(const Mat<T, D>& F) {
  Mat<T, D> C;
  if constexpr (D == 2) {
    C << F(1, 1), -F(1, 0), -F(0, 1), F(0, 0);
  } else {
    C.col(0) = F.col(1).cross(F.col(2));
    C.col(1) = F.col(2).cross(F.col(0));
    C.col(2) = F.col(0).cross(F.col(1));
  }
  return C;
}

template <class T, int D>
Mat<T, D> cofactor_derivative(const Mat<T, D>& F, const Mat<T, D>& dF) {
  Mat<T, D> C;
  if constexpr (D == 2) {
    C << dF(1, 1), -dF(1, 0), -dF(0, 1), dF(0, 0);
  } else {
    C.col(0) = dF.col(1).cross(F.col(2)) + F.col(1).cross(dF.col(2));
    C.col(1) = dF.col(2).cross(F.col(0)) + F.col(2).cross(dF.col(0));
    C.col(2) = dF.col(0).cross(F.col(1)) + F.col(0).cross(dF.col(1));
  }
  return C;
}

}  // namespace apiclab
