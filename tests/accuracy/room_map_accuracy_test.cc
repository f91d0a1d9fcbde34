// The robot's pose in the map along a rendered drive through the example map's L-shaped hall
// (idl/examples/room_map.pbtxt, mount idl/examples/camera_mount.pbtxt), realistic look, a
// seed per frame: corners come into and out of view; every pose is attributed to the corner
// the camera actually measured, lies within the corner goals, and a view the room cannot
// decide is reported ambiguous.
//
// Ground truth is the trajectory itself: base poses built here with Eigen::AngleAxis, the mount
// from the file, rendered by camera/render/room_renderer (OpenCV's undistortion); the pipeline
// solves in a corner's frame and goes back to the map through service/geometry/map_pose.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include "camera/render/room_renderer.h"
#include "service/geometry/map_pose.h"
#include "service/geometry/map_pose_tracker.h"
#include "service/io/calibration_file.h"
#include "service/io/room_map_file.h"
#include "service/vision/corner_locator.h"

namespace monocle {
namespace {

constexpr double kDeg = M_PI / 180;

// Drive along straight legs, turning on the spot between them.
std::vector<BasePose2d> Drive() {
  std::vector<BasePose2d> out;
  BasePose2d at{1.4, 1.3, 0};
  auto go = [&](double x, double y, int frames) {
    const BasePose2d from = at;
    for (int i = 1; i <= frames; ++i) {
      const double f = static_cast<double>(i) / frames;
      // A gentle weave, as a real robot's path has.
      at = {from.x_m + f * (x - from.x_m), from.y_m + f * (y - from.y_m),
            from.heading_rad + 0.08 * std::sin(f * 2 * M_PI)};
      out.push_back(at);
    }
    at.heading_rad = from.heading_rad;
  };
  auto turn = [&](double to_deg, int frames) {
    const double from = at.heading_rad, to = to_deg * kDeg;
    for (int i = 1; i <= frames; ++i) {
      at.heading_rad = from + (to - from) * i / frames;
      out.push_back(at);
    }
  };
  turn(-20, 8);
  go(5.3, 1.5, 50);  // east along the long arm: the corners at (7, 0) and (7, 3) ahead
  turn(60, 20);      // round to the north: the corner at (7, 3), then the bend
  turn(180, 30);     // and west
  go(1.6, 1.6, 45);  // back west: the corners at (0, 0) and (0, 5)
  turn(90, 25);      // north, up the short arm
  go(1.5, 3.9, 35);  // the corners at (0, 5) and (3, 5) ahead
  turn(10, 25);
  return out;
}

RigidTransform Compose3(const BasePose2d& b, const RigidTransform& mount) {
  const RigidTransform base{
      Eigen::Quaterniond(Eigen::AngleAxisd(b.heading_rad, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(b.x_m, b.y_m, 0)};
  return {base.rotation * mount.rotation, base.rotation * mount.translation + base.translation};
}

// Where the camera sees a map corner (pixels), or nothing when behind it or off the image.
std::optional<Eigen::Vector2d> CornerInImage(const CameraIntrinsics& k,
                                             const RigidTransform& map_camera, const MapCorner& c) {
  const Eigen::Vector3d p_map(c.position_m.x(), c.position_m.y(), c.ceiling_height_m);
  const Eigen::Vector3d p_cam = map_camera.rotation.inverse() * (p_map - map_camera.translation);
  if (p_cam.z() <= 0.1) return std::nullopt;
  const Eigen::Vector2d px = ProjectToPixel(k, p_cam);
  if (px.x() < 0 || px.y() < 0 || px.x() >= k.width_px || px.y() >= k.height_px)
    return std::nullopt;
  return px;
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
}

struct Fixture {
  RoomMap map;
  RigidTransform mount;
  CameraIntrinsics k;  // idl/examples/wide_camera.pbtxt: f 700 px, the corners 2-6 m away
  const MapRoom& hall() const { return map.rooms[0]; }
};

Fixture Load() {
  Fixture f;
  auto map = LoadRoomMapFile(std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/room_map.pbtxt");
  EXPECT_TRUE(map.ok()) << map.error();
  f.map = *map;
  auto mount = LoadCameraMountFile(
      std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/camera_mount.pbtxt", f.map);
  EXPECT_TRUE(mount.ok()) << mount.error();
  f.mount = *mount;
  auto camera =
      LoadCalibrationFile(std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/wide_camera.pbtxt");
  EXPECT_TRUE(camera.ok()) << camera.error();
  f.k = camera->intrinsics;
  return f;
}

cv::Mat Render(const Fixture& f, const RigidTransform& map_camera, uint64_t seed) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = map_camera.rotation.toRotationMatrix();
  t.translation() = map_camera.translation;
  RoomScene scene;
  scene.realistic = RandomRealisticLook(seed, f.k);
  scene.seed = seed;
  return RenderRoomView(f.k, f.hall(), t, scene);
}

SeenEdgeExtents Extents(const CameraIntrinsics& k, const CornerLocation& loc) {
  return SeenEdgeExtentsAtLeast(k, loc.pose, loc.corner_px, loc.line_end_px);
}

// The seed of frame i is GetParam() + i: two sets of looks and noise. 40000 was the first
// run; 91000 the second, whose one unflagged pose 5 % off led to the level check.
class RoomDriveTest : public ::testing::TestWithParam<uint64_t> {};

TEST_P(RoomDriveTest, ADriveThroughTheLShapedHall) {
  const Fixture f = Load();
  ASSERT_EQ(f.hall().corners.size(), 5u);
  const std::vector<BasePose2d> drive = Drive();
  ASSERT_GE(drive.size(), 200u);
  const double ceiling_distance = f.hall().ceiling_height_m - f.mount.translation.z();
  // The user gives the start pose (a robot knows where it was parked); after that each
  // decided pose is the next frame's prior, its gates widening with every frame without one.
  MapPoseTracker tracker(f.map, f.mount);
  tracker.SetPose(drive.front());
  int in_view = 0, located = 0, published = 0, wrong_corner = 0, ambiguous = 0, suspect = 0;
  int covered_x = 0, covered_y = 0, unflagged_large = 0;
  std::vector<double> horizontal_rel, heading_deg, level_deg;
  std::vector<int> corners_used(f.hall().corners.size(), 0);
  for (size_t i = 0; i < drive.size(); ++i) {
    const BasePose2d& truth = drive[i];
    const RigidTransform map_camera = Compose3(truth, f.mount);
    bool any_in_view = false;
    for (const auto& c : f.hall().corners)
      any_in_view |= CornerInImage(f.k, map_camera, c).has_value();
    in_view += any_in_view;
    const cv::Mat image = Render(f, map_camera, GetParam() + i);
    const auto loc = LocateCorner(image, f.k, ceiling_distance);
    if (!loc) {
      tracker.Missed();
      continue;
    }
    ++located;
    const std::optional<MapPosePrior> prior = tracker.NextPrior();
    const MapLocation where = tracker.Next(loc->pose, loc->covariance, Extents(f.k, *loc));
    if (where.consistent.empty()) continue;
    if (!where.decided()) {
      // Reported: say what (a Y the room cannot place, or one that contradicts the last pose,
      // e.g. the reflex vertex at (3, 3), which also looks like a Y).
      std::cout << "frame " << i << " unresolved: " << where.consistent.size()
                << (where.prior_contradicted ? " candidate(s), contradicting the prior"
                                             : " candidates")
                << "\n";
      ++ambiguous;
      continue;  // reported, never guessed: nothing published
    }
    const MapPoseCandidate& got = where.consistent.front();
    ++published;
    suspect += loc->suspect || where.suspect;
    // The corner it measured: the map corner the true camera sees nearest the located one.
    const MapCorner* measured = nullptr;
    double nearest_px = 1e9;
    for (const auto& c : f.hall().corners) {
      const auto px = CornerInImage(f.k, map_camera, c);
      if (px && (*px - loc->corner_px).norm() < nearest_px) {
        nearest_px = (*px - loc->corner_px).norm();
        measured = &c;
      }
    }
    const bool right = measured != nullptr && nearest_px < 25 && measured->id == got.corner_id;
    if (!right) {
      ++wrong_corner;
      ADD_FAILURE() << "frame " << i << " " << truth << ": attributed to " << got.corner_id
                    << ", measured " << (measured ? measured->id : "none") << " (" << nearest_px
                    << " px); solved " << loc->pose << ", prior " << prior->base
                    << (where.prior_contradicted ? " contradicted" : "") << ", candidate "
                    << got.base;
      continue;
    }
    for (size_t c = 0; c < f.hall().corners.size(); ++c)
      corners_used[c] += f.hall().corners[c].id == got.corner_id;
    // Errors against the truth, relative to the camera's horizontal distance from its corner
    // (the corner goals' measure).
    const Eigen::Vector2d camera_truth = map_camera.translation.head<2>();
    const double distance = (camera_truth - measured->position_m).norm();
    const double error_m = (got.map_camera.translation.head<2>() - camera_truth).norm();
    horizontal_rel.push_back(error_m / distance);
    heading_deg.push_back(
        std::abs(std::remainder(got.base.heading_rad - truth.heading_rad, 2 * M_PI)) / kDeg);
    level_deg.push_back(where.level_error_rad / kDeg);
    if (error_m / distance > 0.05 && !loc->suspect && !where.suspect) {
      ++unflagged_large;
      std::cout << "frame " << i << " " << truth << ": " << 100 * error_m / distance << " % off at "
                << got.corner_id << ", not flagged; solved " << loc->pose << " rms " << loc->rms_px
                << " px\n";
    }
    covered_x += std::abs(got.base.x_m - truth.x_m) <= std::sqrt(got.base_covariance(0, 0));
    covered_y += std::abs(got.base.y_m - truth.y_m) <= std::sqrt(got.base_covariance(1, 1));
  }
  std::cout << "room drive: " << drive.size() << " frames, a corner in view in " << in_view
            << ", located " << located << ", published " << published << " (" << suspect
            << " suspect), ambiguous " << ambiguous << ", wrong corner " << wrong_corner
            << "\n  horizontal error / distance: median " << 100 * Percentile(horizontal_rel, 0.5)
            << " %, p95 " << 100 * Percentile(horizontal_rel, 0.95) << " %; heading error median "
            << Percentile(heading_deg, 0.5) << " deg, p95 " << Percentile(heading_deg, 0.95)
            << " deg; 1 sigma covers x " << covered_x << ", y " << covered_y << " of "
            << horizontal_rel.size() << "; unflagged > 5 %: " << unflagged_large
            << "\n  level error: median " << Percentile(level_deg, 0.5) << " deg, p95 "
            << Percentile(level_deg, 0.95) << " deg, max " << Percentile(level_deg, 1.0)
            << "\n  corners used:";
  for (size_t c = 0; c < corners_used.size(); ++c)
    std::cout << " " << f.hall().corners[c].id << " " << corners_used[c];
  std::cout << "\n";
  EXPECT_EQ(wrong_corner, 0);
  EXPECT_GE(published, in_view * 7 / 10) << "most views with a corner give a pose";
  int corners_seen = 0;
  for (int n : corners_used) corners_seen += n > 0;
  EXPECT_GE(corners_seen, 4) << "the drive sees most of the hall's corners";
  // The corner goals (median 0.3 %, p95 1 % of the distance) and the heading from tilt's goal.
  EXPECT_LE(Percentile(horizontal_rel, 0.5), 0.003);
  EXPECT_LE(Percentile(horizontal_rel, 0.95), 0.01);
  EXPECT_LE(unflagged_large, 0);
  // Regression gates, 2-3x above the measured (tests/accuracy/README.md).
  EXPECT_LE(Percentile(horizontal_rel, 0.5), 0.002);
  EXPECT_LE(Percentile(heading_deg, 0.5), 0.04);
  EXPECT_LE(Percentile(heading_deg, 0.95), 0.4);
  // The base's reported 1 sigma covers about 68 % of the actual errors. A little more than 68 %:
  // the level update assumes floors level to 0.3 deg (1 sigma) and the renders are exactly level,
  // so wherever it decides the tilt the sigma is on the safe side.
  const double n = static_cast<double>(horizontal_rel.size());
  EXPECT_GE(covered_x / n, 0.55);
  EXPECT_LE(covered_x / n, 0.85);
  EXPECT_GE(covered_y / n, 0.55);
  EXPECT_LE(covered_y / n, 0.85);
}

// Under ThreadSanitizer (MONOCLE_TSAN) the drive takes over ten minutes a seed set: the
// first set alone checks the same code for races.
#if defined(MONOCLE_TSAN)
INSTANTIATE_TEST_SUITE_P(Seeds, RoomDriveTest, ::testing::Values(40000u));
#else
INSTANTIATE_TEST_SUITE_P(Seeds, RoomDriveTest, ::testing::Values(40000u, 91000u));
#endif

TEST(RoomMapAccuracyTest,
     AViewTheHallCannotDecideIsReportedAmbiguousWithTheTruthAmongItsCandidates) {
  const Fixture f = Load();
  // Near the east end facing the corner at (7, 0), 1.3 m from both its walls: seen from close
  // to any right-angle corner the Y looks the same, and without a prior nothing in the room
  // tells them apart (every corner of the map is a candidate here).
  const BasePose2d truth{5.0, 1.3, -25 * kDeg};
  const RigidTransform map_camera = Compose3(truth, f.mount);
  const cv::Mat image = Render(f, map_camera, 777);
  const auto loc = LocateCorner(image, f.k, 2.2);
  ASSERT_TRUE(loc.ok()) << loc.error();
  const MapLocation where =
      LocateInMap(f.map, f.mount, loc->pose, loc->covariance, std::nullopt, Extents(f.k, *loc));
  ASSERT_TRUE(where.ambiguous()) << where.consistent.size() << " candidate(s)";
  bool truth_among = false;
  for (const auto& c : where.consistent) {
    std::cout << "candidate " << c.corner_id << " " << c.base << "\n";
    truth_among |= c.corner_id == "hall-1" &&
                   std::hypot(c.base.x_m - truth.x_m, c.base.y_m - truth.y_m) < 0.05;
  }
  EXPECT_TRUE(truth_among);
  // With the previous pose it is decided, and right.
  const MapLocation tracked =
      LocateInMap(f.map, f.mount, loc->pose, loc->covariance,
                  MapPosePrior{{4.9, 1.3, -0.4}, 0.5, 0.5}, Extents(f.k, *loc));
  ASSERT_EQ(tracked.consistent.size(), 1u);
  EXPECT_EQ(tracked.consistent[0].corner_id, "hall-1");
}

// Frame 5 of room_map_cli_test (its look: seed 3105), the noise drawn afresh 24 times. The
// edge X fades out 240 px from the corner (4 grey levels at noise 1.5); beyond, the second
// pass still finds the steepest noise near the first pass's line, and those far points have
// the most leverage on X's direction. Counted as measurements, they made the reported 1
// sigma 3x too small (covering 27 % of the errors, one 5.8 sigma off). Its direction is
// now only as certain as the points that follow each other from the corner make it.
TEST(RoomMapAccuracyTest, AnEdgeFadingOutIsNotCreditedWithItsFarPoints) {
  const Fixture f = Load();
  const BasePose2d truth{2.40, 1.35, -14 * M_PI / 180};
  const RigidTransform map_camera = Compose3(truth, f.mount);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = map_camera.rotation.toRotationMatrix();
  t.translation() = map_camera.translation;
  RoomScene scene;
  scene.realistic = RandomRealisticLook(3105, f.k);
  int poses = 0, covered = 0;
  double worst_sigmas = 0;
  for (uint64_t noise = 0; noise < 24; ++noise) {
    scene.seed = 5000 + noise;
    const auto loc = LocateCorner(RenderRoomView(f.k, f.hall(), t, scene), f.k, 2.2);
    if (!loc) continue;
    const MapLocation where =
        LocateInMap(f.map, f.mount, loc->pose, loc->covariance,
                    MapPosePrior{{2.2, 1.34, -15 * M_PI / 180}, 0.5, 0.5}, Extents(f.k, *loc));
    ASSERT_TRUE(where.decided()) << "noise " << noise;
    const MapPoseCandidate& got = where.consistent.front();
    ASSERT_EQ(got.corner_id, "hall-2");
    ++poses;
    // Along the view (map x) the error is largest: the far corner's range follows the tilt.
    const double sigmas = std::abs(got.base.x_m - truth.x_m) / std::sqrt(got.base_covariance(0, 0));
    covered += sigmas <= 1;
    worst_sigmas = std::max(worst_sigmas, sigmas);
  }
  std::cout << "  1 sigma covers " << covered << " of " << poses << " errors; the worst is "
            << worst_sigmas << " sigma\n";
  ASSERT_GE(poses, 20);
  EXPECT_GE(static_cast<double>(covered) / poses, 0.5);
  EXPECT_LT(worst_sigmas, 3.5);
}

}  // namespace
}  // namespace monocle
