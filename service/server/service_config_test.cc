#include "service/server/service_config.h"
#include "camera/sim/sim_calibrations.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "service/io/calibration_file.h"

namespace monocle {
namespace {

TEST(ServiceConfigTest, EmbeddedDefaultHasBothSimulatedCameras) {
  const auto setup = ParseServiceConfig(EmbeddedDefaultConfig(), "default", "/state");
  ASSERT_TRUE(setup.ok()) << setup.error();
  EXPECT_EQ(setup->ros_discovery, RosDiscoveryLayout::kIronAndLater);
  const auto humble = ParseServiceConfig(
      "ros_discovery_info: \"humble\"\ncamera { device: \"a\" role: FLOOR calibration: \"x\" }",
      "cfg", "/state");
  ASSERT_TRUE(humble.ok()) << humble.error();
  EXPECT_EQ(humble->ros_discovery, RosDiscoveryLayout::kHumble);
  ASSERT_TRUE(setup.ok()) << setup.error();
  ASSERT_EQ(setup->cameras.size(), 2u);
  EXPECT_EQ(setup->cameras[0].id, "sim-corner");
  EXPECT_EQ(setup->cameras[0].role, CameraRole::kCorner);
  EXPECT_EQ(setup->cameras[0].calibration_path, "/state/sim-corner.pbtxt");
  EXPECT_EQ(setup->cameras[1].options.device, "sim-floor");
  EXPECT_EQ(setup->cameras[1].role, CameraRole::kFloor);
  // ROS 2 names: '-' is not allowed in them.
  EXPECT_EQ(setup->cameras[0].ros_namespace, "/monocle/sim_corner");
  EXPECT_EQ(setup->cameras[0].ros_frame, "sim_corner_optical");
  EXPECT_EQ(setup->cameras[0].ros_parent_frame, "corner");
  EXPECT_EQ(setup->cameras[1].ros_namespace, "/monocle/sim_floor");
}

TEST(ServiceConfigTest, ReadsEveryCameraSetting) {
  const auto setup = ParseServiceConfig(R"(
domain: 7
status_period_s: 0.5
camera {
  id: "front"
  device: "192.168.1.20"
  role: CORNER_AND_FLOOR
  calibration: "/etc/monocle/front.pbtxt"
  ceiling_distance_m: 2.1
  pixel_format: "Mono16"
  exposure_us: 5000
  gain: 3
  frame_rate_hz: 20
  packet_size_bytes: 8000
  feature { name: "BalanceWhiteAuto" value: "Off" }
  stall_timeout_s: 2
  ros_namespace: "robot1/front/"
  ros_parent_frame: "map"
  image_max_rate_hz: 2
  mount { base_frame: "base_link" translation_m: [0.2, 0, 1.1] rotation_xyzw: [0, 0, 0, 1.0004] }
  level_sigma_deg: 0.2
}
)",
                                        "cfg", "/base");
  ASSERT_TRUE(setup.ok()) << setup.error();
  EXPECT_EQ(setup->domain, 7);
  EXPECT_EQ(setup->status_period.count(), 500);
  const auto& c = setup->cameras.at(0);
  EXPECT_EQ(c.id, "front");
  EXPECT_TRUE(c.corner() && c.floor());
  EXPECT_EQ(c.calibration_path, "/etc/monocle/front.pbtxt");
  EXPECT_DOUBLE_EQ(*c.ceiling_distance_m, 2.1);
  EXPECT_EQ(c.options.pixel_format, "Mono16");
  EXPECT_DOUBLE_EQ(*c.options.exposure_us, 5000);
  EXPECT_EQ(*c.options.packet_size_bytes, 8000);
  ASSERT_EQ(c.options.features.size(), 1u);
  EXPECT_EQ(c.options.features[0].second, "Off");
  EXPECT_EQ(c.stall_timeout.count(), 2000);
  EXPECT_EQ(c.ros_namespace, "/robot1/front");  // made absolute, trailing / dropped
  EXPECT_EQ(c.ros_frame, "front_optical");
  EXPECT_EQ(c.ros_parent_frame, "map");
  EXPECT_DOUBLE_EQ(c.image_max_rate_hz, 2);
  ASSERT_TRUE(c.mount.has_value());
  EXPECT_EQ(c.mount->base_frame, "base_link");
  EXPECT_DOUBLE_EQ(c.mount->translation_m[2], 1.1);
  EXPECT_DOUBLE_EQ(c.mount->rotation_xyzw[3], 1.0004);  // as given; the transform normalizes
  EXPECT_DOUBLE_EQ(MountTransform(*c.mount).rotation.w(), 1);
  ASSERT_TRUE(c.level_sigma_rad.has_value());
  EXPECT_NEAR(*c.level_sigma_rad, 0.2 * M_PI / 180, 1e-15);
}

// Each broken file is rejected with its line and the field at fault.
TEST(ServiceConfigTest, ErrorsNameTheLineAndTheField) {
  struct Case {
    const char* text;
    const char* expected;
  };
  const Case cases[] = {
      {"camera {\n  device: \"a\"\n  colour: 3\n}\n", "cfg: line 3, column"},
      {"camera {\n  device: \"a\"\n  colour: 3\n}\n", "no field named \"colour\""},
      // Protobuf reports a bad value where the next token starts; the value is named.
      {"camera {\n  device: \"a\"\n  role: SIDEWAYS\n}\n", "\"SIDEWAYS\" for field \"role\""},
      {"domain: 400\ncamera { device: \"a\" role: FLOOR calibration: \"x\" }\n",
       "cfg: line 1: domain must be 0..232"},
      {"camera {\n  device: \"a\"\n  calibration: \"x\"\n}\n", "camera[0].role is missing"},
      {"ros_discovery_info: \"rolling\"\ncamera { device: \"a\" role: FLOOR calibration: \"x\" }\n",
       "cfg: line 1: ros_discovery_info must be \"jazzy\" (Iron and later), \"humble\" or \"off\""},
      {"camera {\n  role: FLOOR\n}\n", "cfg: line 1: camera[0].device is missing"},
      {"camera { device: \"a\" role: FLOOR calibration: \"x\" }\n"
       "camera {\n  device: \"a\"\n  role: CORNER\n  calibration: \"y\"\n}\n",
       "cfg: line 3: camera[1].id 'a' names two cameras"},
      {"camera {\n  device: \"a\"\n  role: CORNER\n  calibration: \"y\"\n  exposure_us: -1\n}\n",
       "cfg: line 5: camera[0].exposure_us must be > 0"},
      {"domain: 1\n", "no camera"},
      {"camera {\n  device: \"a\"\n  role: CORNER\n  calibration: \"y\"\n"
       "  ros_namespace: \"/robot one\"\n}\n",
       "cfg: line 5: camera[0].ros_namespace '/robot one' is not a ROS 2 namespace"},
      {"camera { device: \"a\" role: CORNER calibration: \"y\" image_max_rate_hz: 0 }\n",
       "camera[0].image_max_rate_hz must be"},
      {"camera {\n  device: \"a\"\n  role: CORNER\n  calibration: \"y\"\n"
       "  mount { translation_m: [0, 0, 1] rotation_xyzw: [0, 0, 0, 1] }\n}\n",
       "cfg: line 5: camera[0].mount.base_frame is missing"},
      {"camera { device: \"a\" role: CORNER calibration: \"y\"\n"
       "  mount { base_frame: \"b\" translation_m: [0, 1] rotation_xyzw: [0, 0, 0, 1] } }\n",
       "cfg: line 2: camera[0].mount.translation_m needs 3 values"},
      {"camera { device: \"a\" role: CORNER calibration: \"y\"\n"
       "  mount { base_frame: \"b\" translation_m: [0, 0, 1] rotation_xyzw: [0, 0, 0, 2] } }\n",
       "camera[0].mount.rotation_xyzw must be a unit quaternion (its norm is 2"},
      {"camera { device: \"a\" role: CORNER calibration: \"y\"\n  level_sigma_deg: 0.3 }\n",
       "cfg: line 2: camera[0].level_sigma_deg needs the camera's mount on the robot"},
      {"camera { device: \"a\" role: CORNER calibration: \"y\"\n"
       "  mount { base_frame: \"b\" translation_m: [0, 0, 1] rotation_xyzw: [0, 0, 0, 1] }\n"
       "  level_sigma_deg: 0 }\n",
       "cfg: line 3: camera[0].level_sigma_deg must be how level the robot stands"},
      {"camera {\n  device: \"a\"\n  id: "
       "\"xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx"
       "xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx\"\n}\n",
       "cfg: line 3: camera[0].id is longer than 128 characters"},
      {"camera {\n  id: \"front\"\n  device: \"ros:camera//image raw\"\n  role: CORNER\n}\n",
       "cfg: line 3: camera[0].device 'camera//image raw' is not an absolute ROS 2 topic name: "
       "write it like ros:/camera/image_raw"},
      {"camera {\n  device: \"ros:/camera/image_raw\"\n  role: CORNER\n}\n",
       "cfg: line 2: camera[0].id is needed for an image topic camera"},
      {"camera {\n  id: \"front\"\n  device: \"ros:/camera/image_raw\"\n  role: CORNER\n}\n",
       "cfg: line 3: camera[0].ceiling_distance_m is needed when the intrinsics come from "
       "camera_info"},
      {"camera { id: \"f\" device: \"ros:/camera/image_raw\" role: FLOOR }\n",
       "camera[0].calibration is missing"},
      {"camera { id: \"f\" device: \"ros:/camera/image_raw\" role: CORNER\n"
       "  ceiling_distance_m: 2 exposure_us: 8000 }\n",
       "camera[0].device is an image topic: its camera's settings"},
  };
  for (const auto& c : cases) {
    const auto setup = ParseServiceConfig(c.text, "cfg", "");
    ASSERT_FALSE(setup.ok()) << c.text;
    EXPECT_NE(setup.error().message.find(c.expected), std::string::npos)
        << "expected '" << c.expected << "' in: " << setup.error().message;
  }
}

TEST(ServiceConfigTest, ARoomMapNeedsAMountAndIsCheckedAgainstIt) {
  const std::string examples = std::string(MONOCLE_SOURCE_DIR) + "/idl/examples";
  const std::string mount =
      "  mount { base_frame: \"base_link\" translation_m: [0.1, 0, 0.4]\n"
      "          rotation_xyzw: [-0.2988362, 0.2988362, -0.6408564, 0.6408564] }\n";
  const auto good = ParseServiceConfig(
      "camera {\n  device: \"a\"\n  role: CORNER\n"
      "  calibration: \"y\"\n  room_map: \"room_map.pbtxt\"\n"
      "  initial_pose: [1.4, 1.3, -20]\n" +
          mount + "}\n",
      "cfg", examples);
  ASSERT_TRUE(good.ok()) << good.error();
  const CameraSetup& cam = good->cameras[0];
  ASSERT_TRUE(cam.room_map);
  EXPECT_EQ(cam.room_map->rooms.size(), 2u);
  EXPECT_EQ(cam.room_map_path, examples + "/room_map.pbtxt");
  EXPECT_NEAR(*cam.ceiling_distance_m, 2.2, 1e-12) << "the hall's 2.6 m less the mount's 0.4 m";
  ASSERT_TRUE(cam.initial_pose);
  EXPECT_NEAR(cam.initial_pose->heading_rad, -20 * M_PI / 180, 1e-12);

  struct Case {
    std::string text, expected;
  };
  const std::string head = "camera {\n  device: \"a\"\n  role: CORNER\n  calibration: \"y\"\n";
  const Case cases[] = {
      {head + "  room_map: \"room_map.pbtxt\"\n}\n",
       "cfg: line 5: camera[0].room_map needs the camera's mount on the robot"},
      {head + "  room_map: \"missing.pbtxt\"\n" + mount + "}\n",
       "cfg: line 5: camera[0].room_map cannot be used: "},
      {head + "  ceiling_distance_m: 2\n  room_map: \"room_map.pbtxt\"\n" + mount + "}\n",
       "cfg: line 5: camera[0].ceiling_distance_m is not used with a room_map"},
      {head + "  room_map: \"room_map.pbtxt\"\n"
              "  mount { base_frame: \"b\" translation_m: [0, 0, 2.5] rotation_xyzw: [0, 0, 0, "
              "1] }\n}\n",
       "cfg: line 6: camera[0].mount.translation_m puts the camera 2.50 m above the floor: it must "
       "be above the floor and 0.1 m below the ceiling of room 'hall' (2.60 m)"},
      {head + "  room_map: \"room_map.pbtxt\"\n  initial_pose: [20, 1, 0]\n" + mount + "}\n",
       "cfg: line 6: camera[0].initial_pose lies in no room of the room map"},
      {head + "  initial_pose: [1, 1, 0]\n" + mount + "}\n",
       "cfg: line 5: camera[0].initial_pose needs a room_map"},
  };
  for (const auto& c : cases) {
    const auto setup = ParseServiceConfig(c.text, "cfg", examples);
    ASSERT_FALSE(setup.ok()) << c.text;
    EXPECT_NE(setup.error().message.find(c.expected), std::string::npos)
        << "expected '" << c.expected << "' in: " << setup.error().message;
  }
}

// Issue 14: 200 000 cameras kept monocled busy (ignoring SIGTERM) for minutes; the count is
// now refused where the first camera too many is written.
TEST(ServiceConfigTest, AnImageTopicCornerCameraMayTakeItsIntrinsicsFromCameraInfo) {
  const auto setup = ParseServiceConfig(
      "camera { id: \"front\" device: \"ros:/robot/front/image_raw\" role: CORNER\n"
      "  ceiling_distance_m: 2.4 }\n",
      "cfg", "/etc/monocle");
  ASSERT_TRUE(setup.ok()) << setup.error();
  EXPECT_EQ(setup->cameras[0].options.device, "ros:/robot/front/image_raw");
  EXPECT_TRUE(setup->cameras[0].calibration_path.empty());
  EXPECT_EQ(setup->cameras[0].ceiling_distance_m, 2.4);
}

TEST(ServiceConfigTest, RefusesMoreCamerasThanOneServiceServes) {
  std::string text;
  for (int i = 0; i <= kMaxCamerasPerService; ++i)
    text += "camera { device: \"c" + std::to_string(i) + "\" role: FLOOR calibration: \"x\" }\n";
  const auto setup = ParseServiceConfig(text, "cfg", "");
  ASSERT_FALSE(setup.ok());
  EXPECT_NE(setup.error().message.find("cfg: line 65: camera[64]"), std::string::npos)
      << setup.error();
  EXPECT_NE(setup.error().message.find("at most 64 cameras"), std::string::npos) << setup.error();
  // One fewer is fine.
  text.erase(text.rfind("camera {"));
  EXPECT_TRUE(ParseServiceConfig(text, "cfg", "").ok());
}

TEST(ServiceConfigTest, RefusesAConfigurationThatIsNotARegularFile) {
  const auto setup = LoadServiceConfig("/dev/zero");
  ASSERT_FALSE(setup.ok());
  EXPECT_NE(setup.error().message.find("not a regular file"), std::string::npos) << setup.error();
}

TEST(ServiceConfigTest, SimulatorCalibrationsAreWrittenOnceAndLoad) {
  const auto dir = std::filesystem::temp_directory_path() / "monocle_config_test_state";
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(EnsureSimulatorCalibrations(dir.string()).ok());
  const auto corner = LoadCalibrationFile((dir / "sim-corner.pbtxt").string());
  ASSERT_TRUE(corner.ok()) << corner.error();
  EXPECT_TRUE(corner->ceiling_distance_m.has_value());
  const auto floor = LoadCalibrationFile((dir / "sim-floor.pbtxt").string());
  ASSERT_TRUE(floor.ok()) << floor.error();
  ASSERT_TRUE(floor->floor.has_value());
  // A later run keeps what is there (a floor calibration command may have updated it).
  CameraCalibration changed = *floor;
  changed.floor->pose.height_m = 0.5;
  ASSERT_TRUE(SaveCalibrationFileAtomically((dir / "sim-floor.pbtxt").string(), changed).ok());
  ASSERT_TRUE(EnsureSimulatorCalibrations(dir.string()).ok());
  EXPECT_DOUBLE_EQ(LoadCalibrationFile((dir / "sim-floor.pbtxt").string())->floor->pose.height_m,
                   0.5);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace monocle
