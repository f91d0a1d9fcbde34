// The embedded simulated cameras `sim-corner`, `sim-corner-realistic` and `sim-floor`: cameras
// in one process
// through Aravis's in-process fake devices, no network and no other process.
#include <gtest/gtest.h>

#include "camera/aravis/aravis_source.h"
#include "camera/sim/sim_gv_camera.h"
#include "service/vision/chessboard.h"
#include "service/vision/corner_locator.h"

namespace monocle {
namespace {

AravisOptions Device(const std::string& id) {
  AravisOptions o;
  o.device = id;
  return o;
}

TEST(SimulatedCamerasTest, CornerAndFloorCamerasRunSideBySide) {
  auto corner = AravisSource::Open(Device("sim-corner"));
  ASSERT_TRUE(corner.ok()) << corner.error();
  auto floor = AravisSource::Open(Device("sim-floor"));
  ASSERT_TRUE(floor.ok()) << floor.error();
  const SimScenes* corner_truth = (*corner)->SimulatedScenes();
  const SimScenes* floor_truth = (*floor)->SimulatedScenes();
  ASSERT_NE(corner_truth, nullptr);
  ASSERT_NE(floor_truth, nullptr);

  for (int i = 0; i < 4; ++i) {
    auto c = (*corner)->Next(std::chrono::milliseconds(3000));
    ASSERT_TRUE(c.ok()) << c.error();
    EXPECT_EQ(cv::norm(c->grey, corner_truth->FrameFor(c->sequence), cv::NORM_INF), 0);
    auto f = (*floor)->Next(std::chrono::milliseconds(3000));
    ASSERT_TRUE(f.ok()) << f.error();
    EXPECT_EQ(cv::norm(f->grey, floor_truth->FrameFor(f->sequence), cv::NORM_INF), 0);
  }
  auto c = (*corner)->Next(std::chrono::milliseconds(3000));
  ASSERT_TRUE(c.ok());
  const CornerPose truth = corner_truth->CornerPoseFor(c->sequence);
  const auto pose = LocateCorner(c->grey, corner_truth->intrinsics(), truth.z_m);
  ASSERT_TRUE(pose.ok()) << pose.error();
  EXPECT_NEAR(pose->pose.x_m, truth.x_m, 0.005 * truth.x_m);
  EXPECT_NEAR(pose->pose.y_m, truth.y_m, 0.005 * truth.y_m);

  auto f = (*floor)->Next(std::chrono::milliseconds(3000));
  ASSERT_TRUE(f.ok());
  const auto board = DetectChessboard(f->grey, BoardSpec{11, 8, 0.05});
  ASSERT_TRUE(board.ok()) << board.error();
  const auto cal = CalibrateFloor(floor_truth->intrinsics(), *board, FloorCalibrationMethod::kFull);
  ASSERT_TRUE(cal.ok()) << cal.error();
  EXPECT_NEAR(cal->pose.height_m, floor_truth->floor_pose().height_m,
              0.002 * floor_truth->floor_pose().height_m);
  EXPECT_NEAR(cal->pose.pitch_rad, floor_truth->floor_pose().pitch_rad, 0.0005);
}

TEST(SimulatedCamerasTest, TheRealisticCornerCameraShowsAWhitePaintedRoom) {
  auto camera = AravisSource::Open(Device("sim-corner-realistic"));
  ASSERT_TRUE(camera.ok()) << camera.error();
  const SimScenes* truth = (*camera)->SimulatedScenes();
  ASSERT_NE(truth, nullptr);
  EXPECT_TRUE(truth->options().realistic);
  auto frame = (*camera)->Next(std::chrono::milliseconds(3000));
  ASSERT_TRUE(frame.ok()) << frame.error();
  EXPECT_EQ(cv::norm(frame->grey, truth->FrameFor(frame->sequence), cv::NORM_INF), 0);
  // Low contrast: the whole frame spans far fewer grey levels than the clean look's 100+.
  double lo = 0, hi = 0;
  cv::minMaxLoc(frame->grey, &lo, &hi);
  EXPECT_LT(hi - lo, 120);
  const CornerPose pose = truth->CornerPoseFor(frame->sequence);
  const auto got = LocateCorner(frame->grey, truth->intrinsics(), pose.z_m);
  ASSERT_TRUE(got.ok()) << got.error();
  EXPECT_NEAR(got->pose.x_m, pose.x_m, 0.01 * pose.x_m);
  EXPECT_NEAR(got->pose.y_m, pose.y_m, 0.01 * pose.y_m);
}

}  // namespace
}  // namespace monocle
