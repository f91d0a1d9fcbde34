// Round trips of the map pose: a robot placed in a room, its camera's pose written in one
// corner's frame (as the corner solver reports it, at any ceiling distance), must come back to
// the same base pose in the map, at that corner, and only there when the room says so.
#include "service/geometry/map_pose.h"

#include "service/geometry/map_pose_tracker.h"

#include <gtest/gtest.h>

#include <random>

#include "service/geometry/corner_test_scenes.h"

namespace monocle {
namespace {

// An L-shaped room (counter-clockwise), arms 7 m and 5 m long, 3 m wide: five right-angle
// corners and one reflex vertex at (3, 3). No two corners have the same pair of wall lengths.
MapRoom LRoom() {
  MapRoom room;
  room.id = "L";
  room.outline_m = {{0, 0}, {7, 0}, {7, 3}, {3, 3}, {3, 5}, {0, 5}};
  room.ceiling_height_m = 2.6;
  room.corners = RightAngleCorners(room.id, room.outline_m, room.ceiling_height_m, 1e-3);
  return room;
}

MapRoom SquareRoom() {
  MapRoom room;
  room.id = "square";
  room.outline_m = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  room.ceiling_height_m = 2.5;
  room.corners = RightAngleCorners(room.id, room.outline_m, room.ceiling_height_m, 1e-3);
  return room;
}

// A camera 0.4 m above the floor, 0.1 m ahead of the base's origin, looking ahead and up,
// tilted `up_deg` from the vertical towards the robot's front.
RigidTransform Mount(double up_deg = 35) {
  const double t = up_deg * M_PI / 180;
  const Eigen::Vector3d z(std::sin(t), 0, std::cos(t));  // optical axis in the base frame
  const Eigen::Vector3d x(0, -1, 0);                     // image right = robot's right
  Eigen::Matrix3d r;
  r << x, z.cross(x), z;
  return {Eigen::Quaterniond(r), Eigen::Vector3d(0.1, 0, 0.4)};
}

RigidTransform BaseInMap(const BasePose2d& b) {
  return {Eigen::Quaterniond(Eigen::AngleAxisd(b.heading_rad, Eigen::Vector3d::UnitZ())),
          Eigen::Vector3d(b.x_m, b.y_m, 0)};
}

// The corner pose the solver would report for this robot pose, seen at `corner`, solved at
// ceiling distance `solved_at_m` (any: the solver's scale is the caller's guess).
CornerPose ObservedCornerPose(const MapCorner& corner, const BasePose2d& base,
                              const RigidTransform& mount, double solved_at_m) {
  const RigidTransform map_camera = Compose(BaseInMap(base), mount);
  Eigen::Isometry3d map_camera_iso = Eigen::Isometry3d::Identity();
  map_camera_iso.linear() = map_camera.rotation.toRotationMatrix();
  map_camera_iso.translation() = map_camera.translation;
  const Eigen::Isometry3d corner_camera = MapFromCorner(corner).inverse() * map_camera_iso;
  CornerPose p = PoseFromRotation(corner_camera.linear().transpose(), corner_camera.translation());
  const double scale = solved_at_m / p.z_m;
  p.x_m *= scale;
  p.y_m *= scale;
  p.z_m = solved_at_m;
  return p;
}

const MapPoseCandidate* Find(const MapLocation& l, const std::string& corner_id) {
  for (const auto& c : l.consistent)
    if (c.corner_id == corner_id) return &c;
  return nullptr;
}

Eigen::Matrix<double, 5, 5> SomeCovariance() {
  Eigen::Matrix<double, 5, 5> c = Eigen::Matrix<double, 5, 5>::Zero();
  c.diagonal() << 1e-4, 2e-4, 1e-5, 2e-5, 1e-5;
  c(0, 1) = c(1, 0) = 5e-5;
  return c;
}

TEST(RoomMapTest, AnLShapedRoomHasFiveCornersAndNoneAtItsReflexVertex) {
  const MapRoom room = LRoom();
  ASSERT_EQ(room.corners.size(), 5u);
  for (const auto& c : room.corners) {
    EXPECT_NE(c.position_m, Eigen::Vector2d(3, 3)) << c;
    const Eigen::Isometry3d t = MapFromCorner(c);
    EXPECT_NEAR(t.linear().determinant(), 1, 1e-12) << c;
    // A point just inside the corner's octant (x, y, z > 0) is inside the room, under the
    // ceiling.
    const Eigen::Vector3d p = t * Eigen::Vector3d(0.2, 0.3, 0.5);
    EXPECT_TRUE(InsideOutline(room.outline_m, p.head<2>())) << c;
    EXPECT_NEAR(p.z(), room.ceiling_height_m - 0.5, 1e-12);
  }
  EXPECT_TRUE(IsSimplePolygon(room.outline_m));
  EXPECT_FALSE(IsSimplePolygon({{0, 0}, {2, 2}, {2, 0}, {0, 2}}));  // a bow tie
  EXPECT_GT(SignedDoubleArea(room.outline_m), 0);
}

TEST(RoomMapTest, AWallHidesACornerAroundTheBend) {
  const MapRoom room = LRoom();
  const Eigen::Vector2d in_lower_arm(6, 1.5);
  for (const auto& c : room.corners) {
    const bool far_arm = c.position_m.y() > 4;  // (3, 5) and (0, 5)
    EXPECT_EQ(CornerInSight(room, c, in_lower_arm), !far_arm) << c;
  }
  EXPECT_FALSE(InsideOutline(room.outline_m, {4, 4}));
  EXPECT_TRUE(InsideOutline(room.outline_m, {1, 4.5}));
  EXPECT_FALSE(InsideOutline(room.outline_m, {0.05, 1}, 0.1));  // within the margin
}

TEST(MapPoseTest, EveryCornerGivesBackTheRobotsPoseAtAnyScale) {
  RoomMap map;
  map.rooms = {LRoom()};
  const RigidTransform mount = Mount();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> heading(-M_PI, M_PI);
  for (int i = 0; i < 50; ++i) {
    const BasePose2d truth{std::uniform_real_distribution<double>(0.5, 2.5)(rng),
                           std::uniform_real_distribution<double>(0.5, 2.5)(rng), heading(rng)};
    for (const auto& corner : map.rooms[0].corners) {
      const CornerPose seen = ObservedCornerPose(corner, truth, mount, 1.0 + i * 0.05);
      const MapPoseCandidate c = PoseInMapFromCorner(corner, mount, seen, SomeCovariance());
      EXPECT_NEAR(c.base.x_m, truth.x_m, 1e-9);
      EXPECT_NEAR(c.base.y_m, truth.y_m, 1e-9);
      EXPECT_NEAR(std::remainder(c.base.heading_rad - truth.heading_rad, 2 * M_PI), 0, 1e-9);
      EXPECT_NEAR(c.corner_pose.z_m, 2.6 - 0.4, 1e-12);
      EXPECT_NEAR(c.map_camera.translation.z(), 0.4, 1e-9);
    }
  }
}

TEST(MapPoseTest, HowFarTheEdgesAreSeenTellsTheLRoomsCornersApart) {
  const RigidTransform mount = Mount();
  RoomMap l_map;
  l_map.rooms = {LRoom()};
  const MapCorner& east = l_map.rooms[0].corners[1];
  ASSERT_EQ(east.position_m, Eigen::Vector2d(7, 0));
  // 4.4 m along the east corner's 7 m X wall, 1.5 m along its 3 m Y wall, facing it.
  const BasePose2d truth{2.5, 1.5, -0.2};
  const CornerPose seen = ObservedCornerPose(east, truth, mount, 2.2);
  // From the position alone, the corners at the origin (walls 5 m and 7 m) and at (3, 5)
  // (2 m and 3 m) fit too: the camera would stand in the room and see them.
  const MapLocation position_only = LocateInMap(l_map, mount, seen, SomeCovariance(), {});
  EXPECT_EQ(position_only.consistent.size(), 3u);
  ASSERT_NE(Find(position_only, east.id), nullptr);
  ASSERT_NE(Find(position_only, "L-0"), nullptr);
  ASSERT_NE(Find(position_only, "L-4"), nullptr);
  // The X edge seen 6.8 m out: only a wall of 7 m has it (a 5 m wall is allowed 25 % and
  // 0.3 m for how the end is measured).
  const MapLocation l =
      LocateInMap(l_map, mount, seen, SomeCovariance(), {}, SeenEdgeExtents{6.8, 1.0, 1.5});
  ASSERT_EQ(l.consistent.size(), 1u) << l.why_none;
  EXPECT_EQ(l.consistent[0].corner_id, east.id);
  EXPECT_NEAR(l.consistent[0].base.x_m, truth.x_m, 1e-9);
  // Seen further than any wall runs: nothing fits, and the reason says so.
  const MapLocation none =
      LocateInMap(l_map, mount, seen, SomeCovariance(), {}, SeenEdgeExtents{9.5, 1.0, 1.5});
  EXPECT_TRUE(none.consistent.empty());
  EXPECT_NE(none.why_none.find("further than its wall runs"), std::string::npos) << none.why_none;
}

TEST(MapPoseTest, TheSeenExtentOfAnEdgeIsWhereItsEndPixelsRayMeetsTheAxis) {
  CameraIntrinsics k;
  k.width_px = 1280;
  k.height_px = 1024;
  k.fx = k.fy = 1600;
  k.cx = 640;
  k.cy = 512;
  k.distortion[0] = -0.1;
  std::mt19937_64 rng(3);
  int checked = 0;
  for (int scene = 0; scene < 20; ++scene) {
    const CornerPose pose = *testing::RandomCornerPose(rng, k);
    for (int axis = 0; axis < 3; ++axis) {
      for (double along : {0.5, 1.0, 2.0}) {
        const Eigen::Vector3d p_camera = CornerToCamera(pose, along * Eigen::Vector3d::Unit(axis));
        if (p_camera.z() <= 0) continue;
        const Eigen::Vector2d px = ProjectToPixel(k, p_camera);
        if (px.x() < 0 || px.y() < 0 || px.x() > k.width_px || px.y() > k.height_px) continue;
        ++checked;
        EXPECT_NEAR(SeenEdgeExtent(k, pose, axis, px), along, 1e-7) << "axis " << axis << pose;
      }
    }
  }
  EXPECT_GE(checked, 60);
}

TEST(MapPoseTest, ASquareRoomIsAmbiguousUntilAPriorDecides) {
  const RigidTransform mount = Mount();
  // A square room looks the same from all four corners: ambiguous, all four candidates.
  RoomMap square;
  square.rooms = {SquareRoom()};
  const BasePose2d in_square{1.0, 1.4, 3.5};
  const MapCorner& origin = square.rooms[0].corners[0];
  const CornerPose seen = ObservedCornerPose(origin, in_square, mount, 2.1);
  const MapLocation s = LocateInMap(square, mount, seen, SomeCovariance(), {});
  EXPECT_TRUE(s.ambiguous());
  EXPECT_EQ(s.consistent.size(), 4u);
  ASSERT_NE(Find(s, origin.id), nullptr);
  // A prior near the truth picks the right one; a prior far from every candidate is reported
  // as contradicted and leaves the ambiguity.
  const MapLocation with_prior = LocateInMap(square, mount, seen, SomeCovariance(),
                                             MapPosePrior{BasePose2d{1.1, 1.3, 3.4}, 0.5, 0.5});
  ASSERT_EQ(with_prior.consistent.size(), 1u);
  EXPECT_EQ(with_prior.consistent[0].corner_id, origin.id);
  EXPECT_FALSE(with_prior.prior_contradicted);
  const MapLocation stale = LocateInMap(square, mount, seen, SomeCovariance(),
                                        MapPosePrior{BasePose2d{2, 2, 0.2}, 0.3, 0.3});
  EXPECT_TRUE(stale.prior_contradicted);
  EXPECT_TRUE(stale.ambiguous());
}

TEST(MapPoseTrackerTest, FollowsTheRobotRoundASquareRoomFromAKnownStart) {
  RoomMap square;
  square.rooms = {SquareRoom()};
  const RigidTransform mount = Mount();
  const MapCorner& origin = square.rooms[0].corners[0];
  MapPoseTracker tracker(square, mount);
  // Without a start the first frame is ambiguous (four look-alike corners), and nothing is
  // learnt from it.
  const BasePose2d start{1.0, 1.4, 3.5};
  MapLocation first =
      tracker.Next(ObservedCornerPose(origin, start, mount, 2.1), SomeCovariance(), {0, 0, 0});
  EXPECT_TRUE(first.ambiguous());
  EXPECT_FALSE(first.decided());
  EXPECT_FALSE(tracker.NextPrior().has_value());
  // Given the start, each decided pose is the next frame's prior: the robot drives 0.1 m a
  // frame and every frame is decided at the right corner.
  tracker.SetPose(start);
  for (int i = 1; i <= 5; ++i) {
    const BasePose2d at{1.0 + 0.1 * i, 1.4, 3.5};
    const MapLocation l =
        tracker.Next(ObservedCornerPose(origin, at, mount, 2.1), SomeCovariance(), {0, 0, 0});
    ASSERT_TRUE(l.decided()) << "frame " << i;
    EXPECT_EQ(l.consistent[0].corner_id, origin.id);
    EXPECT_NEAR(tracker.NextPrior()->base.x_m, at.x_m, 1e-9);
    EXPECT_DOUBLE_EQ(tracker.NextPrior()->max_distance_m, 0.5);
  }
  // Frames without a pose widen the gates by 0.1 m and 0.1 rad each.
  tracker.Missed();
  tracker.Missed();
  EXPECT_DOUBLE_EQ(tracker.NextPrior()->max_distance_m, 0.7);
  EXPECT_DOUBLE_EQ(tracker.NextPrior()->max_heading_rad, 0.7);
  // A view the prior contradicts (the robot was carried 2 m) is not decided, and the last
  // pose stays the prior, wider by one more frame.
  const MapLocation carried = tracker.Next(ObservedCornerPose(origin, {3.0, 3.2, 0.5}, mount, 2.1),
                                           SomeCovariance(), {0, 0, 0});
  EXPECT_TRUE(carried.prior_contradicted);
  EXPECT_FALSE(carried.decided());
  EXPECT_NEAR(tracker.NextPrior()->base.x_m, 1.5, 1e-9);
  EXPECT_DOUBLE_EQ(tracker.NextPrior()->max_distance_m, 0.8);
  // Gates past their caps (1.5 m, 1.2 rad) hold nothing the room does not: the robot is lost.
  for (int i = 0; i < 4; ++i) tracker.Missed();
  ASSERT_TRUE(tracker.NextPrior().has_value());
  EXPECT_DOUBLE_EQ(tracker.NextPrior()->max_heading_rad, 1.2);
  tracker.Missed();
  EXPECT_FALSE(tracker.NextPrior().has_value());
  tracker.SetPose(start);
  tracker.Forget();
  EXPECT_FALSE(tracker.NextPrior().has_value());
}

TEST(MapPoseTest, TheMountsLevelCorrectsATiltErrorAndFlagsAPoseThatTipsTheRobot) {
  RoomMap map;
  map.rooms = {LRoom()};
  const RigidTransform mount = Mount();
  const MapCorner& corner = map.rooms[0].corners[0];
  const BasePose2d truth{2.0, 1.5, -2.4};
  const CornerPose exact = ObservedCornerPose(corner, truth, mount, 2.2);
  // The truth is level: nothing to correct.
  Eigen::Matrix<double, 5, 5> cov = SomeCovariance();
  const LevelledCornerPose same = LevelWithMount(exact, cov, mount, 0.3 * M_PI / 180);
  EXPECT_NEAR(same.level_error_rad, 0, 1e-9);
  EXPECT_NEAR(same.pose.x_m, exact.x_m, 1e-9);
  EXPECT_NEAR(same.pose.tilt_rad, exact.tilt_rad, 1e-9);
  // A tilt error that moved x with it (x errs by 2 m per radian of tilt, as the covariance
  // says): the mount's level takes both back.
  const Eigen::Matrix<double, 5, 1> along =
      (Eigen::Matrix<double, 5, 1>() << 2, 0, 0, 1, 0).finished();
  cov = along * along.transpose() * 1e-4 + 1e-10 * Eigen::Matrix<double, 5, 5>::Identity();
  CornerPose tipped = exact;
  tipped.x_m += 2 * 0.01;
  tipped.tilt_rad += 0.01;
  const LevelledCornerPose fixed = LevelWithMount(tipped, cov, mount, 1e-6);
  EXPECT_NEAR(fixed.level_error_rad, 0.01, 1e-6);
  EXPECT_NEAR(fixed.pose.x_m, exact.x_m, 1e-4);
  EXPECT_NEAR(fixed.pose.tilt_rad, exact.tilt_rad, 1e-5);
  EXPECT_LT(fixed.covariance(0, 0), 1e-3 * cov(0, 0));
  // Tipped 2 degrees: placed (the map cannot tell it is wrong) but suspect, with the reason.
  tipped = exact;
  tipped.tilt_rad += 2 * M_PI / 180;
  const MapLocation l =
      LocateInMap(map, mount, tipped, SomeCovariance(), MapPosePrior{truth, 0.5, 0.5});
  EXPECT_TRUE(l.suspect);
  EXPECT_NEAR(l.level_error_rad, 2 * M_PI / 180, 1e-6);
  EXPECT_NE(l.suspect_reason.find("2.00 deg from level"), std::string::npos) << l.suspect_reason;
  EXPECT_FALSE(
      LocateInMap(map, mount, exact, SomeCovariance(), MapPosePrior{truth, 0.5, 0.5}).suspect);
}

TEST(MapPoseTrackerTest, RelocatesAfterThreeFramesTheRoomAloneDecides) {
  RoomMap map;
  map.rooms = {LRoom()};
  const RigidTransform mount = Mount();
  // A view of the L room that its shape alone decides (one candidate without a prior).
  const MapCorner* seen = nullptr;
  BasePose2d at;
  for (const MapCorner& c : map.rooms[0].corners) {
    for (double x = 0.8; x < 6.5 && seen == nullptr; x += 0.7) {
      const BasePose2d b{x, 1.5, std::atan2(c.position_m.y() - 1.5, c.position_m.x() - x)};
      const MapLocation l =
          LocateInMap(map, mount, ObservedCornerPose(c, b, mount, 2.2), SomeCovariance(), {});
      if (l.consistent.size() == 1 && l.consistent[0].corner_id == c.id) {
        seen = &c;
        at = b;
      }
    }
  }
  ASSERT_NE(seen, nullptr) << "no view of the L room is decided by its shape alone";
  // The tracker believes the robot is elsewhere (a stale prior): the first two such frames
  // are reported as contradicting it, the third relocates, the fourth is decided.
  MapPoseTracker tracker(map, mount);
  tracker.SetPose({at.x_m - 0.1, 4.5, at.heading_rad + 2.5});
  for (int frame = 0; frame < 4; ++frame) {
    const BasePose2d b{at.x_m + 0.02 * frame, at.y_m, at.heading_rad};
    const MapLocation l =
        tracker.Next(ObservedCornerPose(*seen, b, mount, 2.2), SomeCovariance(), {0, 0, 0});
    if (frame < 3) {
      EXPECT_TRUE(l.prior_contradicted) << "frame " << frame;
      EXPECT_FALSE(l.decided()) << "frame " << frame;
    } else {
      ASSERT_TRUE(l.decided());
      EXPECT_EQ(l.consistent[0].corner_id, seen->id);
      EXPECT_NEAR(l.consistent[0].base.x_m, b.x_m, 1e-6);
    }
  }
  // Frames that jump about (no two within the gates) never relocate.
  MapPoseTracker jumpy(map, mount);
  jumpy.SetPose({at.x_m - 0.1, 4.5, at.heading_rad + 2.5});
  for (int frame = 0; frame < 4; ++frame) {
    const BasePose2d b{at.x_m + (frame % 2 == 0 ? 0.0 : 0.8), at.y_m, at.heading_rad};
    jumpy.Next(ObservedCornerPose(*seen, b, mount, 2.2), SomeCovariance(), {0, 0, 0});
  }
  EXPECT_NEAR(jumpy.NextPrior()->base.y_m, 4.5, 1e-9) << "still the old prior";
}

TEST(MapPoseTest, NoCornerFitsAViewFromOutsideEveryRoom) {
  RoomMap map;
  map.rooms = {SquareRoom()};
  const RigidTransform mount = Mount();
  // A pose 6 m from the corner along both walls: outside the 4 m room from every corner.
  CornerPose far;
  far.x_m = 6;
  far.y_m = 6;
  far.z_m = 2.1;
  far.tilt_rad = 0.9;
  far.pan_rad = 0.8;
  const MapLocation l = LocateInMap(map, mount, far, SomeCovariance(), {});
  EXPECT_TRUE(l.consistent.empty());
  EXPECT_NE(l.why_none.find("outside the room"), std::string::npos) << l.why_none;
}

TEST(MapPoseTest, TheBaseCovarianceMatchesSampledCornerPoses) {
  RoomMap map;
  map.rooms = {LRoom()};
  const RigidTransform mount = Mount();
  const MapCorner& corner = map.rooms[0].corners[0];
  const CornerPose seen = ObservedCornerPose(corner, {1.5, 1.2, 0.7}, mount, 2.2);
  const Eigen::Matrix<double, 5, 5> cov = SomeCovariance();
  const MapPoseCandidate predicted = PoseInMapFromCorner(corner, mount, seen, cov);
  // Monte Carlo through the same placement: sample (x, y, pan, tilt, swing) from cov.
  const Eigen::Matrix<double, 5, 5> l = cov.llt().matrixL();
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0, 1);
  const int samples = 20000;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> values;
  for (int i = 0; i < samples; ++i) {
    Eigen::Matrix<double, 5, 1> e;
    for (int k = 0; k < 5; ++k) e[k] = n(rng);
    const Eigen::Matrix<double, 5, 1> d = l * e;
    const BasePose2d b = PoseInMapFromCorner(corner, mount, MovedBy(seen, d), cov).base;
    values.emplace_back(b.x_m, b.y_m,
                        predicted.base.heading_rad +
                            std::remainder(b.heading_rad - predicted.base.heading_rad, 2 * M_PI));
    mean += values.back() / samples;
  }
  Eigen::Matrix3d sampled = Eigen::Matrix3d::Zero();
  for (const auto& v : values) sampled += (v - mean) * (v - mean).transpose() / (samples - 1);
  EXPECT_TRUE(predicted.base_covariance == predicted.base_covariance.transpose())
      << "exactly symmetric, as published\n"
      << predicted.base_covariance;
  for (int r = 0; r < 3; ++r) {
    EXPECT_NEAR(std::sqrt(sampled(r, r)), std::sqrt(predicted.base_covariance(r, r)),
                0.05 * std::sqrt(predicted.base_covariance(r, r)))
        << "row " << r << "\nsampled\n"
        << sampled << "\npredicted\n"
        << predicted.base_covariance;
  }
}

}  // namespace
}  // namespace monocle
