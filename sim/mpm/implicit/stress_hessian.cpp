// The projected ∂P/∂F's eigenvalue clamp, its double instantiations and the float ones computed
// through them (stress_hessian.hpp).
#include "sim/mpm/implicit/stress_hessian.hpp"

#include <Eigen/Eigenvalues>

namespace apiclab {

void clamp_negative_eigenvalues(Eigen::MatrixXd& symmetric) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(symmetric);
  if (eig.eigenvalues().minCoeff() >= 0.0) return;
  symmetric = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
              eig.eigenvectors().transpose();
}

APICLAB_STRESS_HESSIAN(, double, 2)
APICLAB_STRESS_HESSIAN(, double, 3)

namespace {

Lame<double> in_double(Lame<float> l) { return {double(l.mu), double(l.lambda)}; }

}  // namespace

#define APICLAB_STRESS_HESSIAN_FLOAT(D, NAME)                                                \
  template <>                                                                                \
  Eigen::Matrix<float, D * D, D * D> NAME<float, D>(MaterialModel m, const Mat<float, D>& F, \
                                                    Lame<float> l) {                         \
    return NAME<double, D>(m, F.cast<double>(), in_double(l)).cast<float>();                 \
  }
APICLAB_STRESS_HESSIAN_FLOAT(2, stress_differential_matrix)
APICLAB_STRESS_HESSIAN_FLOAT(3, stress_differential_matrix)
APICLAB_STRESS_HESSIAN_FLOAT(2, stress_hessian)
APICLAB_STRESS_HESSIAN_FLOAT(3, stress_hessian)
APICLAB_STRESS_HESSIAN_FLOAT(2, projected_stress_hessian)
APICLAB_STRESS_HESSIAN_FLOAT(3, projected_stress_hessian)

}  // namespace apiclab
