#include "service/geometry/corner_pose.h"

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

// The paper's (u, v) = (-x_n, y_n); forward-project a corner-frame point.
Eigen::Vector2d PaperImage(const CornerPose& pose, const Eigen::Vector3d& p) {
  const Eigen::Vector3d c = CornerToCamera(pose, p);
  return {-c.x() / c.z(), c.y() / c.z()};
}

TEST(CornerPoseTest, UprightCameraSeesTheVerticalEdgeRunDown) {
  // Swing 0, tilt 50 degrees, looking at the corner: the Z edge (down from the ceiling)
  // leaves the corner's image downwards (+y in OpenCV pixels), the ceiling is above it.
  const CornerPose pose{2.0, 1.5, 1.6, std::atan2(2.0, -1.5), Deg(50), 0};
  const Eigen::Vector3d corner = CornerToCamera(pose, Eigen::Vector3d::Zero());
  const Eigen::Vector3d down = CornerToCamera(pose, Eigen::Vector3d(0, 0, 0.3));
  const Eigen::Vector3d ceiling = CornerToCamera(pose, Eigen::Vector3d(0.5, 0.5, 0));
  EXPECT_GT(down.y() / down.z(), corner.y() / corner.z() + 0.01);
  EXPECT_LT(ceiling.y() / ceiling.z(), corner.y() / corner.z());
}

TEST(CornerPoseTest, RotationIsProperAndLooksUpAtTiltZero) {
  const CornerPose pose{1, 2, 1.5, 0.3, 0, 0};
  const Eigen::Matrix3d r = RotationCameraFromCorner(pose);
  EXPECT_NEAR((r * r.transpose() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-15);
  EXPECT_NEAR(r.determinant(), 1, 1e-15);
  // Tilt 0: the optical axis points up (-Z, since Z points down from the ceiling).
  EXPECT_NEAR((r.transpose() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(0, 0, -1)).norm(), 0,
              1e-15);
  // Tilt 90 degrees, pan 0: level, looking along +Y.
  const Eigen::Matrix3d level = RotationCameraFromCorner({1, 2, 1.5, 0, Deg(90), 0});
  EXPECT_NEAR((level.transpose() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(0, 1, 0)).norm(), 0,
              1e-15);
}

TEST(CornerPoseTest, EquationsFiveToTenAgreeWithForwardProjection) {
  std::mt19937_64 rng(86);
  const auto k = CornerCamera();
  for (int trial = 0; trial < 500; ++trial) {
    const auto pose = testing::RandomCornerPose(rng, k);
    ASSERT_TRUE(pose.has_value());
    const auto lines = PaperLineCoefficients(*pose);
    for (int axis = 0; axis < 3; ++axis) {
      for (double t : {0.0, 0.01, 0.1}) {
        const Eigen::Vector3d p = t * Eigen::Vector3d::Unit(axis);
        if (CornerToCamera(*pose, p).z() <= 0) continue;
        const Eigen::Vector2d uv = PaperImage(*pose, p);
        const double scale = std::sqrt(1 + lines[axis].b * lines[axis].b);
        EXPECT_NEAR((uv.x() + lines[axis].b * uv.y() + lines[axis].c) / scale, 0, 1e-9)
            << "axis " << axis << " " << *pose;
      }
    }
  }
}

TEST(CornerPoseTest, EquationFifteenAsPrintedIsMisprinted) {
  std::mt19937_64 rng(15);
  const auto k = CornerCamera();
  int printed_fails = 0, trials = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const auto pose = testing::RandomCornerPose(rng, k);
    const auto l = PaperLineCoefficients(*pose);
    const double b1 = l[0].b, c1 = l[0].c, b2 = l[1].b, c2 = l[1].c, b3 = l[2].b, c3 = l[2].c;
    const double a = c3 * c3 * b1 * b2 + c3 * c3 * c1 * c2 + c1 * c3 + c2 * c3 + (1 + b1 * b2);
    const double b_derived =
        c3 * c3 * (b1 + b2) - c1 * c3 * (b2 + b3) - c2 * c3 * (b3 + b1) - 2 * b3 * (1 + b1 * b2);
    const double b_printed =
        c3 * c3 * (b1 + b2) + c1 * c3 * (b2 + b3) - c2 * c3 * (b3 + b1) - 2 * b3 * (1 + b1 * b2);
    const double c = c3 * c3 + c3 * c3 * c1 * c2 + c1 * c3 * b2 * b3 + c2 * c3 * b1 * b3 +
                     (1 + b1 * b2) * b3 * b3;
    const double t = std::tan(pose->swing_rad);
    const double norm = std::abs(a) * t * t + std::abs(b_derived * t) + std::abs(c);
    EXPECT_NEAR((a * t * t + b_derived * t + c) / norm, 0, 1e-12) << *pose;
    if (std::abs(a * t * t + b_printed * t + c) / norm > 1e-6) ++printed_fails;
    ++trials;
  }
  EXPECT_GT(printed_fails, trials * 9 / 10);
}

TEST(CornerPoseTest, ClosedFormRecoversRandomPosesWithNoWrongBranch) {
  std::mt19937_64 rng(1986);
  const auto k = CornerCamera();
  std::array<int, 3> order{0, 1, 2};
  for (int trial = 0; trial < 3000; ++trial) {
    const auto pose = testing::RandomCornerPose(rng, k);
    ASSERT_TRUE(pose.has_value());
    // The detector does not know which ray is which axis: shuffle them.
    std::shuffle(order.begin(), order.end(), rng);
    const auto rays = testing::ExactRays(*pose, order);
    const auto best = SolveCornerClosedForm(rays, pose->z_m);
    ASSERT_TRUE(best.ok()) << best.error() << " " << *pose;
    ExpectPoseNear(best->pose, *pose, 1e-9);
    for (int r = 0; r < 3; ++r) EXPECT_EQ(best->axis_of_ray[r], order[r]);
    // Every other physically valid candidate that explains the rays is a cyclic relabelling
    // of the trihedron: looking down, or with a swing far outside an upright mount's.
    for (const auto& c : SolveCornerCandidates(rays, pose->z_m)) {
      if (!c.valid || c.residual > 1e-6) continue;
      const bool is_truth =
          std::abs(c.pose.x_m - pose->x_m) < 1e-6 && std::abs(c.pose.y_m - pose->y_m) < 1e-6;
      if (!is_truth && c.pose.tilt_rad < Deg(90)) {
        EXPECT_GT(std::abs(c.pose.swing_rad), Deg(50)) << c.pose << " vs truth " << *pose;
      }
    }
    if (::testing::Test::HasFailure()) break;
  }
}

TEST(CornerPoseTest, ImpossibleRaysAreRejected) {
  // Three rays 120 degrees apart, but the first and second point the same way: no corner.
  std::array<ObservedRay, 3> rays;
  rays[0].direction = Eigen::Vector2d(1, 0);
  rays[1].direction = Eigen::Vector2d(1, 0.001).normalized();
  rays[2].direction = Eigen::Vector2d(-1, 0);
  EXPECT_FALSE(SolveCornerClosedForm(rays, 2.0).ok());
}

}  // namespace
}  // namespace monocle
