// Round trips of every conversion between monocle's values and their DDS samples, and the
// refusals of malformed columns.
#include "idl/protocol/convert.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace monocle::wire {
namespace {

TEST(ConvertTest, PoseRoundTrip) {
  Pose p;
  p.camera_id = "ceiling";
  p.frame_id = "corner";
  p.frame_sequence = 42;
  p.capture_time_ns = 1'700'000'000'123'456'789;
  p.camera_clock = true;
  p.valid = true;
  p.x_m = 1.5;
  p.y_m = -2.25;
  p.z_m = 2.7;
  p.pan_rad = 0.1;
  p.tilt_rad = -0.6;
  p.swing_rad = 0.05;
  p.quaternion_wxyz = {0.9, 0.1, -0.3, 0.2};
  for (size_t i = 0; i < 25; ++i) p.covariance[i] = static_cast<double>(i) * 0.5;
  p.corner_px = {640.5, 100.25};
  p.rms_px = 0.3;
  p.processing_ns = 1234567;
  p.tracked = true;
  p.suspect = true;
  p.suspect_reason = "one edge is short";
  p.map_status = MapStatus::kLocated;
  p.map_corner = "hall-1";
  p.map_room = "hall";
  p.map_x_m = 3.25;
  p.map_y_m = 1.5;
  p.map_heading_rad = -0.4;
  for (size_t i = 0; i < 9; ++i) p.map_covariance[i] = static_cast<double>(i) * 0.25;
  p.map_camera_position_m = {3.3, 1.45, 0.4};
  p.map_camera_quaternion_wxyz = {0.7, 0.1, 0.5, -0.3};
  p.map_candidates = 1;
  p.map_reason = "";
  p.level_error_rad = 0.004;
  p.level_sigma_rad = 0.0017;
  p.base_known = true;
  p.base_position_m = {1.4, -2.3, 3.1};
  p.base_quaternion_wxyz = {0.5, -0.5, 0.5, 0.5};
  p.base_heading_rad = 1.2;
  for (size_t i = 0; i < 9; ++i) p.base_covariance[i] = static_cast<double>(i) * 0.125;
  monocle_msgs_msg_dds__CornerPose_ s;
  ToSample(p, &s);
  // ROS's quaternion order is x, y, z, w.
  EXPECT_EQ(s.orientation.w, 0.9);
  EXPECT_EQ(s.orientation.x, 0.1);
  EXPECT_EQ(s.header.stamp.sec, 1'700'000'000);
  EXPECT_EQ(s.header.stamp.nanosec, 123'456'789u);
  const Pose back = FromSample(s);
  EXPECT_EQ(back.camera_id, p.camera_id);
  EXPECT_EQ(back.frame_id, p.frame_id);
  EXPECT_EQ(back.frame_sequence, p.frame_sequence);
  EXPECT_EQ(back.capture_time_ns, p.capture_time_ns);
  EXPECT_EQ(back.camera_clock, p.camera_clock);
  EXPECT_EQ(back.valid, p.valid);
  EXPECT_EQ(back.x_m, p.x_m);
  EXPECT_EQ(back.y_m, p.y_m);
  EXPECT_EQ(back.z_m, p.z_m);
  EXPECT_EQ(back.pan_rad, p.pan_rad);
  EXPECT_EQ(back.tilt_rad, p.tilt_rad);
  EXPECT_EQ(back.swing_rad, p.swing_rad);
  EXPECT_EQ(back.quaternion_wxyz, p.quaternion_wxyz);
  EXPECT_EQ(back.covariance, p.covariance);
  EXPECT_EQ(back.corner_px, p.corner_px);
  EXPECT_EQ(back.rms_px, p.rms_px);
  EXPECT_EQ(back.processing_ns, p.processing_ns);
  EXPECT_EQ(back.tracked, p.tracked);
  EXPECT_EQ(back.suspect, p.suspect);
  EXPECT_EQ(back.suspect_reason, p.suspect_reason);
  EXPECT_EQ(s.map_status, monocle_msgs_msg_dds__MAP_LOCATED);
  EXPECT_EQ(s.map_camera.orientation.w, 0.7) << "ROS order x, y, z, w";
  EXPECT_EQ(s.map_camera.orientation.x, 0.1);
  EXPECT_EQ(s.map_camera.orientation.z, -0.3);
  EXPECT_EQ(back.map_status, p.map_status);
  EXPECT_EQ(back.map_corner, p.map_corner);
  EXPECT_EQ(back.map_room, p.map_room);
  EXPECT_EQ(back.map_x_m, p.map_x_m);
  EXPECT_EQ(back.map_y_m, p.map_y_m);
  EXPECT_EQ(back.map_heading_rad, p.map_heading_rad);
  EXPECT_EQ(back.map_covariance, p.map_covariance);
  EXPECT_EQ(back.map_camera_position_m, p.map_camera_position_m);
  EXPECT_EQ(back.map_camera_quaternion_wxyz, p.map_camera_quaternion_wxyz);
  EXPECT_EQ(back.map_candidates, p.map_candidates);
  EXPECT_EQ(back.level_error_rad, p.level_error_rad);
  EXPECT_EQ(back.level_sigma_rad, p.level_sigma_rad);
  EXPECT_EQ(s.base.orientation.w, 0.5) << "ROS order x, y, z, w";
  EXPECT_EQ(s.base.orientation.x, -0.5);
  EXPECT_EQ(back.base_known, p.base_known);
  EXPECT_EQ(back.base_position_m, p.base_position_m);
  EXPECT_EQ(back.base_quaternion_wxyz, p.base_quaternion_wxyz);
  EXPECT_EQ(back.base_heading_rad, p.base_heading_rad);
  EXPECT_EQ(back.base_covariance, p.base_covariance);
  s.map_status = static_cast<monocle_msgs_msg_dds__MapStatus>(17);
  EXPECT_EQ(FromSample(s).map_status, MapStatus::kNone) << "a status from a newer service";

  Pose none;
  none.error = "no corner";
  ToSample(none, &s);
  EXPECT_EQ(s.status, monocle_msgs_msg_dds__POSE_NO_CORNER);
  EXPECT_FALSE(FromSample(s).valid);
  EXPECT_EQ(FromSample(s).error, "no corner");
}

TEST(ConvertTest, RosTimeOfTimesBefore1970KeepsNanosecondsPositive) {
  const auto t = RosTime(-1);
  EXPECT_EQ(t.sec, -1);
  EXPECT_EQ(t.nanosec, 999'999'999u);
  EXPECT_EQ(UnixNs(t), -1);
}

TEST(ConvertTest, StatusAndCalibrationRoundTrip) {
  CameraStatus c;
  c.camera_id = "floor";
  c.device = "sim-floor";
  c.role = "floor";
  c.ros_namespace = "/robot1/monocle/floor";
  c.service = "host/123";
  c.state = CameraState::kReconnecting;
  c.fps = 29.5;
  c.frames = 100;
  c.dropped = 2;
  c.skipped = 3;
  c.latency_ms = 12.5;
  c.last_error = "camera lost";
  c.last_error_ns = 55;
  c.stamp_ns = 1'000'000'007;
  monocle_msgs_msg_dds__CameraStatus_ s;
  const std::string frame = "floor_optical";  // the sample points into it (ASan found a temporary)
  ToSample(c, frame, &s);
  EXPECT_STREQ(s.header.frame_id, "floor_optical");
  const CameraStatus b = FromSample(s);
  EXPECT_EQ(b.camera_id, c.camera_id);
  EXPECT_EQ(b.device, c.device);
  EXPECT_EQ(b.role, c.role);
  EXPECT_EQ(b.ros_namespace, c.ros_namespace);
  EXPECT_EQ(b.service, c.service);
  EXPECT_EQ(b.state, c.state);
  EXPECT_EQ(b.fps, c.fps);
  EXPECT_EQ(b.frames, c.frames);
  EXPECT_EQ(b.dropped, c.dropped);
  EXPECT_EQ(b.skipped, c.skipped);
  EXPECT_EQ(b.latency_ms, c.latency_ms);
  EXPECT_EQ(b.last_error, c.last_error);
  EXPECT_EQ(b.last_error_ns, c.last_error_ns);
  EXPECT_EQ(b.stamp_ns, c.stamp_ns);

  Calibration k;
  k.camera_id = "floor";
  k.ros_namespace = "/monocle/floor";
  k.revision = 3;
  k.updated_ns = 99;
  k.width_px = 1280;
  k.height_px = 1024;
  k.fx = 1000;
  k.fy = 1001;
  k.cx = 640;
  k.cy = 512;
  k.distortion = {0.1, -0.2, 0.001, 0.002, 0.03, 0, 0, 0};
  k.floor = FloorPoseEstimate{1.05, 0.5, 0.01, -0.02, {0.001, 0.002, 0.003, 0.004}, 0.2};
  k.ceiling_distance_m = 2.5;
  k.file = "/var/lib/monocle/floor.pb.txt";
  k.text = "intrinsics { }";
  monocle_msgs_msg_dds__Calibration_ ks;
  ToSample(k, &ks);
  const Calibration kb = FromSample(ks);
  EXPECT_EQ(kb.camera_id, k.camera_id);
  EXPECT_EQ(kb.ros_namespace, k.ros_namespace);
  EXPECT_EQ(kb.revision, k.revision);
  EXPECT_EQ(kb.updated_ns, k.updated_ns);
  EXPECT_EQ(kb.width_px, k.width_px);
  EXPECT_EQ(kb.height_px, k.height_px);
  EXPECT_EQ(kb.fy, k.fy);
  EXPECT_EQ(kb.cy, k.cy);
  EXPECT_EQ(kb.distortion, k.distortion);
  ASSERT_TRUE(kb.floor.has_value());
  EXPECT_EQ(kb.floor->pitch_rad, 0.5);
  EXPECT_EQ(kb.floor->sigma, k.floor->sigma);
  EXPECT_EQ(kb.ceiling_distance_m, k.ceiling_distance_m);
  EXPECT_EQ(kb.file, k.file);
  EXPECT_EQ(kb.text, k.text);
  k.floor.reset();
  k.ceiling_distance_m.reset();
  ToSample(k, &ks);
  EXPECT_FALSE(FromSample(ks).floor.has_value());
  EXPECT_FALSE(FromSample(ks).ceiling_distance_m.has_value());
}

TEST(ConvertTest, PointRequestColumnsRoundTrip) {
  const std::vector<PixelQuery> pixels = {{640, 900, std::nullopt},
                                          {600, 500, std::array<double, 2>{600, 900}}};
  PointRequestColumns columns;
  monocle_msgs_srv_dds__MeasurePoints_Request_ s;
  ToSample(pixels, 0.7, &columns, &s);
  EXPECT_EQ(s.pixel_sigma_px, 0.7);
  ASSERT_EQ(s.foot_u._length, 2u);
  EXPECT_TRUE(std::isnan(s.foot_u._buffer[0]));
  auto back = FromSample(s);
  ASSERT_TRUE(back.ok()) << back.error();
  ASSERT_EQ(back->size(), 2u);
  EXPECT_EQ((*back)[0].u, 640);
  EXPECT_FALSE((*back)[0].foot_px.has_value());
  ASSERT_TRUE((*back)[1].foot_px.has_value());
  EXPECT_EQ((*(*back)[1].foot_px)[1], 900);

  // Floor pixels only: no foot columns at all.
  ToSample({{1, 2, std::nullopt}}, 0, &columns, &s);
  EXPECT_EQ(s.foot_u._length, 0u);
  ASSERT_TRUE(FromSample(s).ok());

  // A foot half given is a foot (rejected later as an invalid pixel), not a floor pixel.
  ToSample(pixels, 0, &columns, &s);
  columns.foot_v[0] = 3;
  back = FromSample(s);
  ASSERT_TRUE(back.ok());
  EXPECT_TRUE((*back)[0].foot_px.has_value());
}

TEST(ConvertTest, MalformedPointColumnsAreRefusedWithWhatIsWrong) {
  std::vector<double> u = {1, 2, 3}, v = {1, 2}, foot = {1};
  monocle_msgs_srv_dds__MeasurePoints_Request_ s{};
  s.u = {3, 3, u.data(), false};
  s.v = {2, 2, v.data(), false};
  auto r = FromSample(s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("u has 3 pixels but v has 2"), std::string::npos)
      << r.error().message;
  s.v = {3, 3, u.data(), false};
  s.foot_u = {1, 1, foot.data(), false};
  r = FromSample(s);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("foot_u and foot_v"), std::string::npos) << r.error().message;
}

TEST(ConvertTest, PointReplyRoundTrip) {
  std::vector<MeasuredPoint> points(3);
  points[0].p_robot_m = {0.1, 2.0, 0};
  points[0].sigma_m = {0.01, 0.02, 0};
  points[1].status = MeasuredPoint::Status::kNotMeasurable;
  points[1].error = "above the horizon";
  points[2].status = MeasuredPoint::Status::kInvalidPixel;
  points[2].error = "outside the image";
  PointReplyColumns columns;
  monocle_msgs_srv_dds__MeasurePoints_Response_ s;
  ToSample(monocle_msgs_msg_dds__REQUEST_OK, "", points, &columns, &s);
  EXPECT_EQ(s.point_errors._length, 2u);
  const auto back = FromSample(s);
  ASSERT_TRUE(back.ok());
  ASSERT_EQ(back->size(), 3u);
  EXPECT_EQ((*back)[0].p_robot_m, points[0].p_robot_m);
  EXPECT_EQ((*back)[0].sigma_m, points[0].sigma_m);
  EXPECT_TRUE((*back)[0].ok());
  EXPECT_EQ((*back)[1].status, MeasuredPoint::Status::kNotMeasurable);
  EXPECT_EQ((*back)[1].error, "above the horizon");
  EXPECT_EQ((*back)[2].status, MeasuredPoint::Status::kInvalidPixel);
  // A status this client does not know (a newer service) is "not measured", with why; read
  // as an integer, never loaded as the enum type (UBSan).
  uint32_t unknown = 17;
  std::memcpy(&columns.status[0], &unknown, sizeof unknown);
  const auto newer = FromSample(s);
  ASSERT_TRUE(newer.ok());
  EXPECT_EQ((*newer)[0].status, MeasuredPoint::Status::kNotMeasurable);
  EXPECT_NE((*newer)[0].error.find("unknown point status 17"), std::string::npos);
  // A reply whose columns disagree is refused, not read out of bounds.
  s.z._length = 2;
  EXPECT_FALSE(FromSample(s).ok());
}

TEST(ConvertTest, FloorCalibrationResultRoundTrip) {
  FloorCalibrationResult r;
  r.floor = {1.1, 0.4, 0.01, 0.02, {1e-3, 2e-3, 3e-3, 4e-3}, 0.15};
  r.corners = 88;
  r.frame_sequence = 7;
  r.file = "floor.pb.txt";
  r.revision = 2;
  r.report.board = {2.5, 0.4, 0.12, 31};
  r.report.accuracy = {{1, true, 0.002, 0.0015, 0.0005, 0.001}, {4, false, 0.03, 0.02, 0.01, 0.02}};
  r.report.ill_conditioned = true;
  r.report.ill_conditioned_reason = "the board is too small";
  r.report.target_met = false;
  r.report.target_met_out_to_m = 1.5;
  r.report.advice = {"lay the board nearer", "use larger squares"};
  r.overlay_png = {0x89, 'P', 'N', 'G', 0, 255};
  monocle_msgs_srv_dds__CalibrateFloor_Response_ s{};
  FloorReplyStorage storage;
  ToSample(r, &storage, &s);
  const auto b = FromSample(s);
  EXPECT_EQ(b.report.board.distance_m, 2.5);
  EXPECT_EQ(b.report.board.depth_span_m, 0.4);
  EXPECT_EQ(b.report.board.image_fraction, 0.12);
  EXPECT_EQ(b.report.board.sight_angle_deg, 31);
  ASSERT_EQ(b.report.accuracy.size(), 2u);
  EXPECT_EQ(b.report.accuracy[1].distance_m, 4);
  EXPECT_FALSE(b.report.accuracy[1].in_image);
  EXPECT_EQ(b.report.accuracy[0].sigma_m, 0.002);
  EXPECT_EQ(b.report.accuracy[0].calibration_sigma_m, 0.0015);
  EXPECT_EQ(b.report.accuracy[0].intrinsics_sigma_m, 0.0005);
  EXPECT_EQ(b.report.accuracy[0].pixel_sigma_m, 0.001);
  EXPECT_TRUE(b.report.ill_conditioned);
  EXPECT_EQ(b.report.ill_conditioned_reason, "the board is too small");
  EXPECT_FALSE(b.report.target_met);
  EXPECT_EQ(b.report.target_met_out_to_m, 1.5);
  EXPECT_EQ(b.report.advice, r.report.advice);
  EXPECT_EQ(b.overlay_png, r.overlay_png);
  EXPECT_EQ(b.floor.height_m, 1.1);
  EXPECT_EQ(b.floor.sigma, r.floor.sigma);
  EXPECT_EQ(b.floor.rms_px, 0.15);
  EXPECT_EQ(b.corners, 88u);
  EXPECT_EQ(b.frame_sequence, 7u);
  EXPECT_EQ(b.file, "floor.pb.txt");
  EXPECT_EQ(b.revision, 2u);
}

TEST(ConvertTest, FloorCalibrationRequestRoundTrip) {
  FloorCalibrationOptions o;
  o.pixel_sigma_px = 0.3;
  o.target = FloorAccuracyTarget{0.01, 4};
  o.force = true;
  o.overlay = true;
  monocle_msgs_srv_dds__CalibrateFloor_Request_ s{};
  ToSample(9, 6, 0.025, o, &s);
  EXPECT_EQ(s.board_cols, 9);
  EXPECT_EQ(s.board_rows, 6);
  EXPECT_EQ(s.square_m, 0.025);
  const FloorCalibrationOptions back = OptionsFromSample(s);
  EXPECT_EQ(back.pixel_sigma_px, 0.3);
  ASSERT_TRUE(back.target.has_value());
  EXPECT_EQ(back.target->sigma_m, 0.01);
  EXPECT_EQ(back.target->distance_m, 4);
  EXPECT_TRUE(back.force);
  EXPECT_TRUE(back.overlay);
  // A caller that sets neither (a ROS 2 client of the old layout's fields): no target, and a
  // target without its distance is 3 m ahead.
  s.target_sigma_m = 0;
  EXPECT_FALSE(OptionsFromSample(s).target.has_value());
  s.target_sigma_m = 0.02;
  s.target_distance_m = 0;
  EXPECT_EQ(OptionsFromSample(s).target->distance_m, 3.0);
}

}  // namespace
}  // namespace monocle::wire
