#include "service/geometry/floor_calibration.h"

#include <gtest/gtest.h>

#include <random>

#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

using testing::Deg;
using testing::PaperCamera;
using testing::RandomFloorPose;

// Inner corner (0, 0) placed so the board is centred where the optical axis meets the floor.
Eigen::Vector2d CenteredOrigin(const FloorPose& pose, int cols, int rows, double square) {
  const Eigen::Vector3d axis = RotationCameraFromRobot(pose).transpose() * Eigen::Vector3d::UnitZ();
  const double t = pose.height_m / -axis.z();
  const Eigen::Vector2d center = t * axis.head<2>();
  return center - BoardToRobot(pose.yaw_rad, Eigen::Vector2d::Zero(),
                               Eigen::Vector2d((cols - 1) * square / 2, (rows - 1) * square / 2))
                      .head<2>();
}

void ExpectPoseNear(const FloorPose& a, const FloorPose& b, double tol) {
  EXPECT_NEAR(a.height_m, b.height_m, tol * b.height_m) << a << " vs " << b;
  EXPECT_NEAR(a.pitch_rad, b.pitch_rad, tol) << a << " vs " << b;
  EXPECT_NEAR(a.yaw_rad, b.yaw_rad, tol) << a << " vs " << b;
  EXPECT_NEAR(a.roll_rad, b.roll_rad, tol) << a << " vs " << b;
}

TEST(FloorCalibrationTest, FullMethodRecoversRandomPosesFromExactCorners) {
  std::mt19937_64 rng(3);
  const CameraIntrinsics k = PaperCamera();
  for (int trial = 0; trial < 100; ++trial) {
    const FloorPose truth = RandomFloorPose(rng);
    const Eigen::Vector2d origin = CenteredOrigin(truth, 9, 6, 0.1);
    const auto board = ProjectBoard(k, truth, origin, 9, 6, 0.1);
    ASSERT_TRUE(board.ok());
    const auto cal = CalibrateFloor(k, *board, FloorCalibrationMethod::kFull);
    ASSERT_TRUE(cal.ok()) << cal.error() << " " << truth;
    ExpectPoseNear(cal->pose, truth, 1e-9);
    EXPECT_LT((cal->board_origin_robot_m - origin).norm(), 1e-8);
    EXPECT_LT(cal->rms_px, 1e-8);
  }
}

TEST(FloorCalibrationTest, PaperMethodRecoversRandomPosesWithoutRollFromExactCorners) {
  std::mt19937_64 rng(4);
  const CameraIntrinsics k = PaperCamera();
  for (int trial = 0; trial < 100; ++trial) {
    const FloorPose truth = RandomFloorPose(rng, /*with_roll=*/false);
    const auto board = ProjectBoard(k, truth, CenteredOrigin(truth, 9, 6, 0.1), 9, 6, 0.1);
    ASSERT_TRUE(board.ok());
    const auto cal = CalibrateFloor(k, *board, FloorCalibrationMethod::kPaper);
    ASSERT_TRUE(cal.ok()) << cal.error() << " " << truth;
    ExpectPoseNear(cal->pose, truth, 1e-9);
    EXPECT_LT(cal->rms_px, 1e-6);
  }
}

TEST(FloorCalibrationTest, PaperMethodIsBiasedByRollWhereFullIsNot) {
  const CameraIntrinsics k = PaperCamera();
  const FloorPose truth{1.0, Deg(110), Deg(2), Deg(3)};
  const auto board = ProjectBoard(k, truth, CenteredOrigin(truth, 9, 6, 0.1), 9, 6, 0.1);
  const auto paper = CalibrateFloor(k, *board, FloorCalibrationMethod::kPaper);
  const auto full = CalibrateFloor(k, *board, FloorCalibrationMethod::kFull);
  ASSERT_TRUE(paper.ok() && full.ok());
  EXPECT_GT(paper->rms_px, 1.0);  // the paper's model cannot explain a rolled camera
  ExpectPoseNear(full->pose, truth, 1e-9);
}

TEST(FloorCalibrationTest, CovarianceShrinksWithCornerNoise) {
  const CameraIntrinsics k = PaperCamera();
  const FloorPose truth{1.0, Deg(110), Deg(2), Deg(1)};
  auto board = *ProjectBoard(k, truth, CenteredOrigin(truth, 9, 6, 0.1), 9, 6, 0.1);
  std::mt19937_64 rng(5);
  auto sigma_h = [&](double noise_px) {
    auto noisy = board;
    std::normal_distribution<double> n(0, noise_px);
    for (auto& p : noisy.pixels) p += Eigen::Vector2d(n(rng), n(rng));
    return CalibrateFloor(k, noisy, FloorCalibrationMethod::kFull)->Sigma()[0];
  };
  const double small = sigma_h(0.05), large = sigma_h(0.5);
  EXPECT_GT(small, 0);
  EXPECT_NEAR(large / small, 10, 3);
}

TEST(FloorCalibrationTest, MonteCarloScatterMatchesReportedSigma) {
  const CameraIntrinsics k = PaperCamera();
  const FloorPose truth{1.2, Deg(115), Deg(-4), Deg(2)};
  const auto board = *ProjectBoard(k, truth, CenteredOrigin(truth, 9, 6, 0.1), 9, 6, 0.1);
  std::mt19937_64 rng(6);
  std::normal_distribution<double> n(0, 0.2);
  std::vector<double> heights;
  double reported = 0;
  for (int i = 0; i < 200; ++i) {
    auto noisy = board;
    for (auto& p : noisy.pixels) p += Eigen::Vector2d(n(rng), n(rng));
    const auto cal = CalibrateFloor(k, noisy, FloorCalibrationMethod::kFull);
    ASSERT_TRUE(cal.ok());
    heights.push_back(cal->pose.height_m);
    reported += cal->Sigma()[0] / 200;
  }
  double mean = 0, var = 0;
  for (double h : heights) mean += h / heights.size();
  for (double h : heights) var += (h - mean) * (h - mean) / (heights.size() - 1);
  EXPECT_NEAR(std::sqrt(var) / reported, 1.0, 0.25);
}

// Round trip for the intrinsics' share: refit the same (exact) corners with each intrinsic
// moved by +-delta; the pose moves as the reported cross-covariance says (cross = dq/dk * K).
TEST(FloorCalibrationTest, IntrinsicsSensitivityMatchesRefitting) {
  const CameraIntrinsics k = PaperCamera();
  const FloorPose truth{1.05, Deg(128), Deg(6), Deg(2)};
  const auto board = ProjectBoard(k, truth, CenteredOrigin(truth, 11, 8, 0.05), 11, 8, 0.05);
  ASSERT_TRUE(board.ok());
  const double sigma[kNumIntrinsicParams] = {3, 3, 2, 2, 0.01, 0.02, 5e-4, 5e-4, 0.02};
  IntrinsicsCovariance k_cov = IntrinsicsCovariance::Zero();
  for (int p = 0; p < kNumIntrinsicParams; ++p) k_cov(p, p) = sigma[p] * sigma[p];
  for (const auto method : {FloorCalibrationMethod::kFull, FloorCalibrationMethod::kPaper}) {
    const auto cal = CalibrateFloor(k, *board, method, k_cov);
    ASSERT_TRUE(cal.ok()) << cal.error();
    const int pose_params = method == FloorCalibrationMethod::kFull ? 4 : 3;
    for (int p = 0; p < kNumIntrinsicParams; ++p) {
      Eigen::Matrix<double, kNumIntrinsicParams, 1> delta =
          Eigen::Matrix<double, kNumIntrinsicParams, 1>::Zero();
      delta[p] = sigma[p] * 0.01;
      const auto plus = CalibrateFloor(PerturbIntrinsics(k, delta), *board, method);
      const auto minus = CalibrateFloor(PerturbIntrinsics(k, -delta), *board, method);
      ASSERT_TRUE(plus.ok() && minus.ok());
      const Eigen::Vector4d moved(
          plus->pose.height_m - minus->pose.height_m, plus->pose.pitch_rad - minus->pose.pitch_rad,
          plus->pose.yaw_rad - minus->pose.yaw_rad, plus->pose.roll_rad - minus->pose.roll_rad);
      const Eigen::Vector4d numeric = moved / (2 * delta[p]) * k_cov(p, p);
      const Eigen::Vector4d reported = cal->intrinsics_cross_covariance.col(p);
      for (int a = 0; a < pose_params; ++a) {
        EXPECT_NEAR(reported[a], numeric[a], 1e-3 * std::abs(numeric[a]) + 1e-12)
            << ToString(method) << " " << kIntrinsicParamNames[p] << " pose param " << a;
      }
    }
    // The total covariance grew by exactly the intrinsics' share.
    const Eigen::Matrix4d share = cal->covariance - cal->corner_covariance;
    EXPECT_GT(share.trace(), 0);
    EXPECT_TRUE(share.isApprox(share.transpose(), 1e-9));
  }
}

TEST(FloorCalibrationTest, DegenerateBoardIsAnError) {
  const CameraIntrinsics k = PaperCamera();
  BoardObservation board{3, 3, 0.1, std::vector<Eigen::Vector2d>(9, Eigen::Vector2d(600, 700))};
  EXPECT_FALSE(CalibrateFloor(k, board, FloorCalibrationMethod::kFull).ok());
  EXPECT_FALSE(CalibrateFloor(k, board, FloorCalibrationMethod::kPaper).ok());
}

}  // namespace
}  // namespace monocle
