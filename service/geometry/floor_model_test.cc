#include "service/geometry/floor_model.h"

#include <gtest/gtest.h>

#include <random>

#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

using testing::Deg;
using testing::PaperCamera;
using testing::RandomFloorPose;

// A random floor point the camera sees, in the robot frame.
std::optional<Eigen::Vector3d> RandomVisibleFloorPoint(std::mt19937_64& rng,
                                                       const CameraIntrinsics& k,
                                                       const FloorPose& pose) {
  std::uniform_real_distribution<double> u(0, k.width_px - 1), v(0, k.height_px - 1);
  for (int attempt = 0; attempt < 100; ++attempt) {
    const auto p = FloorPointFromPixel(k, pose, Eigen::Vector2d(u(rng), v(rng)));
    if (p && p->head<2>().norm() < 30) return *p;
  }
  return std::nullopt;
}

TEST(FloorModelTest, ForwardThenMeasureFloorPointsRoundTrips) {
  std::mt19937_64 rng(1);
  const CameraIntrinsics k = PaperCamera();
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const FloorPose pose = RandomFloorPose(rng);
    const auto p = RandomVisibleFloorPoint(rng, k, pose);
    if (!p) continue;
    // Forward: project a ground-truth point; back: measure it.
    const Eigen::Vector3d truth(p->x() + 0.01, p->y() - 0.01, 0);
    const auto px = ProjectRobotPoint(k, pose, truth);
    ASSERT_TRUE(px.has_value());
    const auto m = MeasureFloorPoint(k, pose, {}, *px);
    ASSERT_TRUE(m.ok()) << m.error() << " " << pose;
    EXPECT_LT((m->p_robot_m - truth).norm(), 1e-9 * std::max(1.0, truth.norm())) << pose;
    ++checked;
  }
  EXPECT_GT(checked, 250);
}

TEST(FloorModelTest, ForwardThenMeasureBoxPointsRoundTrips) {
  std::mt19937_64 rng(2);
  const CameraIntrinsics k = PaperCamera();
  std::uniform_real_distribution<double> height_fraction(0.05, 0.9);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const FloorPose pose = RandomFloorPose(rng);
    const auto base = RandomVisibleFloorPoint(rng, k, pose);
    if (!base) continue;
    // A point on the vertical line above the floor point, below the camera's height.
    const Eigen::Vector3d top(base->x(), base->y(), height_fraction(rng) * pose.height_m);
    const auto floor_px = ProjectRobotPoint(k, pose, *base);
    const auto top_px = ProjectRobotPoint(k, pose, top);
    ASSERT_TRUE(floor_px && top_px);
    const auto m = MeasureVerticalPoint(k, pose, {}, *floor_px, *top_px);
    ASSERT_TRUE(m.ok()) << m.error();
    EXPECT_LT((m->p_robot_m - top).norm(), 1e-9 * std::max(1.0, top.norm())) << pose;
    ++checked;
  }
  EXPECT_GT(checked, 250);
}

// Issue 14: a paired point whose top is below its foot got a negative height without a word.
// Swapped pixels are refused, saying which; a point on the floor (top = foot, height 0 within
// the noise) still stands.
TEST(FloorModelTest, ATopBelowItsFootIsRefused) {
  const CameraIntrinsics k = PaperCamera();
  const FloorPose pose{1.05, 2.0595, 0.0698, 0.0262};
  MeasurementNoise noise;
  noise.pixel_sigma_px = 0.5;
  const Eigen::Vector3d foot(0.1, 2.0, 0), top(0.1, 2.0, 0.4);
  const auto foot_px = ProjectRobotPoint(k, pose, foot);
  const auto top_px = ProjectRobotPoint(k, pose, top);
  ASSERT_TRUE(foot_px && top_px);
  const auto right = MeasureVerticalPoint(k, pose, noise, *foot_px, *top_px);
  ASSERT_TRUE(right.ok()) << right.error();
  EXPECT_NEAR(right->p_robot_m.z(), 0.4, 1e-9);

  const auto swapped = MeasureVerticalPoint(k, pose, noise, *top_px, *foot_px);
  ASSERT_FALSE(swapped.ok());
  EXPECT_EQ(swapped.error().code, ErrorCode::kOutOfRange);
  EXPECT_NE(swapped.error().message.find("is below its foot"), std::string::npos)
      << swapped.error();
  EXPECT_NE(swapped.error().message.find("first"), std::string::npos);

  // Height zero, and a hair under it within the noise: measured, not refused.
  const auto on_floor = MeasureVerticalPoint(k, pose, noise, *foot_px, *foot_px);
  ASSERT_TRUE(on_floor.ok()) << on_floor.error();
  EXPECT_NEAR(on_floor->p_robot_m.z(), 0, 1e-9);
  const auto hair =
      MeasureVerticalPoint(k, pose, noise, *foot_px, *foot_px + Eigen::Vector2d(0, 0.3));
  ASSERT_TRUE(hair.ok()) << hair.error();
  EXPECT_LT(hair->p_robot_m.z(), 0);
}

TEST(FloorModelTest, PaperEquationFiveAsPrintedAgreesWithoutRoll) {
  // Eq. (5) typed in literally, independent of the implementation's rearrangement.
  const FloorPose pose{1.013, 1.8354, -0.0119, 0};
  CameraIntrinsics k = PaperCamera();
  k.distortion = {};
  const double h = pose.height_m, t = pose.pitch_rad;
  for (const Eigen::Vector2d& px :
       {Eigen::Vector2d(100, 900), Eigen::Vector2d(640, 700), Eigen::Vector2d(1200, 1000)}) {
    const double x1 = (px.x() - k.cx) / k.fx, y1 = (px.y() - k.cy) / k.fy;
    const double y_w = (h * std::sin(t) + y1 * h * std::cos(t)) / (y1 * std::sin(t) - std::cos(t));
    const double x_w = x1 * y_w * std::sin(t) - x1 * h * std::cos(t);
    const auto m = FloorPointFromPixel(k, pose, px);
    ASSERT_TRUE(m.ok());
    EXPECT_NEAR(m->x(), x_w, 1e-12);
    EXPECT_NEAR(m->y(), y_w, 1e-12);
  }
}

TEST(FloorModelTest, PixelAboveTheHorizonIsAnError) {
  const CameraIntrinsics k = PaperCamera();
  const FloorPose pose{1.0, Deg(95), 0, 0};  // looking almost level: top rows see the wall
  const auto m = MeasureFloorPoint(k, pose, {}, Eigen::Vector2d(640, 5));
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.error().code, ErrorCode::kOutOfRange);
  EXPECT_NE(m.error().message.find("horizon"), std::string::npos);
}

// Covariance propagation: compare the analytic Jacobians against finite differences of the
// whole measurement, by checking J * e_i for unit covariance in each input.
TEST(FloorModelTest, UncertaintyMatchesFiniteDifferences) {
  const CameraIntrinsics k = PaperCamera();
  const FloorPose pose{1.1, Deg(112), Deg(3), Deg(4)};
  const Eigen::Vector2d floor_px(300, 800), top_px(305, 600);
  auto measure = [&](const FloorPose& p, const Eigen::Vector2d& f, const Eigen::Vector2d& t) {
    return MeasureVerticalPoint(k, p, {}, f, t)->p_robot_m;
  };
  for (int param = 0; param < 4; ++param) {
    MeasurementNoise noise;
    noise.pose_covariance(param, param) = 1.0;
    const auto m = MeasureVerticalPoint(k, pose, noise, floor_px, top_px);
    ASSERT_TRUE(m.ok());
    const double step = 1e-6;
    FloorPose plus = pose, minus = pose;
    double* fields_plus[4] = {&plus.height_m, &plus.pitch_rad, &plus.yaw_rad, &plus.roll_rad};
    double* fields_minus[4] = {&minus.height_m, &minus.pitch_rad, &minus.yaw_rad, &minus.roll_rad};
    *fields_plus[param] += step;
    *fields_minus[param] -= step;
    const Eigen::Vector3d derivative =
        (measure(plus, floor_px, top_px) - measure(minus, floor_px, top_px)) / (2 * step);
    const Eigen::Matrix3d expected = derivative * derivative.transpose();
    EXPECT_LT((m->covariance - expected).norm(), 1e-6 * std::max(1.0, expected.norm()))
        << "param " << param;
  }
  MeasurementNoise pixel_noise;
  pixel_noise.pixel_sigma_px = 1.0;
  const auto m = MeasureVerticalPoint(k, pose, pixel_noise, floor_px, top_px);
  Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();
  const double step = 1e-4;
  for (int a = 0; a < 4; ++a) {
    Eigen::Vector2d df = Eigen::Vector2d::Zero(), dt = Eigen::Vector2d::Zero();
    (a < 2 ? df : dt)[a % 2] = step;
    const Eigen::Vector3d d =
        (measure(pose, floor_px + df, top_px + dt) - measure(pose, floor_px - df, top_px - dt)) /
        (2 * step);
    expected += d * d.transpose();
  }
  EXPECT_LT((m->covariance - expected).norm(), 1e-6 * expected.norm());
  // The floor-only measurement shares the same model.
  const auto f = MeasureFloorPoint(k, pose, pixel_noise, floor_px);
  EXPECT_NEAR(f->covariance(0, 0), expected(0, 0), 1e-6 * expected(0, 0));
  EXPECT_NEAR(f->covariance(1, 1), expected(1, 1), 1e-6 * expected(1, 1));
}

// The intrinsics' part, cross-covariance included: a random joint covariance of the pose and
// the intrinsics propagated analytically equals J * Sigma * J^T with J by finite differences.
TEST(FloorModelTest, IntrinsicsUncertaintyMatchesFiniteDifferences) {
  const CameraIntrinsics k = PaperCamera();
  const FloorPose pose{1.1, Deg(112), Deg(3), Deg(4)};
  const Eigen::Vector2d floor_px(300, 800), top_px(305, 600);
  constexpr int kParams = 4 + kNumIntrinsicParams;
  const double steps[kParams] = {1e-6, 1e-7, 1e-7, 1e-7, 1e-4, 1e-4, 1e-4,
                                 1e-4, 1e-7, 1e-7, 1e-8, 1e-8, 1e-7};
  Eigen::Matrix<double, 3, kParams> jacobian;
  for (int p = 0; p < kParams; ++p) {
    FloorPose plus = pose, minus = pose;
    Eigen::Matrix<double, kNumIntrinsicParams, 1> dk =
        Eigen::Matrix<double, kNumIntrinsicParams, 1>::Zero();
    if (p < 4) {
      double* fp[4] = {&plus.height_m, &plus.pitch_rad, &plus.yaw_rad, &plus.roll_rad};
      double* fm[4] = {&minus.height_m, &minus.pitch_rad, &minus.yaw_rad, &minus.roll_rad};
      *fp[p] += steps[p];
      *fm[p] -= steps[p];
    } else {
      dk[p - 4] = steps[p];
    }
    const auto a = MeasureVerticalPoint(PerturbIntrinsics(k, dk), plus, {}, floor_px, top_px);
    const auto b = MeasureVerticalPoint(PerturbIntrinsics(k, -dk), minus, {}, floor_px, top_px);
    ASSERT_TRUE(a.ok() && b.ok());
    jacobian.col(p) = (a->p_robot_m - b->p_robot_m) / (2 * steps[p]);
  }
  // A random covariance with the scales of a real calibration.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  const double scale[kParams] = {2e-3, 1e-3, 1e-3, 1e-3, 2,    2,   1.5,
                                 1.5,  4e-3, 8e-3, 3e-4, 3e-4, 5e-3};
  Eigen::Matrix<double, kParams, kParams> a;
  for (int i = 0; i < kParams; ++i)
    for (int j = 0; j < kParams; ++j) a(i, j) = normal(rng) * scale[i];
  const Eigen::Matrix<double, kParams, kParams> sigma = a * a.transpose() / kParams;
  MeasurementNoise noise;
  noise.pose_covariance = sigma.topLeftCorner<4, 4>();
  noise.pose_intrinsics_covariance = sigma.topRightCorner<4, kNumIntrinsicParams>();
  noise.intrinsics_covariance = sigma.bottomRightCorner<kNumIntrinsicParams, kNumIntrinsicParams>();
  const Eigen::Matrix3d expected = jacobian * sigma * jacobian.transpose();
  const auto m = MeasureVerticalPoint(k, pose, noise, floor_px, top_px);
  ASSERT_TRUE(m.ok());
  EXPECT_LT((m->covariance - expected).norm(), 1e-4 * expected.norm())
      << "analytic\n"
      << m->covariance << "\nnumeric\n"
      << expected;
  const auto f = MeasureFloorPoint(k, pose, noise, floor_px);
  ASSERT_TRUE(f.ok());
  const Eigen::Matrix2d expected_xy = expected.topLeftCorner(2, 2);
  const Eigen::Matrix2d got_xy = f->covariance.topLeftCorner(2, 2);
  EXPECT_LT((got_xy - expected_xy).norm(), 1e-4 * expected_xy.norm());
  // Without the cross term the answer differs: the test can tell it is there.
  MeasurementNoise no_cross = noise;
  no_cross.pose_intrinsics_covariance.setZero();
  const auto m2 = MeasureVerticalPoint(k, pose, no_cross, floor_px, top_px);
  EXPECT_GT((m2->covariance - expected).norm(), 1e-2 * expected.norm());
}

TEST(FloorModelTest, PaperSensitivityExampleOfSectionFour) {
  // Section 4: 0.5 degree of pitch error around 100 degrees moves y_w by about -42.6 mm
  // for a point with v - v0 near 500 px, dominated by the pitch term of eq. (16).
  CameraIntrinsics k = PaperCamera();
  k.fx = k.fy = 1600;
  k.distortion = {};
  const FloorPose pose{0.8746, Deg(100), 0, 0};
  MeasurementNoise noise;
  noise.pose_covariance(1, 1) = std::pow(Deg(0.5), 2);
  const auto m = MeasureFloorPoint(k, pose, noise, Eigen::Vector2d(k.cx + 300, k.cy + 500));
  ASSERT_TRUE(m.ok());
  // |dy| = h (1 + y1^2) / (y1 sin t - cos t)^2 * dtheta
  const double y1 = 500.0 / 1600, s = std::sin(Deg(100)), c = std::cos(Deg(100));
  const double expected = pose.height_m * (1 + y1 * y1) / std::pow(y1 * s - c, 2) * Deg(0.5);
  EXPECT_NEAR(m->Sigma().y(), expected, 1e-9);
}

}  // namespace
}  // namespace monocle
