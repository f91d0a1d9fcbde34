// Small dense Levenberg-Marquardt for problems with a handful of parameters.
// Pure geometry: Eigen only.
#pragma once

#include <Eigen/Core>
#include <functional>

namespace monocle {

// Fills `residuals` (size fixed by the problem) for parameters `x`; returns false where
// the model is undefined (e.g. a point behind the camera), which the solver treats as a
// rejected step.
using ResidualFunction = std::function<bool(const Eigen::VectorXd& x, Eigen::VectorXd* residuals)>;

struct LevenbergMarquardtOptions {
  int max_iterations = 100;
  double relative_cost_tolerance = 1e-15;  // stop when the cost improves less than this
  double step_tolerance = 1e-14;           // stop when |dx| < tol * (|x| + tol)
  double initial_lambda = 1e-3;
};

struct LevenbergMarquardtSummary {
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0;  // 0.5 * |r|^2
  double final_cost = 0;
  Eigen::MatrixXd jacobian;   // at the solution, numeric (central differences)
  Eigen::VectorXd residuals;  // at the solution
};

// Minimises 0.5 * |r(x)|^2 starting from *x (updated in place). Numeric Jacobian by
// central differences with a step relative to each parameter's scale.
LevenbergMarquardtSummary MinimizeLevenbergMarquardt(const ResidualFunction& f, int num_residuals,
                                                     Eigen::VectorXd* x,
                                                     const LevenbergMarquardtOptions& options = {});

// d(residuals)/dx at x (m residuals) by central differences, the solver's own; false where
// the model is undefined at a step.
bool NumericJacobian(const ResidualFunction& f, const Eigen::VectorXd& x, int num_residuals,
                     Eigen::MatrixXd* jacobian);

// Covariance of the parameters from the Jacobian at the solution, scaling by the
// residual variance (sum r^2 / (m - n)). Empty (zero-size) matrix if J^T J is singular.
Eigen::MatrixXd CovarianceFromJacobian(const Eigen::MatrixXd& jacobian,
                                       const Eigen::VectorXd& residuals);

}  // namespace monocle
