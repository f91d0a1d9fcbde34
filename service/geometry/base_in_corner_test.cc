// Round trips of the base in the corner frame: a robot placed under a corner, its camera's
// corner pose written as the solver reports it, must give back the same base; its covariance
// must match the spread of bases from poses drawn from the corner pose's covariance; and the
// room map's placement at a corner at the origin must agree with it.
#include "service/geometry/base_in_corner.h"

#include <gtest/gtest.h>

#include <random>

#include "service/geometry/map_pose.h"
#include "service/geometry/robot_test_scenes.h"

namespace monocle {
namespace {

RigidTransform Mount() { return testing::MountLookingUp(35, 0); }

// The base upright on the floor `ceiling_m` below the corner (corner frame: Z down), at x, y,
// its +x axis `heading_rad` from the corner's X towards Y.
RigidTransform UprightBase(double x_m, double y_m, double heading_rad, double ceiling_m) {
  return {Eigen::Quaterniond(testing::CornerFromBase(heading_rad)),
          Eigen::Vector3d(x_m, y_m, ceiling_m)};
}

CornerPose SolvedPose(const RigidTransform& corner_base, const RigidTransform& mount) {
  const RigidTransform corner_camera = Compose(corner_base, mount);
  return PoseFromRotation(corner_camera.rotation.toRotationMatrix().transpose(),
                          corner_camera.translation);
}

Eigen::Matrix<double, 5, 5> PoseCovariance() {
  Eigen::Matrix<double, 5, 1> sigma;
  sigma << 0.02, 0.03, 0.01, 0.004, 0.006;
  Eigen::Matrix<double, 5, 5> c = sigma.cwiseAbs2().asDiagonal();
  c(0, 2) = c(2, 0) = 0.5 * sigma[0] * sigma[2];  // position and pan correlated
  return c;
}

TEST(BaseInCornerTest, GivesBackTheBaseItWasPlacedAt) {
  for (double heading_deg : {-170.0, -60.0, 0.0, 35.0, 120.0}) {
    const double heading = heading_deg * M_PI / 180;
    const RigidTransform base = UprightBase(1.7, 2.4, heading, 2.6);
    const BaseInCorner got =
        BaseInCornerFrame(SolvedPose(base, Mount()), Eigen::Matrix<double, 5, 5>::Zero(), Mount());
    EXPECT_NEAR(got.x_m(), 1.7, 1e-9) << heading_deg;
    EXPECT_NEAR(got.y_m(), 2.4, 1e-9) << heading_deg;
    EXPECT_NEAR(got.corner_base.translation.z(), 2.6, 1e-9) << heading_deg;
    EXPECT_NEAR(std::remainder(got.heading_rad - heading, 2 * M_PI), 0, 1e-9) << heading_deg;
    EXPECT_NEAR(got.corner_base.rotation.angularDistance(base.rotation), 0, 1e-9);
  }
}

TEST(BaseInCornerTest, CovarianceMatchesTheSpreadOfDrawnPoses) {
  const CornerPose pose = SolvedPose(UprightBase(2.0, 1.5, 0.7, 2.5), Mount());
  const Eigen::Matrix<double, 5, 5> covariance = PoseCovariance();
  const BaseInCorner reported = BaseInCornerFrame(pose, covariance, Mount());
  const Eigen::Matrix<double, 5, 5> l = covariance.llt().matrixL();
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  const int n = 20000;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    Eigen::Matrix<double, 5, 1> z;
    for (int k = 0; k < 5; ++k) z[k] = normal(rng);
    const BaseInCorner b =
        BaseInCornerFrame(MovedBy(pose, l * z), Eigen::Matrix<double, 5, 5>::Zero(), Mount());
    const Eigen::Vector3d d(b.x_m() - reported.x_m(), b.y_m() - reported.y_m(),
                            std::remainder(b.heading_rad - reported.heading_rad, 2 * M_PI));
    scatter += d * d.transpose();
  }
  const Eigen::Matrix3d empirical = scatter / n;
  for (int r = 0; r < 3; ++r) {
    EXPECT_NEAR(std::sqrt(empirical(r, r)) / reported.Sigma()[r], 1, 0.05) << r;
    for (int c = 0; c < 3; ++c) {
      const double scale = std::sqrt(reported.covariance(r, r) * reported.covariance(c, c));
      EXPECT_NEAR(empirical(r, c) / scale, reported.covariance(r, c) / scale, 0.05) << r << c;
    }
  }
  EXPECT_EQ(reported.covariance, reported.covariance.transpose());
}

// The room map's own path: a corner at the map's origin whose X runs along +x and whose Y
// along -y (so that X x Y points down) sees the same base, with y and heading mirrored.
TEST(BaseInCornerTest, AgreesWithTheMapsPlacementAtACornerAtTheOrigin) {
  const CornerPose pose = SolvedPose(UprightBase(1.2, 3.1, -0.4, 2.7), Mount());
  const Eigen::Matrix<double, 5, 5> covariance = PoseCovariance();
  const BaseInCorner in_corner = BaseInCornerFrame(pose, covariance, Mount());
  MapCorner corner;
  corner.x_edge = Eigen::Vector2d::UnitX();
  corner.y_edge = -Eigen::Vector2d::UnitY();
  corner.ceiling_height_m = 2.7;
  const MapPoseCandidate in_map = PoseInMapFromCorner(corner, Mount(), pose, covariance);
  EXPECT_NEAR(in_map.base.x_m, in_corner.x_m(), 1e-9);
  EXPECT_NEAR(in_map.base.y_m, -in_corner.y_m(), 1e-9);
  EXPECT_NEAR(in_map.base.heading_rad, -in_corner.heading_rad, 1e-9);
  const Eigen::Matrix3d mirror = Eigen::Vector3d(1, -1, -1).asDiagonal();
  EXPECT_TRUE((mirror * in_corner.covariance * mirror).isApprox(in_map.base_covariance, 1e-5))
      << in_corner.covariance << "\n\n"
      << in_map.base_covariance;
}

}  // namespace
}  // namespace monocle
