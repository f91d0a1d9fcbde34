// Small dense Levenberg-Marquardt for problems with a handful of parameters.
// Pure geometry: Eigen only.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
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
  // Forward differences while iterating: half the residual evaluations of central ones, and
  // the steps still judged by the residuals themselves, so the minimum found is the same to
  // the tolerances above. The Jacobian returned (for a covariance) is central either way.
  bool forward_differences_while_iterating = false;
};

// M residuals, N parameters: fixed sizes (a hot fit of a known shape, no allocation) or
// Eigen::Dynamic.
template <int M, int N>
struct LevenbergMarquardtSummaryOf {
  bool started = false;  // the residuals were defined at the start
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0;  // 0.5 * |r|^2
  double final_cost = 0;
  // At the solution: the residuals (empty at run-time sizes if not started), and the Jacobian
  // by central differences, if it is defined there.
  Eigen::Matrix<double, M, N> jacobian;
  Eigen::Matrix<double, M, 1> residuals;
  bool has_jacobian = false;
};
using LevenbergMarquardtSummary = LevenbergMarquardtSummaryOf<Eigen::Dynamic, Eigen::Dynamic>;

// d(residuals)/dx at x (m residuals) by central differences, the solver's own; false where
// the model is undefined at a step. `f(x, &r)` as ResidualFunction, at the sizes M, N.
// With `at_x` (the residuals at x), forward differences instead: half the evaluations, error
// O(step) ~ 1e-6 relative.
template <int M, int N, typename Residuals>
bool NumericJacobianOf(const Residuals& f, const Eigen::Matrix<double, N, 1>& x, int m,
                       Eigen::Matrix<double, M, N>* jacobian,
                       const Eigen::Matrix<double, M, 1>* at_x = nullptr) {
  const auto n = x.size();
  jacobian->resize(m, n);
  Eigen::Matrix<double, M, 1> plus, minus;
  plus.resize(m);
  minus.resize(m);
  Eigen::Matrix<double, N, 1> xp = x, xm = x;  // (allocated once, not per column)
  for (Eigen::Index j = 0; j < n; ++j) {
    // Central differences: error O(step^2) ~ 1e-11 relative, enough for 1e-9 round trips.
    // Forward ones: O(step) ~ 1e-6, enough to choose a step the residuals then judge.
    const double step = 1e-6 * std::max(1.0, std::abs(x[j]));
    xp[j] = x[j] + step;
    if (at_x != nullptr) {
      if (!f(xp, &plus)) return false;
      jacobian->col(j) = (plus - *at_x) / step;
    } else {
      xm[j] = x[j] - step;
      if (!f(xp, &plus) || !f(xm, &minus)) return false;
      jacobian->col(j) = (plus - minus) / (2 * step);
    }
    xp[j] = xm[j] = x[j];
  }
  return true;
}

// Minimises 0.5 * |r(x)|^2 starting from *x (updated in place), m residuals. Numeric
// Jacobian by central differences with a step relative to each parameter's scale.
template <int M, int N, typename Residuals>
LevenbergMarquardtSummaryOf<M, N> MinimizeLevenbergMarquardtOf(
    const Residuals& f, int m, Eigen::Matrix<double, N, 1>* x,
    const LevenbergMarquardtOptions& options = {}) {
  using Vector = Eigen::Matrix<double, N, 1>;
  using Square = Eigen::Matrix<double, N, N>;
  LevenbergMarquardtSummaryOf<M, N> summary;
  Eigen::Matrix<double, M, 1> r, candidate_r;
  r.resize(m);
  candidate_r.resize(m);
  if (!f(*x, &r)) return summary;
  summary.started = true;
  double cost = 0.5 * r.squaredNorm();
  summary.initial_cost = cost;
  double lambda = options.initial_lambda;
  Eigen::Matrix<double, M, N> j;
  for (int it = 0; it < options.max_iterations; ++it) {
    summary.iterations = it + 1;
    if (!NumericJacobianOf<M, N>(f, *x, m, &j,
                                 options.forward_differences_while_iterating ? &r : nullptr))
      break;
    const Square jtj = j.transpose() * j;
    const Vector gradient = j.transpose() * r;
    bool improved = false;
    for (int attempt = 0; attempt < 20 && !improved; ++attempt) {
      Square damped = jtj;
      damped.diagonal() += lambda * jtj.diagonal().cwiseMax(1e-12);
      const Vector dx = damped.ldlt().solve(-gradient);
      // A step below the parameters' rounding cannot lower the cost: at the minimum (the
      // damping that grows with each rejected step only shrinks it further).
      if (dx.norm() < options.step_tolerance * (x->norm() + options.step_tolerance)) break;
      const Vector candidate = *x + dx;
      if (f(candidate, &candidate_r) && 0.5 * candidate_r.squaredNorm() < cost) {
        const double new_cost = 0.5 * candidate_r.squaredNorm();
        const double improvement = (cost - new_cost) / std::max(cost, 1e-300);
        *x = candidate;
        r = candidate_r;
        cost = new_cost;
        lambda = std::max(lambda / 10, 1e-12);
        improved = true;
        if (improvement < options.relative_cost_tolerance) summary.converged = true;
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
  summary.has_jacobian = NumericJacobianOf<M, N>(f, *x, m, &summary.jacobian);
  return summary;
}

// The same at run-time sizes, for a std::function.
LevenbergMarquardtSummary MinimizeLevenbergMarquardt(const ResidualFunction& f, int num_residuals,
                                                     Eigen::VectorXd* x,
                                                     const LevenbergMarquardtOptions& options = {});

// NumericJacobianOf at run-time sizes (central differences), for a std::function.
bool NumericJacobian(const ResidualFunction& f, const Eigen::VectorXd& x, int num_residuals,
                     Eigen::MatrixXd* jacobian);

// Covariance of the parameters from the Jacobian at the solution, scaling by the
// residual variance (sum r^2 / (m - n)). Empty (zero-size) matrix if J^T J is singular.
Eigen::MatrixXd CovarianceFromJacobian(const Eigen::MatrixXd& jacobian,
                                       const Eigen::VectorXd& residuals);

}  // namespace monocle
