#include "service/geometry/levenberg_marquardt.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

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

}  // namespace
}  // namespace monocle
