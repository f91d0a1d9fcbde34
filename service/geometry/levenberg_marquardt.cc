#include "service/geometry/levenberg_marquardt.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>

namespace monocle {

bool NumericJacobian(const ResidualFunction& f, const Eigen::VectorXd& x, int m,
                     Eigen::MatrixXd* jacobian) {
  const int n = static_cast<int>(x.size());
  jacobian->resize(m, n);
  Eigen::VectorXd plus(m), minus(m), xp = x, xm = x;  // (allocated once, not per column)
  for (int j = 0; j < n; ++j) {
    // Central differences: error O(step^2) ~ 1e-11 relative, enough for 1e-9 round trips.
    const double step = 1e-6 * std::max(1.0, std::abs(x[j]));
    xp[j] = x[j] + step;
    xm[j] = x[j] - step;
    if (!f(xp, &plus) || !f(xm, &minus)) return false;
    jacobian->col(j) = (plus - minus) / (2 * step);
    xp[j] = xm[j] = x[j];
  }
  return true;
}

LevenbergMarquardtSummary MinimizeLevenbergMarquardt(const ResidualFunction& f, int m,
                                                     Eigen::VectorXd* x,
                                                     const LevenbergMarquardtOptions& options) {
  LevenbergMarquardtSummary summary;
  Eigen::VectorXd r(m);
  if (!f(*x, &r)) return summary;
  double cost = 0.5 * r.squaredNorm();
  summary.initial_cost = cost;
  double lambda = options.initial_lambda;
  Eigen::MatrixXd j;
  Eigen::VectorXd candidate_r(m);
  for (int it = 0; it < options.max_iterations; ++it) {
    summary.iterations = it + 1;
    if (!NumericJacobian(f, *x, m, &j)) break;
    const Eigen::MatrixXd jtj = j.transpose() * j;
    const Eigen::VectorXd gradient = j.transpose() * r;
    bool improved = false;
    for (int attempt = 0; attempt < 20 && !improved; ++attempt) {
      Eigen::MatrixXd damped = jtj;
      damped.diagonal() += lambda * jtj.diagonal().cwiseMax(1e-12);
      const Eigen::VectorXd dx = damped.ldlt().solve(-gradient);
      const Eigen::VectorXd candidate = *x + dx;
      if (f(candidate, &candidate_r) && 0.5 * candidate_r.squaredNorm() < cost) {
        const double new_cost = 0.5 * candidate_r.squaredNorm();
        const double improvement = (cost - new_cost) / std::max(cost, 1e-300);
        const bool small_step =
            dx.norm() < options.step_tolerance * (x->norm() + options.step_tolerance);
        *x = candidate;
        r = candidate_r;
        cost = new_cost;
        lambda = std::max(lambda / 10, 1e-12);
        improved = true;
        if (improvement < options.relative_cost_tolerance || small_step) summary.converged = true;
      } else {
        lambda *= 10;
      }
    }
    // No step improves the cost: we are at the minimum to machine precision.
    if (!improved) summary.converged = true;
    if (summary.converged) break;
  }
  summary.final_cost = cost;
  summary.residuals = r;
  NumericJacobian(f, *x, m, &summary.jacobian);
  return summary;
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
