// A robot's own camera driver on ROS 2's default middleware feeds monocled: ros2_peer (Fast DDS
// from Debian, types from fastddsgen, none of monocle's code) publishes rendered frames on
// /camera/image_raw, monocled reads them through a camera configured as
// device "ros:/camera/image_raw", and ROS 2 readers on Fast DDS receive its pose, camera_info,
// tf and diagnostics. Separate processes on loopback.
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "idl/cli_output.pb.h"
#include "tests/integration/cli_process.h"
#include "tests/integration/service_process.h"

namespace monocle::testing {
namespace {

struct Truth {
  double x, y, z;
};

std::string PeerBinary() {
  const std::string bin = MonocleBinary();
  return bin.substr(0, bin.rfind("/client/")) + "/tests/integration/ros2_peer";
}

std::vector<std::vector<std::string>> Words(const std::string& text) {
  std::vector<std::vector<std::string>> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string word; words >> word;) w.push_back(word);
    if (!w.empty()) lines.push_back(w);
  }
  return lines;
}

// `corner locate --camera --json` or `replay --json`: one pose a line.
std::vector<proto::LivePoseOutput> LivePoses(const std::string& text) {
  std::vector<proto::LivePoseOutput> poses;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    proto::LivePoseOutput pose;
    EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(line, &pose).ok()) << line;
    poses.push_back(pose);
  }
  return poses;
}

class RosImageTopicTest : public ::testing::Test {
 protected:
  // Three realistic frames of a robot moving 1 cm at a time under the corner, the camera's
  // calibration, and monocled with one camera reading the image topic (`camera_entry`, by
  // default with the calibration file).
  void StartService(int domain, const std::string& camera_entry = "calibration: \"cal.pbtxt\"",
                    const std::vector<std::string>& monocled_args = {}) {
    domain_ = domain;
    std::ofstream(dir_ / "cal.pbtxt")
        << "intrinsics { width: 1280 height: 1024 fx: 1624.34 fy: 1623.04 cx: 634.77 "
           "cy: 499.02 distortion: [-0.07021, 0.07348, -0.00112, 0.00267] }\n"
           "corner { ceiling_distance: 1.6 }\n";
    for (int i = 0; i < 3; ++i) {
      truth_.push_back({2.0 + 0.01 * i, 1.5, 1.6});
      const std::string pose = std::to_string(truth_[i].x) + ",1.5,1.6,2.2143,0.9,0.1";
      const std::string frame = dir_ / ("frame" + std::to_string(i) + ".png");
      auto r = RunMonocle(dir_, "render corner --calibration " + dir_ / "cal.pbtxt" + " --pose " +
                                    pose + " --realistic --seed 11 --out " + frame);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      frames_.push_back(frame);
    }
    monocled_ = StartMonocled(dir_,
                              "domain: " + std::to_string(domain) +
                                  "\ncamera { id: \"front\" role: CORNER device: "
                                  "\"ros:/camera/image_raw\" " +
                                  camera_entry + " }\n",
                              monocled_args);
  }

  std::unique_ptr<ChildProcess> Publish(const std::string& qos, const std::string& encoding,
                                        double seconds, const std::string& camera_info = "") {
    std::vector<std::string> args{"publish",
                                  "--domain",
                                  std::to_string(domain_),
                                  "--qos",
                                  qos,
                                  "--encoding",
                                  encoding,
                                  "--rate",
                                  "10",
                                  "--seconds",
                                  std::to_string(seconds)};
    if (!camera_info.empty()) args.insert(args.end(), {"--camera-info", camera_info});
    args.insert(args.end(), frames_.begin(), frames_.end());
    return std::make_unique<ChildProcess>(PeerBinary(), args, dir_ / "publisher.log");
  }

  void TearDown() override {
    if (monocled_) {
      EXPECT_EQ(monocled_->Stop(), 0) << ReadFile(dir_ / "monocled.log");
    }
  }

  TempDir dir_{"monocle_ros_image_topic"};
  int domain_ = 0;
  std::vector<Truth> truth_;
  std::vector<std::string> frames_;
  std::unique_ptr<ChildProcess> monocled_;
};

// The driver's frames (rgb8, sensor-data QoS: best effort) give poses that match the rendered
// truth, stamped with the frame's own stamp; Fast DDS readers receive every topic, and ROS 2's
// graph shows monocled's node with their writers.
TEST_F(RosImageTopicTest, AFastDdsDriversFramesBecomePosesFastDdsReadersReceive) {
  ASSERT_NO_FATAL_FAILURE(StartService(73));
  auto publisher = Publish("sensor", "rgb8", 30);
  ChildProcess reader(PeerBinary(),
                      {"read", "--domain", std::to_string(domain_), "--namespace", "/monocle/front",
                       "--seconds", "8", "--out", dir_ / "read.txt"},
                      dir_ / "reader.log");
  ASSERT_EQ(reader.WaitFor(std::chrono::seconds(30)), 0) << ReadFile(dir_ / "reader.log");
  const auto lines = Words(ReadFile(dir_ / "read.txt"));
  std::map<std::string, int> count;
  std::string last_diagnostic_level, node_namespace, node_writers;
  std::map<std::string, std::string> writer_of;  // DDS topic: its writer's GUID
  for (const auto& w : lines) {
    ++count[w[0]];
    if (w[0] == "pose") {
      // pose SEC NANOSEC FRAME X Y Z QX QY QZ QW VAR_X: the stamp's nanoseconds name the frame.
      ASSERT_EQ(w.size(), 12u);
      const size_t frame = std::stoul(w[2]);
      ASSERT_LT(frame, truth_.size());
      EXPECT_GE(std::stoi(w[1]), 1000) << "the driver's stamp is carried through";
      EXPECT_EQ(w[3], "corner");
      const double dx = std::stod(w[4]) - truth_[frame].x, dy = std::stod(w[5]) - truth_[frame].y;
      EXPECT_LT(std::hypot(dx, dy), 0.01 * std::hypot(truth_[frame].x, truth_[frame].y))
          << "frame " << frame;
      EXPECT_GT(std::stod(w[11]), 0) << "a covariance is published";
    } else if (w[0] == "camera_info") {
      ASSERT_EQ(w.size(), 8u);
      EXPECT_EQ(w[2], "1280");
      EXPECT_NEAR(std::stod(w[4]), 1624.34, 1e-6);
    } else if (w[0] == "tf") {
      EXPECT_EQ(w[1], "corner");
      EXPECT_EQ(w[2], "front_optical");
    } else if (w[0] == "diagnostics" && w.size() > 3 && w[2] == "front") {
      last_diagnostic_level = w[3];
    } else if (w[0] == "image") {
      // image SEC NANOSEC FRAME_ID WIDTH HEIGHT ENCODING: the frame monocled measured, as the
      // driver stamped and named it.
      ASSERT_EQ(w.size(), 7u);
      EXPECT_GE(std::stoi(w[1]), 1000);
      EXPECT_EQ(w[3], "camera_optical_frame") << "the driver's frame id is kept";
      EXPECT_EQ(w[4] + "x" + w[5], "1280x1024");
    } else if (w[0] == "writer") {
      writer_of[w[1]] = w[2];
    } else if (w[0] == "graph" && w.size() == 6 && w[3] == "monocled") {
      node_namespace = w[2];
      node_writers = w[4];
    }
  }
  // ROS 2's graph (ros_discovery_info, read as rmw_fastrtps's graph cache reads it) names
  // monocled's node, and lists the writer of every topic this reader received.
  EXPECT_EQ(node_namespace, "/") << "no node /monocled in ros_discovery_info";
  for (const std::string topic :
       {"rt/monocle/front/pose", "rt/monocle/front/camera_info", "rt/tf", "rt/diagnostics"}) {
    ASSERT_EQ(writer_of.count(topic), 1u) << topic;
    EXPECT_NE(node_writers.find(writer_of[topic]), std::string::npos)
        << topic << "'s writer " << writer_of[topic] << " is not among /monocled's "
        << node_writers;
  }
  EXPECT_GE(count["pose"], 20) << "8 s of a 10 Hz driver";
  EXPECT_GE(count["camera_info"], 1);
  EXPECT_GE(count["tf"], 20);
  EXPECT_GE(count["diagnostics"], 1);
  EXPECT_GE(count["image"], 5) << "8 s of frames republished at image_max_rate_hz (5 Hz)";
  EXPECT_EQ(last_diagnostic_level, "level=0") << "the streaming camera is OK";
  EXPECT_EQ(publisher->Stop(), 0) << ReadFile(dir_ / "publisher.log");
}

// Bayer frames with ROS 2's default QoS (reliable) are read too; when the driver stops, the
// camera's status and ROS 2's /diagnostics say the topic went quiet, and it streams again
// when frames come back.
TEST_F(RosImageTopicTest, DefaultQosBayerFramesAndAQuietTopicIsReported) {
  ASSERT_NO_FATAL_FAILURE(StartService(74));
  auto publisher = Publish("default", "bayer_rggb8", 4);
  auto r = RunMonocle(dir_, "corner locate --camera front --domain 74 --count 5 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err << ReadFile(dir_ / "monocled.log");
  EXPECT_EQ(Words(r.out).size(), 5u) << r.out;
  ASSERT_EQ(publisher->WaitFor(std::chrono::seconds(20)), 0) << ReadFile(dir_ / "publisher.log");
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  r = RunMonocle(dir_, "status --domain 74");
  EXPECT_EQ(r.exit_code, 0) << "a camera being waited for is not a failure:\n" << r.out << r.err;
  EXPECT_NE(r.out.find("reconnecting"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("no image on /camera/image_raw"), std::string::npos) << r.out;
  // ROS 2's /diagnostics says so too, to a Fast DDS reader: the camera's level is ERROR (2).
  ChildProcess reader(PeerBinary(),
                      {"read", "--domain", "74", "--namespace", "/monocle/front", "--seconds", "3",
                       "--out", dir_ / "quiet.txt"},
                      dir_ / "reader.log");
  ASSERT_EQ(reader.WaitFor(std::chrono::seconds(20)), 0) << ReadFile(dir_ / "reader.log");
  std::string quiet;  // the camera's last status in /diagnostics
  std::istringstream quiet_lines(ReadFile(dir_ / "quiet.txt"));
  for (std::string line; std::getline(quiet_lines, line);)
    if (line.starts_with("diagnostics monocle: front ")) quiet = line;
  EXPECT_NE(quiet.find(" level=2 message=reconnecting: no image on /camera/image_raw"),
            std::string::npos)
      << ReadFile(dir_ / "quiet.txt");
  publisher = Publish("default", "mono8", 30);
  r = RunMonocle(dir_, "corner locate --camera front --domain 74 --count 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunMonocle(dir_, "status --domain 74");
  EXPECT_NE(r.out.find("streaming"), std::string::npos) << r.out;
  EXPECT_EQ(publisher->Stop(), 0);
}

// A camera configured without a calibration file takes its intrinsics from the driver's
// camera_info (and says that their uncertainty is not in the 1-sigma figures).
TEST_F(RosImageTopicTest, WithoutACalibrationFileTheDriversCameraInfoGivesTheIntrinsics) {
  ASSERT_NO_FATAL_FAILURE(StartService(75, "ceiling_distance_m: 1.6"));
  auto publisher = Publish("sensor", "mono8", 30,
                           "1624.34,1623.04,634.77,499.02,-0.07021,0.07348,-0.00112,0.00267");
  auto r = RunMonocle(dir_, "corner locate --camera front --domain 75 --count 6 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err << ReadFile(dir_ / "monocled.log");
  const auto lines = Words(r.out);
  ASSERT_EQ(lines.size(), 6u) << r.out;
  int located = 0;
  for (const auto& w : lines) {
    const std::string line = w[0];
    // The pose's "x" (metres) comes after its "sigma":{"x":...} and before its "z".
    const auto z_at = line.find("\"z\":");
    if (z_at == std::string::npos) continue;  // the first frame may come before camera_info
    const auto x_at = line.rfind("\"x\":", z_at);
    const double x = std::stod(line.substr(x_at + 4));
    // Any of the three frames: within 1 % of the horizontal distance of the nearest truth.
    double nearest = 1e9;
    for (const auto& t : truth_) nearest = std::min(nearest, std::abs(x - t.x));
    EXPECT_LT(nearest, 0.01 * 2.5) << line;
    EXPECT_NE(line.find("\"sigma_excludes_intrinsics\":true"), std::string::npos)
        << "camera_info has no covariance, and the output says so: " << line;
    ++located;
  }
  EXPECT_GE(located, 5) << r.out;
  EXPECT_NE(ReadFile(dir_ / "monocled.log").find("takes its intrinsics from camera_info"),
            std::string::npos);
  EXPECT_EQ(publisher->Stop(), 0);
}

// What monocled does with any camera it does with an image topic's: after the first frame the
// driver's frames are tracked, and monocled's recording of them replays to the rendered truth.
TEST_F(RosImageTopicTest, AnImageTopicsFramesAreTrackedRecordedAndReplayed) {
  const std::string recording = dir_ / "front.mcap";
  ASSERT_NO_FATAL_FAILURE(StartService(77, "calibration: \"cal.pbtxt\"",
                                       {"--record", recording, "--record-frames", "every"}));
  auto publisher = Publish("sensor", "mono8", 60);
  auto r = RunMonocle(dir_, "corner locate --camera front --domain 77 --count 8 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err << ReadFile(dir_ / "monocled.log");
  int tracked = 0;
  for (const auto& live : LivePoses(r.out)) tracked += live.pose().source() == "tracked";
  EXPECT_GE(tracked, 6) << "each frame moves 1 cm (2 cm back after the third):\n" << r.out;
  EXPECT_EQ(publisher->Stop(), 0) << ReadFile(dir_ / "publisher.log");
  ASSERT_EQ(monocled_->Stop(), 0) << ReadFile(dir_ / "monocled.log");
  monocled_.reset();

  r = RunMonocle(dir_, "replay --json " + recording);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int replayed = 0;
  for (const auto& pose : LivePoses(r.out)) {
    ASSERT_FALSE(pose.pose().has_error()) << "every recorded frame gives a pose";
    // The stamp's nanoseconds name the frame.
    const size_t frame = static_cast<size_t>(pose.capture_time_ns() % 1000000000);
    ASSERT_LT(frame, truth_.size());
    EXPECT_LT(std::abs(pose.pose().x() - truth_[frame].x), 0.01 * 2.5) << r.out;
    ++replayed;
  }
  EXPECT_GE(replayed, 8) << "the frames of at least the 8 poses located live: " << r.out;
}

// A camera on an image topic in a room map: the driver's frames of the example hall (rendered
// along a short drive) give the robot's pose in the map, near the drive's truth.
TEST_F(RosImageTopicTest, AnImageTopicsFramesGiveTheRobotsPoseInARoomMap) {
  const std::string examples = std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/";
  std::ofstream(dir_ / "drive.txt") << "1.42 1.30 -20\n1.44 1.30 -20\n1.46 1.31 -19\n";
  auto r = RunMonocle(dir_, "render room --map " + examples + "room_map.pbtxt --mount " + examples +
                                "camera_mount.pbtxt --calibration " + examples +
                                "wide_camera.pbtxt --trajectory " + dir_ / "drive.txt" +
                                " --realistic --seed 6301 --out " + dir_ / "frames");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<Truth> truth{{1.42, 1.30, 0}, {1.44, 1.30, 0}, {1.46, 1.31, 0}};
  for (int i = 0; i < 3; ++i)
    frames_.push_back(dir_ / ("frames/frame_000" + std::to_string(i) + ".png"));
  domain_ = 78;
  monocled_ = StartMonocled(dir_,
                            "domain: 78\ncamera { id: \"front\" role: CORNER device: "
                            "\"ros:/camera/image_raw\" calibration: \"" +
                                examples + "wide_camera.pbtxt\" room_map: \"" + examples +
                                "room_map.pbtxt\" initial_pose: [1.4, 1.3, -20] mount { "
                                "base_frame: \"base_link\" translation_m: [0.1, 0, 0.4] "
                                "rotation_xyzw: [-0.2988362, 0.2988362, -0.6408564, "
                                "0.6408564] } }\n");
  auto publisher = Publish("sensor", "mono8", 60);
  r = RunMonocle(dir_, "corner locate --camera front --domain 78 --count 6 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err << ReadFile(dir_ / "monocled.log");
  int located = 0;
  for (const auto& live : LivePoses(r.out)) {
    if (live.pose().has_error()) continue;  // a realistic frame may show no corner clearly
    const auto& map = live.pose().map();
    ASSERT_EQ(map.status(), "located") << r.out;
    const size_t frame = static_cast<size_t>(live.capture_time_ns() % 1000000000);
    ASSERT_LT(frame, truth.size());
    EXPECT_LT(std::hypot(map.pose().x() - truth[frame].x, map.pose().y() - truth[frame].y), 0.06)
        << "frame " << frame << ": " << r.out;
    ++located;
  }
  EXPECT_GE(located, 4) << "of 6: " << r.out;
  EXPECT_EQ(publisher->Stop(), 0) << ReadFile(dir_ / "publisher.log");
}

// A floor camera on an image topic: calibrated live from the driver's frame of a board on the
// floor (written to its calibration file), then asked for floor points, which match those of
// the calibration the frame was rendered with.
TEST_F(RosImageTopicTest, AFloorCameraOnAnImageTopicCalibratesAndMeasures) {
  const std::string intrinsics =
      "intrinsics { width: 1280 height: 1024 fx: 1624.34 fy: 1623.04 cx: 634.77 cy: 499.02 "
      "distortion: [-0.07021, 0.07348, -0.00112, 0.00267] }\n";
  std::ofstream(dir_ / "truth.pbtxt")
      << intrinsics << "floor { height: 0.9 pitch: 2.2 yaw: 0 roll: 0.01 }\n";
  std::ofstream(dir_ / "down.pbtxt") << intrinsics;
  auto r = RunMonocle(dir_, "render floor --calibration " + dir_ / "truth.pbtxt" +
                                " --board 9x6 --square 0.05 --noise 2 --out " + dir_ / "board.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  frames_ = {dir_ / "board.png"};
  domain_ = 76;
  monocled_ = StartMonocled(dir_,
                            "domain: 76\ncamera { id: \"down\" role: FLOOR device: "
                            "\"ros:/down/image_raw\" calibration: \"down.pbtxt\" }\n");
  std::vector<std::string> args{"publish", "--domain", "76",        "--topic", "/down/image_raw",
                                "--rate",  "10",       "--seconds", "60",      frames_[0]};
  ChildProcess publisher(PeerBinary(), args, dir_ / "publisher.log");
  r = RunMonocle(dir_,
                 "floor calibrate --board 9x6 --square 0.05 --camera down --domain 76 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err << ReadFile(dir_ / "monocled.log");
  // The first (floor calibrate: before its sigma {}) or last (floor measure: after it) value.
  const auto number_after = [](const std::string& json, const std::string& key, bool last) {
    const std::string quoted = "\"" + key + "\":";
    const auto at = last ? json.rfind(quoted) : json.find(quoted);
    return at == std::string::npos ? -1.0 : std::stod(json.substr(at + quoted.size()));
  };
  EXPECT_NEAR(number_after(r.out, "height", false), 0.9, 0.01) << r.out;
  EXPECT_NE(ReadFile(dir_ / "down.pbtxt").find("floor"), std::string::npos)
      << "the calibration is written to the camera's file";
  const auto truth =
      RunMonocle(dir_, "floor measure 640,900 --calibration " + dir_ / "truth.pbtxt" + " --json");
  const auto live = RunMonocle(dir_, "floor measure 640,900 --camera down --domain 76 --json");
  ASSERT_EQ(truth.exit_code, 0) << truth.err;
  ASSERT_EQ(live.exit_code, 0) << live.err;
  // The point 0.76 m ahead, as the true calibration and the live one see it.
  EXPECT_NEAR(number_after(live.out, "y", true), number_after(truth.out, "y", true), 0.005)
      << live.out << truth.out;
  EXPECT_EQ(publisher.Stop(), 0);
}

}  // namespace
}  // namespace monocle::testing
