#include "service/geometry/levenberg_marquardt.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <utility>

namespace monocle {
namespace {

TEST(LevenbergMarquardtTest, SolvesRosenbrock) {
  Eigen::VectorXd x(2);
  x << -1.2, 1.0;
  const auto summary = MinimizeLevenbergMarquardt(
      [](const Eigen::VectorXd& p, Eigen::VectorXd* r) {
        (*r)[0] = 10 * (p[1] - p[0] * p[0]);
        (*r)[1] = 1 - p[0];
        return true;
      },
      2, &x, {.max_iterations = 500});
  EXPECT_TRUE(summary.converged);
  EXPECT_NEAR(x[0], 1, 1e-9);
  EXPECT_NEAR(x[1], 1, 1e-9);
}

TEST(LevenbergMarquardtTest, CovarianceOfALineFitMatchesTheClosedForm) {
  // y = a + b t with residual noise; cov = s^2 (A^T A)^-1.
  const std::vector<double> t{0, 1, 2, 3, 4, 5}, y{0.1, 0.9, 2.1, 2.9, 4.2, 4.8};
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  const auto summary = MinimizeLevenbergMarquardt(
      [&](const Eigen::VectorXd& p, Eigen::VectorXd* r) {
        for (size_t i = 0; i < t.size(); ++i) (*r)[i] = p[0] + p[1] * t[i] - y[i];
        return true;
      },
      6, &x);
  Eigen::MatrixXd a(6, 2);
  for (int i = 0; i < 6; ++i) a.row(i) << 1, t[i];
  const double s2 = summary.residuals.squaredNorm() / 4;
  const Eigen::MatrixXd expected = s2 * (a.transpose() * a).inverse();
  EXPECT_LT((CovarianceFromJacobian(summary.jacobian, summary.residuals) - expected).norm(), 1e-8);
}

TEST(LevenbergMarquardtTest, RejectedRegionIsAvoided) {
  // Minimum at x = -1 lies in the forbidden half; the solver must stay at x > 0.
  Eigen::VectorXd x(1);
  x << 2.0;
  MinimizeLevenbergMarquardt(
      [](const Eigen::VectorXd& p, Eigen::VectorXd* r) {
        if (p[0] <= 0) return false;
        (*r)[0] = p[0] + 1;
        return true;
      },
      1, &x);
  EXPECT_GT(x[0], 0);
}

TEST(LevenbergMarquardtTest, FixedSizesSolveAsRunTimeSizes) {
  auto rosenbrock = [](const auto& p, auto* r) {
    (*r)[0] = 10 * (p[1] - p[0] * p[0]);
    (*r)[1] = 1 - p[0];
    return true;
  };
  Eigen::Vector2d fixed(-1.2, 1.0);
  Eigen::VectorXd dynamic = fixed;
  const auto fixed_summary =
      MinimizeLevenbergMarquardtOf<2, 2>(rosenbrock, 2, &fixed, {.max_iterations = 500});
  const auto dynamic_summary = MinimizeLevenbergMarquardt(
      [&](const Eigen::VectorXd& p, Eigen::VectorXd* r) { return rosenbrock(p, r); }, 2, &dynamic,
      {.max_iterations = 500});
  EXPECT_TRUE(fixed_summary.converged);
  EXPECT_TRUE(fixed_summary.started);
  EXPECT_TRUE(fixed_summary.has_jacobian);
  EXPECT_NEAR(fixed[0], 1, 1e-9);
  EXPECT_NEAR(fixed[1], 1, 1e-9);
  EXPECT_LT((fixed - dynamic).norm(), 1e-12);
  EXPECT_LT((fixed_summary.jacobian - dynamic_summary.jacobian).norm(), 1e-9);
}

// An exponential decay fitted to six noisy samples (amplitude 5, rate 0.3), counting the
// residual evaluations in `evaluations`.
auto DecayResiduals(int* evaluations) {
  return [evaluations](const Eigen::Vector2d& p, Eigen::Matrix<double, 6, 1>* r) {
    ++*evaluations;
    for (int i = 0; i < 6; ++i)
      (*r)[i] = p[0] * std::exp(-p[1] * i) - (5 * std::exp(-0.3 * i) + 0.02 * (i % 3 - 1));
    return true;
  };
}

// At the minimum, where no step can lower the cost any more, the solver stops once the damped
// step falls below the parameters' rounding, instead of trying ever more damped steps, up to
// 20, each a residual evaluation. (Without that stop this fit takes 33 trial steps.)
TEST(LevenbergMarquardtTest, StopsAtTheMinimumWithoutTryingStepsBelowRounding) {
  int evaluations = 0;
  const auto decay = DecayResiduals(&evaluations);
  Eigen::Vector2d x(3, 0.1);
  const auto summary = MinimizeLevenbergMarquardtOf<6, 2>(decay, 6, &x);
  EXPECT_TRUE(summary.converged);
  EXPECT_NEAR(x[0], 5, 0.05);
  EXPECT_NEAR(x[1], 0.3, 0.01);
  // The start, 2 x 2 evaluations per Jacobian (one per iteration and the final one), and the
  // trial steps: about two an iteration.
  const int trial_steps = evaluations - 1 - 4 * (summary.iterations + 1);
  EXPECT_LE(trial_steps, 2 * summary.iterations + 4) << summary.iterations << " iterations";
}

// Forward differences while iterating reach the same minimum with fewer evaluations, and the
// Jacobian returned is still the central one.
TEST(LevenbergMarquardtTest, ForwardDifferencesWhileIteratingReachTheSameMinimum) {
  int evaluations = 0;
  const auto decay = DecayResiduals(&evaluations);
  Eigen::Vector2d central(3, 0.1), forward = central;
  const auto central_summary = MinimizeLevenbergMarquardtOf<6, 2>(decay, 6, &central);
  const int central_evaluations = std::exchange(evaluations, 0);
  const auto forward_summary = MinimizeLevenbergMarquardtOf<6, 2>(
      decay, 6, &forward, {.forward_differences_while_iterating = true});
  EXPECT_TRUE(forward_summary.converged);
  EXPECT_LT((forward - central).norm(), 1e-9);
  EXPECT_LT(evaluations, central_evaluations);
  EXPECT_LT((forward_summary.jacobian - central_summary.jacobian).norm(), 1e-8);
}

}  // namespace
}  // namespace monocle
