#include "service/geometry/levenberg_marquardt.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>

namespace monocle {

bool NumericJacobian(const ResidualFunction& f, const Eigen::VectorXd& x, int m,
                     Eigen::MatrixXd* jacobian) {
  return NumericJacobianOf<Eigen::Dynamic, Eigen::Dynamic>(f, x, m, jacobian);
}

LevenbergMarquardtSummary MinimizeLevenbergMarquardt(const ResidualFunction& f, int m,
                                                     Eigen::VectorXd* x,
                                                     const LevenbergMarquardtOptions& options) {
  return MinimizeLevenbergMarquardtOf<Eigen::Dynamic, Eigen::Dynamic>(f, m, x, options);
}

Eigen::MatrixXd CovarianceFromJacobian(const Eigen::MatrixXd& jacobian,
                                       const Eigen::VectorXd& residuals) {
  const auto m = jacobian.rows(), n = jacobian.cols();
  if (m <= n) return {};
  const Eigen::MatrixXd jtj = jacobian.transpose() * jacobian;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(jtj);
  if (!lu.isInvertible()) return {};
  const double variance = residuals.squaredNorm() / static_cast<double>(m - n);
  return variance * lu.inverse();
}

}  // namespace monocle
