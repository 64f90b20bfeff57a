// The projected ∂P/∂F's eigenvalue clamp and its four instantiations (stress_hessian.hpp).
#include "sim/mpm/implicit/stress_hessian.hpp"

#include <Eigen/Eigenvalues>

namespace apiclab {

void clamp_negative_eigenvalues(Eigen::MatrixXd& symmetric) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(symmetric);
  if (eig.eigenvalues().minCoeff() >= 0.0) return;
  symmetric = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
              eig.eigenvectors().transpose();
}

APICLAB_STRESS_HESSIAN(, float, 2)
APICLAB_STRESS_HESSIAN(, float, 3)
APICLAB_STRESS_HESSIAN(, double, 2)
APICLAB_STRESS_HESSIAN(, double, 3)

}  // namespace apiclab
