// monocled with a room map: the simulated GigE Vision camera (`monocle simcam --scene room`)
// drives the example hall, monocled places every pose in the map, and separate processes read
// it as users do: `monocle corner locate --camera --json` (the client library) against the
// ground truth by frame id, and a plain ROS 2-style reader (the test's own message IDL) on
// <namespace>/map_pose and /tf (map -> base_link).
#include <dds/dds.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <thread>

#include "idl/cli_output.pb.h"
#include "service/io/base_trajectory_file.h"
#include "tests/integration/room_drive.h"
#include "tests/integration/ros2_wire.h"
#include "tests/integration/service_process.h"

namespace monocle {
namespace {

using testing::RunMonocle;
using testing::TempDir;

constexpr int kDomain = 95;
const std::string kExamples = std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/";

// Takes samples until `accept` says enough, or the time is up.
template <typename T>
void TakeFor(dds_entity_t reader, std::chrono::seconds timeout,
             const std::function<bool(const T&)>& accept) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    void* samples[8] = {};
    dds_sample_info_t infos[8];
    const int n = dds_take(reader, samples, infos, 8, 8);
    bool done = false;
    for (int i = 0; i < n && !done; ++i)
      if (infos[i].valid_data) done = accept(*static_cast<const T*>(samples[i]));
    if (n > 0) dds_return_loan(reader, samples, n);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

double DistanceToPath(const std::vector<BasePose2d>& path, double x, double y) {
  double best = 1e9;
  for (const auto& p : path) best = std::min(best, std::hypot(p.x_m - x, p.y_m - y));
  return best;
}

TEST(RoomMapServiceTest, PosesInTheMapFrameOnTheWireAndOnTf) {
  TempDir dir("monocle_room_map_service");
  const auto truth = LoadBaseTrajectoryFile(kExamples + "drive.txt");
  ASSERT_TRUE(truth.ok());
  std::unique_ptr<testing::ChildProcess> simcam;
  ASSERT_NO_FATAL_FAILURE(testing::StartRoomDrive(dir, "5", "10", &simcam));
  auto monocled = testing::StartMonocled(
      dir, "domain: " + std::to_string(kDomain) + testing::RoomDriveCameraConfig());
  // A ROS 2 node's readers (default QoS), from the test's own IDL.
  const dds_entity_t participant = dds_create_participant(kDomain, nullptr, nullptr);
  ASSERT_GT(participant, 0);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
  const dds_entity_t map_pose_topic =
      dds_create_topic(participant, &geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc,
                       "rt/monocle/front/map_pose", qos, nullptr);
  const dds_entity_t map_pose_reader = dds_create_reader(participant, map_pose_topic, qos, nullptr);
  const dds_entity_t tf_topic =
      dds_create_topic(participant, &tf2_msgs_msg_dds__TFMessage__desc, "rt/tf", qos, nullptr);
  const dds_entity_t tf_reader = dds_create_reader(participant, tf_topic, qos, nullptr);
  dds_delete_qos(qos);
  ASSERT_GT(map_pose_reader, 0);
  ASSERT_GT(tf_reader, 0);

  // The client library's view, by frame id against the truth (the drive loops: frame k shows
  // pose k mod 25, so the robot jumps back to the start every 25 frames).
  const auto r = RunMonocle(dir,
                            "corner locate --camera front --count 60 --json --timeout 60 "
                            "--domain " +
                                std::to_string(kDomain));
  ASSERT_EQ(r.exit_code, 0) << r.err << testing::ReadFile(dir / "monocled.log");
  int located = 0, no_corner = 0;
  std::map<std::string, int> statuses;
  std::stringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    proto::LivePoseOutput out;
    ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(line, &out).ok()) << line;
    if (out.pose().has_error()) {
      ++no_corner;
      continue;
    }
    ASSERT_TRUE(out.pose().has_map()) << "a map pose for every corner pose: " << line;
    const auto& m = out.pose().map();
    ++statuses[m.status()];
    if (m.status() != "located") continue;
    ++located;
    const BasePose2d& t = (*truth)[out.sequence() % truth->size()];
    EXPECT_LT(std::hypot(m.pose().x() - t.x_m, m.pose().y() - t.y_m), 0.06) << line;
    EXPECT_LT(std::abs(std::remainder(m.pose().heading_deg() - t.heading_rad * 180 / M_PI, 360)),
              0.5)
        << line;
    EXPECT_TRUE(m.pose().corner() == "hall-1" || m.pose().corner() == "hall-2") << line;
    EXPECT_GT(m.pose().sigma().x(), 0) << line;
  }
  std::cout << "60 frames: " << no_corner << " without a corner";
  for (const auto& [status, n] : statuses) std::cout << ", " << n << " " << status;
  std::cout << "\n";
  // The initial pose is where the drive starts, but the camera's frame counter is not: the
  // service starts anywhere on the looping drive, and again at each jump back to the start
  // must find the robot by the room alone (views near a corner are ambiguous until then).
  // Where on the loop the service starts decides how many frames pass before the room or the
  // start pose decides (29 to 45 of the 60 located in runs on a loaded 2-core machine); how
  // often, on a fixed drive, is room_map_accuracy_test's to judge. Here: every located pose
  // is right (above), and at least a third of the frames get one.
  // Under ThreadSanitizer monocled keeps up with a fraction of the frames: the robot then
  // moves further between processed frames than a prior's gates allow, and fewer are located.
  EXPECT_GE(located, testing::kThreadSanitizer ? 5 : 20);

  // map_pose in "map" and /tf map -> base_link, on the drive.
  int map_poses = 0;
  TakeFor<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>(
      map_pose_reader, std::chrono::seconds(10), [&](const auto& p) {
        EXPECT_STREQ(p.header.frame_id, "map");
        EXPECT_LT(DistanceToPath(*truth, p.pose.pose.position.x, p.pose.pose.position.y), 0.06);
        EXPECT_GT(p.pose.covariance[0], 0);
        EXPECT_GT(p.pose.covariance[35], 0) << "yaw";
        return ++map_poses >= 5;
      });
  EXPECT_GE(map_poses, 5);
  int transforms = 0;
  TakeFor<tf2_msgs_msg_dds__TFMessage_>(tf_reader, std::chrono::seconds(10), [&](const auto& m) {
    for (uint32_t i = 0; i < m.transforms._length; ++i) {
      const auto& t = m.transforms._buffer[i];
      EXPECT_STREQ(t.header.frame_id, "map");
      EXPECT_STREQ(t.child_frame_id, "base_link");
      EXPECT_NEAR(t.transform.translation.z, 0, 1e-9) << "the base on the floor";
      EXPECT_LT(DistanceToPath(*truth, t.transform.translation.x, t.transform.translation.y), 0.06);
      ++transforms;
    }
    return transforms >= 5;
  });
  EXPECT_GE(transforms, 5);
  dds_delete(participant);
  EXPECT_EQ(monocled->Stop(), 0) << testing::ReadFile(dir / "monocled.log");
  EXPECT_EQ(simcam->Stop(), 0);
}

}  // namespace
}  // namespace monocle
