#include "service/geometry/corner_pose_refinement.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <functional>
#include <iostream>
#include <random>

#include "service/geometry/corner_pose_test_helpers.h"
#include "service/geometry/corner_test_scenes.h"
#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

using testing::AngleDiff;
using testing::CornerCamera;
using testing::Deg;
using testing::ExpectPoseNear;

TEST(CornerPoseRefinementTest, RefinementConvergesToTruthAndCovarianceScalesWithNoise) {
  std::mt19937_64 rng(7);
  const auto k = CornerCamera();
  for (int trial = 0; trial < 100; ++trial) {
    const auto pose = testing::RandomCornerPose(rng, k);
    const auto rays = testing::ExactRays(*pose, {0, 1, 2});
    std::array<LineObservation, 3> lines;
    for (int a = 0; a < 3; ++a) {
      lines[a].direction = rays[a].direction;
      lines[a].centroid = rays[a].corner + 0.1 * rays[a].direction;
      lines[a].spread = 0.05;
      lines[a].num_points = 300;
    }
    CornerPose start = *pose;
    start.x_m *= 1.05;
    start.y_m *= 0.97;
    start.pan_rad += 0.02;
    start.tilt_rad -= 0.01;
    start.swing_rad += 0.01;
    const auto refined = RefineCornerPose(start, lines, {0, 1, 2}, 1600, 0.5);
    ASSERT_TRUE(refined.ok()) << refined.error();
    ExpectPoseNear(refined->pose, *pose, 1e-8);
    const auto twice = RefineCornerPose(start, lines, {0, 1, 2}, 1600, 1.0);
    EXPECT_NEAR(twice->covariance(0, 0) / refined->covariance(0, 0), 4.0, 1e-6);
    EXPECT_GT(refined->covariance(0, 0), 0);
  }
}

// Edge points scattered about a line as a real edge's are, summarised as the locator does.
LineObservation ObserveLine(const ObservedRay& ray, double t0, double t1, int count,
                            double sigma_px, double focal_px, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> along(t0, t1);
  std::normal_distribution<double> across(0, sigma_px / focal_px);
  const Eigen::Vector2d normal(-ray.direction.y(), ray.direction.x());
  std::vector<Eigen::Vector2d> points;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int i = 0; i < count; ++i) {
    points.push_back(ray.corner + along(rng) * ray.direction + across(rng) * normal);
    mean += points.back() / count;
  }
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : points) scatter += (p - mean) * (p - mean).transpose() / count;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  LineObservation line;
  line.centroid = mean;
  line.direction = eig.eigenvectors().col(1);
  if (line.direction.dot(ray.direction) < 0) line.direction = -line.direction;
  line.spread = std::sqrt(eig.eigenvalues()(1));
  line.num_points = count;
  line.scatter_sigma_px = std::sqrt(eig.eigenvalues()(0)) * focal_px;  // RMS off the fitted line
  return line;
}

using Lines = std::array<LineObservation, 3>;

struct Coverage {
  double with = 0, without = 0;  // fraction of errors within the reported 1 sigma
};

// 50 random poses, 20 noise draws each: `observe` draws the three lines, `strip` removes what
// is being tested from them. Both are fitted with the same pooled noise; the fit must not
// change, only the covariance. Coverage counts x and y: 2000 trials, standard error 1 %.
Coverage CompareCoverage(
    uint64_t seed,
    const std::function<Lines(const std::array<ObservedRay, 3>&, std::mt19937_64&)>& observe,
    const std::function<void(Lines*)>& strip) {
  std::mt19937_64 rng(seed);
  const auto k = CornerCamera();
  constexpr double kFocal = 1600;
  int covered_with = 0, covered_without = 0, trials = 0;
  for (int pose_index = 0; pose_index < 50; ++pose_index) {
    const auto pose = testing::RandomCornerPose(rng, k);
    EXPECT_TRUE(pose.has_value());
    if (!pose) return {};
    const auto rays = testing::ExactRays(*pose, {0, 1, 2});
    for (int repeat = 0; repeat < 20; ++repeat) {
      Lines lines = observe(rays, rng);
      double pooled2 = 0;
      int total = 0;
      for (const auto& l : lines) {
        pooled2 += l.scatter_sigma_px * l.scatter_sigma_px * l.num_points;
        total += l.num_points;
      }
      const double pooled_px = std::sqrt(pooled2 / total);
      const auto with = RefineCornerPose(*pose, lines, {0, 1, 2}, kFocal, pooled_px);
      strip(&lines);
      const auto without = RefineCornerPose(*pose, lines, {0, 1, 2}, kFocal, pooled_px);
      EXPECT_TRUE(with.ok() && without.ok());
      if (!with.ok() || !without.ok()) return {};
      EXPECT_NEAR(with->pose.x_m, without->pose.x_m, 1e-12) << "only the covariance differs";
      // Exactly symmetric, as published (G D G^T rounds its two triangles differently).
      EXPECT_TRUE(with->covariance == with->covariance.transpose()) << with->covariance;
      const Eigen::Vector2d error(with->pose.x_m - pose->x_m, with->pose.y_m - pose->y_m);
      for (int i = 0; i < 2; ++i) {
        covered_with += std::abs(error[i]) < std::sqrt(with->covariance(i, i));
        covered_without += std::abs(error[i]) < std::sqrt(without->covariance(i, i));
        ++trials;
      }
    }
  }
  return {static_cast<double>(covered_with) / trials,
          static_cast<double>(covered_without) / trials};
}

// One long, crisp edge and two short, faint ones (a corner near the image's border in a
// white room): the fit weights all points alike, so the pooled noise would credit the short
// edges with the long one's precision. With each line's own scatter propagated, the reported
// 1 sigma covers ~68 % of the actual errors; with the pooled noise alone it covers far fewer.
TEST(CornerPoseRefinementTest, CovarianceFollowsEachLinesOwnScatter) {
  constexpr double kFocal = 1600;
  const Coverage c = CompareCoverage(
      11,
      [&](const std::array<ObservedRay, 3>& rays, std::mt19937_64& rng) {
        return Lines{ObserveLine(rays[0], 0.02, 0.40, 300, 0.1, kFocal, rng),  // 32-640 px
                     ObserveLine(rays[1], 0.01, 0.06, 40, 0.4, kFocal, rng),   // 16-96 px
                     ObserveLine(rays[2], 0.01, 0.06, 40, 0.4, kFocal, rng)};
      },
      [](Lines* lines) {
        for (auto& l : *lines) l.scatter_sigma_px = 0;
      });
  std::cout << "1 sigma covers " << 100 * c.with << " % with each line's own scatter, "
            << 100 * c.without << " % with the pooled one\n";
  EXPECT_NEAR(c.with, 0.683, 0.05);
  EXPECT_LT(c.without, 0.55);
}

// A line whose direction is three times less certain than its points' spread says (a faint
// edge whose far points lean towards where the search started): with direction_sigma_scale
// the reported 1 sigma covers ~68 % of the errors again, without it far fewer.
TEST(CornerPoseRefinementTest, CovarianceWidensWithALinesUncertainDirection) {
  constexpr double kFocal = 1600, kDirectionScale = 3;
  const Coverage c = CompareCoverage(
      12,
      [&](const std::array<ObservedRay, 3>& rays, std::mt19937_64& rng) {
        Lines lines{ObserveLine(rays[0], 0.02, 0.40, 300, 0.1, kFocal, rng),
                    ObserveLine(rays[1], 0.01, 0.30, 150, 0.8, kFocal, rng),
                    ObserveLine(rays[2], 0.02, 0.30, 150, 0.3, kFocal, rng)};
        // Line 1's direction turned about its centroid by the extra error.
        LineObservation& faint = lines[1];
        const double nominal =
            faint.scatter_sigma_px / (kFocal * std::sqrt(faint.num_points) * faint.spread);
        std::normal_distribution<double> extra(
            0, nominal * std::sqrt(kDirectionScale * kDirectionScale - 1));
        faint.direction = Eigen::Rotation2Dd(extra(rng)) * faint.direction;
        faint.direction_sigma_scale = kDirectionScale;
        return lines;
      },
      [](Lines* lines) { (*lines)[1].direction_sigma_scale = 1; });
  std::cout << "1 sigma covers " << 100 * c.with << " % with the direction's scale, "
            << 100 * c.without << " % without\n";
  EXPECT_NEAR(c.with, 0.683, 0.05);
  EXPECT_LT(c.without, 0.55);
}

// The position's variance is split over the lines: each line's part is what that line's
// noise alone does to (x, y). Checked by sampling: in each draw the other two lines are put
// back on the truth (their summaries otherwise kept, so the fit weighs them alike), and the
// squared error that is left averages the line's reported part. The parts add up to the
// covariance's var(x) + var(y).
TEST(CornerPoseRefinementTest, EachLinesPartOfThePositionVarianceIsWhatItsNoiseDoes) {
  constexpr double kFocal = 1600, kLineBiasPx = 0.02;
  const auto k = CornerCamera();
  std::mt19937_64 rng(13);
  std::array<double, 3> ratio_sum{}, reported_m2{};
  int draws = 0;
  for (int pose_index = 0; pose_index < 40; ++pose_index) {
    const auto pose = testing::RandomCornerPose(rng, k);
    ASSERT_TRUE(pose.has_value());
    const auto rays = testing::ExactRays(*pose, {0, 1, 2});
    for (int repeat = 0; repeat < 25; ++repeat, ++draws) {
      // A long crisp edge, a short faint one, a middling one; each with its points' true
      // scatter, so that what is checked is the split, not how well 40 points measure it.
      constexpr std::array<double, 3> kSigmaPx{0.1, 0.4, 0.25};
      Lines noisy{ObserveLine(rays[0], 0.02, 0.40, 300, kSigmaPx[0], kFocal, rng),
                  ObserveLine(rays[1], 0.01, 0.06, 40, kSigmaPx[1], kFocal, rng),
                  ObserveLine(rays[2], 0.02, 0.20, 100, kSigmaPx[2], kFocal, rng)};
      for (int line = 0; line < 3; ++line) noisy[line].scatter_sigma_px = kSigmaPx[line];
      // The line bias is a whole line's offset: draw it too, as the model assumes.
      std::normal_distribution<double> bias(0, kLineBiasPx / kFocal);
      for (int line = 0; line < 3; ++line) {
        Lines only = noisy;
        for (int other = 0; other < 3; ++other) {
          const Eigen::Vector2d d = rays[other].direction;
          if (other == line) {
            only[other].centroid += bias(rng) * Eigen::Vector2d(-d.y(), d.x());
            continue;
          }
          only[other].centroid =
              rays[other].corner + d * d.dot(noisy[other].centroid - rays[other].corner);
          only[other].direction = d;
        }
        const auto got = RefineCornerPose(*pose, only, {0, 1, 2}, kFocal, 0.2, kLineBiasPx);
        ASSERT_TRUE(got.ok()) << got.error();
        const double squared_error =
            std::pow(got->pose.x_m - pose->x_m, 2) + std::pow(got->pose.y_m - pose->y_m, 2);
        ratio_sum[line] += squared_error / got->horizontal_variance_m2_by_line[line];
        reported_m2[line] += got->horizontal_variance_m2_by_line[line];
        const auto& parts = got->horizontal_variance_m2_by_line;
        const double horizontal = got->covariance(0, 0) + got->covariance(1, 1);
        EXPECT_NEAR(parts[0] + parts[1] + parts[2], horizontal, 1e-9 * horizontal);
      }
    }
  }
  for (int line = 0; line < 3; ++line) {
    // Per draw, squared error / reported part averages 1 where the part is honest; over 1000
    // draws that mean scatters 3-5 %. (The plain mean squared error is ruled by the few
    // poses where the position is weakest, and scatters far more.)
    std::cout << "line " << line << ": squared error / reported part averages "
              << ratio_sum[line] / draws << ", part " << reported_m2[line] / draws << " m^2\n";
    EXPECT_NEAR(ratio_sum[line] / draws, 1.0, 0.15) << "line " << line;
  }
  // The short, faint edge limits the position most.
  EXPECT_GT(reported_m2[1], reported_m2[2]);
  EXPECT_GT(reported_m2[2], reported_m2[0]);
}

}  // namespace
}  // namespace monocle
