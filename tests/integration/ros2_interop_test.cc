// A ROS 2 node's view of monocled: readers written only from ROS 2's message definitions
// (tests/integration/ros2_wire.idl, none of monocle's headers or types), with ROS 2's QoS
// profiles, on a plain Cyclone DDS participant in this process; monocled runs its embedded
// default (the simulated cameras sim-corner and sim-floor) in another.
#include <dds/dds.h>
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "tests/integration/cli_process.h"
#include "tests/integration/ros2_wire.h"

namespace {

using monocle::testing::ChildProcess;
using monocle::testing::ReadFile;
using monocle::testing::TempDir;

constexpr dds_domainid_t kDomain = 41;

std::string MonocledBinary() {
  const std::string bin = monocle::testing::MonocleBinary();
  return bin.substr(0, bin.rfind("/client/")) + "/service/monocled";
}

// rmw_qos_profile_default and rmw_qos_profile_sensor_data.
dds_qos_t* RosQos(bool sensor_data) {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, sensor_data ? DDS_RELIABILITY_BEST_EFFORT : DDS_RELIABILITY_RELIABLE,
                       DDS_MSECS(100));
  dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, sensor_data ? 5 : 10);
  return qos;
}

class Ros2InteropTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string config = std::string(MONOCLE_SOURCE_DIR) + "/docker/cyclonedds-loopback.xml";
    setenv("CYCLONEDDS_URI", ("file://" + config).c_str(), 1);
    monocled_ =
        std::make_unique<ChildProcess>(MonocledBinary(),
                                       std::vector<std::string>{"--domain", std::to_string(kDomain),
                                                                "--state-dir", dir_ / "state"},
                                       dir_ / "monocled.log");
    participant_ = dds_create_participant(kDomain, nullptr, nullptr);
    ASSERT_GT(participant_, 0);
  }
  void TearDown() override {
    dds_delete(participant_);
    EXPECT_EQ(monocled_->Stop(), 0) << ReadFile(dir_ / "monocled.log");
  }

  dds_entity_t Reader(const dds_topic_descriptor_t* type, const char* topic, bool sensor_data) {
    dds_qos_t* qos = RosQos(sensor_data);
    const dds_entity_t t = dds_create_topic(participant_, type, topic, qos, nullptr);
    const dds_entity_t r = t > 0 ? dds_create_reader(participant_, t, qos, nullptr) : t;
    dds_delete_qos(qos);
    return r;
  }

  // Takes samples from `reader` until `accept` returns true for one (then true) or `timeout`.
  template <typename T>
  bool TakeUntil(dds_entity_t reader, std::chrono::seconds timeout,
                 const std::function<bool(const T&)>& accept) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      void* samples[4] = {};
      dds_sample_info_t infos[4];
      const int n = dds_take(reader, samples, infos, 4, 4);
      bool done = false;
      for (int i = 0; i < n && !done; ++i) {
        if (infos[i].valid_data) done = accept(*static_cast<const T*>(samples[i]));
      }
      if (n > 0) dds_return_loan(reader, samples, n);
      if (done) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  TempDir dir_{"monocle_ros2_interop"};
  std::unique_ptr<ChildProcess> monocled_;
  dds_entity_t participant_ = 0;
};

double NowS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

double StampS(const builtin_interfaces_msg_dds__Time_& t) { return t.sec + 1e-9 * t.nanosec; }

TEST_F(Ros2InteropTest, DefaultQosReadersReceivePoseTfCameraInfoImageAndDiagnostics) {
  const auto pose_reader = Reader(&geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc,
                                  "rt/monocle/sim_corner/pose", false);
  const auto tf_reader = Reader(&tf2_msgs_msg_dds__TFMessage__desc, "rt/tf", false);
  const auto info_reader =
      Reader(&sensor_msgs_msg_dds__CameraInfo__desc, "rt/monocle/sim_floor/camera_info", false);
  // rviz and rqt_image_view subscribe to images with the sensor-data profile (best effort).
  const auto image_reader =
      Reader(&sensor_msgs_msg_dds__Image__desc, "rt/monocle/sim_corner/image_raw", true);
  const auto diagnostics_reader =
      Reader(&diagnostic_msgs_msg_dds__DiagnosticArray__desc, "rt/diagnostics", false);
  for (auto r : {pose_reader, tf_reader, info_reader, image_reader, diagnostics_reader})
    ASSERT_GT(r, 0);
  constexpr std::chrono::seconds kWait{40};

  // The pose of the camera in the corner frame: the ceiling 1.6 m above the camera (the
  // simulated room's), inside the room, a unit quaternion, a covariance ROS can use.
  geometry_msgs_msg_dds__PoseWithCovarianceStamped_ pose{};
  std::string pose_frame;
  ASSERT_TRUE(TakeUntil<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>(pose_reader, kWait,
                                                                           [&](const auto& p) {
                                                                             pose = p;
                                                                             pose_frame =
                                                                                 p.header.frame_id;
                                                                             return true;
                                                                           }))
      << ReadFile(dir_ / "monocled.log");
  EXPECT_EQ(pose_frame, "corner");
  EXPECT_NEAR(StampS(pose.header.stamp), NowS(), 60);
  const auto& position = pose.pose.pose.position;
  EXPECT_NEAR(position.z, 1.6, 1e-9);
  EXPECT_GT(position.x, 0);
  EXPECT_GT(position.y, 0);
  const auto& q = pose.pose.pose.orientation;
  EXPECT_NEAR(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w, 1, 1e-9);
  const double* c = pose.pose.covariance;
  for (int i : {0, 7, 21, 28, 35}) EXPECT_GT(c[i], 0) << "diagonal " << i / 6;
  EXPECT_EQ(c[14], 0);  // z: the ceiling distance is given, not measured
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < a; ++b) EXPECT_DOUBLE_EQ(c[6 * a + b], c[6 * b + a]);
  // 1 sigma of a centimetre to decimetres and of well under a degree: a usable pose.
  EXPECT_LT(std::sqrt(c[0]), 0.2);
  EXPECT_LT(std::sqrt(c[35]), 0.05);

  // tf: corner -> sim_corner_optical, the same transform as some pose.
  bool tf_ok = TakeUntil<tf2_msgs_msg_dds__TFMessage_>(tf_reader, kWait, [&](const auto& m) {
    if (m.transforms._length != 1) return false;
    const auto& t = m.transforms._buffer[0];
    EXPECT_STREQ(t.header.frame_id, "corner");
    EXPECT_STREQ(t.child_frame_id, "sim_corner_optical");
    EXPECT_NEAR(t.transform.translation.z, 1.6, 1e-9);
    const auto& r = t.transform.rotation;
    EXPECT_NEAR(r.x * r.x + r.y * r.y + r.z * r.z + r.w * r.w, 1, 1e-9);
    return true;
  });
  EXPECT_TRUE(tf_ok);

  // camera_info of the floor camera, plumb_bob (OpenCV's k1 k2 p1 p2 k3).
  bool info_ok =
      TakeUntil<sensor_msgs_msg_dds__CameraInfo_>(info_reader, kWait, [&](const auto& info) {
        EXPECT_EQ(info.width, 1280u);
        EXPECT_EQ(info.height, 1024u);
        EXPECT_STREQ(info.distortion_model, "plumb_bob");
        EXPECT_EQ(info.d._length, 5u);
        EXPECT_GT(info.k[0], 100);  // fx
        EXPECT_EQ(info.k[8], 1);
        EXPECT_EQ(info.p[0], info.k[0]);  // P = [K | 0]
        EXPECT_EQ(info.p[3], 0);
        EXPECT_EQ(info.p[10], 1);
        EXPECT_STREQ(info.header.frame_id, "sim_floor_optical");
        return true;
      });
  EXPECT_TRUE(info_ok);

  // The live image, mono8, as the camera sees the ceiling corner.
  bool image_ok = TakeUntil<sensor_msgs_msg_dds__Image_>(image_reader, kWait, [&](const auto& im) {
    EXPECT_STREQ(im.encoding, "mono8");
    EXPECT_EQ(im.step, im.width);
    EXPECT_EQ(im.data._length, static_cast<uint32_t>(im.width * im.height));
    EXPECT_EQ(im.width, 1280u);
    int lo = 255, hi = 0;
    for (uint32_t i = 0; i < im.data._length; i += 97) {
      lo = std::min<int>(lo, im.data._buffer[i]);
      hi = std::max<int>(hi, im.data._buffer[i]);
    }
    EXPECT_GT(hi - lo, 20) << "a picture, not a blank buffer";
    return true;
  });
  EXPECT_TRUE(image_ok);

  // Diagnostics: both cameras, streaming (OK) once they run, their device as hardware id.
  bool both_ok = TakeUntil<diagnostic_msgs_msg_dds__DiagnosticArray_>(
      diagnostics_reader, kWait, [&](const auto& d) {
        int ok = 0;
        for (uint32_t i = 0; i < d.status._length; ++i) {
          const auto& s = d.status._buffer[i];
          const std::string name = s.name;
          if ((name == "monocle: sim-corner" || name == "monocle: sim-floor") && s.level == 0 &&
              std::string(s.hardware_id).rfind("sim-", 0) == 0 && s.values._length > 0)
            ++ok;
        }
        return ok == 2;
      });
  EXPECT_TRUE(both_ok) << ReadFile(dir_ / "monocled.log");
}

// A ROS 2 service client as rmw_cyclonedds makes one: a request writer and a reply reader
// with ROS's default QoS, guid = the request writer's instance handle.
struct RosServiceClient {
  dds_entity_t writer = 0, reader = 0;
  uint64_t guid = 0;
};

RosServiceClient OpenClient(dds_entity_t participant, const std::string& service) {
  RosServiceClient c;
  dds_qos_t* qos = RosQos(false);
  const dds_entity_t rq =
      dds_create_topic(participant, &monocle_msgs_srv_dds__MeasurePoints_Request__desc,
                       ("rq" + service + "Request").c_str(), qos, nullptr);
  const dds_entity_t rr =
      dds_create_topic(participant, &monocle_msgs_srv_dds__MeasurePoints_Response__desc,
                       ("rr" + service + "Reply").c_str(), qos, nullptr);
  c.reader = dds_create_reader(participant, rr, qos, nullptr);
  c.writer = dds_create_writer(participant, rq, qos, nullptr);
  dds_delete_qos(qos);
  dds_instance_handle_t handle = 0;
  dds_get_instance_handle(c.writer, &handle);
  c.guid = handle;
  return c;
}

// Both directions matched, as rclcpp's wait_for_service.
bool WaitForService(const RosServiceClient& c, std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    dds_publication_matched_status_t pub{};
    dds_subscription_matched_status_t sub{};
    dds_get_publication_matched_status(c.writer, &pub);
    dds_get_subscription_matched_status(c.reader, &sub);
    if (pub.current_count > 0 && sub.current_count > 0) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

void Ask(const RosServiceClient& c, int64_t seq, double u, double v) {
  monocle_msgs_srv_dds__MeasurePoints_Request_ request{};
  request.guid = c.guid;
  request.seq = seq;
  request.u = {1, 1, &u, false};
  request.v = {1, 1, &v, false};
  ASSERT_EQ(dds_write(c.writer, &request), 0);
}

struct Answer {
  uint64_t guid = 0;
  int64_t seq = 0;
  uint32_t status = 99;
  double y = 0, sigma_y = 0;
};

TEST_F(Ros2InteropTest, ServiceCallsWithTheRmwHeaderGetTheirOwnRepliesBack) {
  const std::string service = "/monocle/sim_floor/measure_points";
  const RosServiceClient a = OpenClient(participant_, service);
  const RosServiceClient b = OpenClient(participant_, service);
  ASSERT_GT(a.writer, 0);
  ASSERT_GT(b.writer, 0);
  ASSERT_NE(a.guid, b.guid);
  ASSERT_TRUE(WaitForService(a, std::chrono::seconds(40))) << ReadFile(dir_ / "monocled.log");
  ASSERT_TRUE(WaitForService(b, std::chrono::seconds(40)));

  // Both ask at once, with sequence numbers of their own; a's pixel is nearer the camera.
  Ask(a, 7, 640, 900);
  Ask(b, 1234, 640, 700);
  // Every reply travels on the one reply topic: each client's reader sees both and must keep
  // only those with its own guid, as rmw_cyclonedds does.
  auto collect = [&](const RosServiceClient& c) {
    std::vector<Answer> seen;
    TakeUntil<monocle_msgs_srv_dds__MeasurePoints_Response_>(c.reader, std::chrono::seconds(20),
                                                             [&](const auto& r) {
                                                               Answer x{r.guid, r.seq, r.status};
                                                               if (r.y._length == 1) {
                                                                 x.y = r.y._buffer[0];
                                                                 x.sigma_y = r.sigma_y._buffer[0];
                                                               }
                                                               seen.push_back(x);
                                                               return seen.size() == 2;
                                                             });
    return seen;
  };
  for (const auto* c : {&a, &b}) {
    const auto seen = collect(*c);
    ASSERT_EQ(seen.size(), 2u) << ReadFile(dir_ / "monocled.log");
    int own = 0;
    for (const auto& r : seen) {
      ASSERT_TRUE(r.guid == a.guid || r.guid == b.guid) << "a reply to nobody: guid " << r.guid;
      EXPECT_EQ(r.status, 0u);  // REQUEST_OK
      if (r.guid != c->guid) continue;
      ++own;
      // The request's own seq echoed, and the answer to its own pixel.
      EXPECT_EQ(r.seq, c == &a ? 7 : 1234);
      EXPECT_GT(r.y, 0.2);
      EXPECT_GT(r.sigma_y, 0);
    }
    EXPECT_EQ(own, 1);
  }
  // The same two answers, told apart only by guid: a's pixel lies nearer.
  std::map<uint64_t, double> y_by_guid;
  Ask(a, 8, 640, 900);
  Ask(b, 1235, 640, 700);
  for (const auto* c : {&a, &b}) {
    for (const auto& r : collect(*c)) {
      if (r.guid == c->guid) y_by_guid[r.guid] = r.y;
    }
  }
  ASSERT_EQ(y_by_guid.size(), 2u);
  EXPECT_LT(y_by_guid[a.guid], y_by_guid[b.guid]);
}

TEST_F(Ros2InteropTest, AMountedCameraGivesTheRobotsBaseOnTfAndTheMountOnTfStatic) {
  // The default service has written the simulated cameras' calibrations; restart with the
  // corner camera mounted on a robot: 0.3 m ahead of base_link, 1.0 m up, looking up.
  for (int i = 0; i < 400 && ReadFile(dir_ / "monocled.log").find("serving on DDS domain") ==
                                 std::string::npos;
       ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_EQ(monocled_->Stop(), 0) << ReadFile(dir_ / "monocled.log");
  std::ofstream(dir_ / "state/mounted.pbtxt") << R"(
camera {
  id: "sim-corner" device: "sim-corner" role: CORNER calibration: "sim-corner.pbtxt"
  mount { base_frame: "base_link" translation_m: [0.3, 0, 1.0] rotation_xyzw: [0, 0, 0, 1] }
}
)";
  monocled_ = std::make_unique<ChildProcess>(
      MonocledBinary(),
      std::vector<std::string>{"--domain", std::to_string(kDomain), "--config",
                               dir_ / "state/mounted.pbtxt"},
      dir_ / "monocled.log");
  // tf_static as ROS's static broadcaster gives it: reliable, transient-local, keep-last 1.
  dds_qos_t* qos = RosQos(false);
  dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
  const dds_entity_t static_topic = dds_create_topic(
      participant_, &tf2_msgs_msg_dds__TFMessage__desc, "rt/tf_static", qos, nullptr);
  const dds_entity_t static_reader = dds_create_reader(participant_, static_topic, qos, nullptr);
  dds_delete_qos(qos);
  ASSERT_GT(static_reader, 0);
  const auto tf_reader = Reader(&tf2_msgs_msg_dds__TFMessage__desc, "rt/tf", false);
  const auto pose_reader = Reader(&geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc,
                                  "rt/monocle/sim_corner/pose", false);

  bool mount_ok = TakeUntil<tf2_msgs_msg_dds__TFMessage_>(
      static_reader, std::chrono::seconds(40), [&](const auto& m) {
        if (m.transforms._length != 1) return false;
        const auto& t = m.transforms._buffer[0];
        EXPECT_STREQ(t.header.frame_id, "base_link");
        EXPECT_STREQ(t.child_frame_id, "sim_corner_optical");
        EXPECT_EQ(t.transform.translation.x, 0.3);
        EXPECT_EQ(t.transform.translation.z, 1.0);
        return true;
      });
  ASSERT_TRUE(mount_ok) << ReadFile(dir_ / "monocled.log");

  // corner -> base_link on /tf; with the identity rotation of the mount the base sits
  // 1.0 m below the camera and 0.3 m behind it along the camera's own x axis.
  std::map<int64_t, std::array<double, 3>> base_by_stamp, camera_by_stamp;
  auto stamp = [](const builtin_interfaces_msg_dds__Time_& t) {
    return static_cast<int64_t>(t.sec) * 1000000000 + t.nanosec;
  };
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(40);
  bool matched = false;
  while (!matched && std::chrono::steady_clock::now() < deadline) {
    TakeUntil<tf2_msgs_msg_dds__TFMessage_>(tf_reader, std::chrono::seconds(1), [&](const auto& m) {
      for (uint32_t i = 0; i < m.transforms._length; ++i) {
        const auto& t = m.transforms._buffer[i];
        EXPECT_STREQ(t.header.frame_id, "corner");
        EXPECT_STREQ(t.child_frame_id, "base_link");
        const auto& p = t.transform.translation;
        base_by_stamp[stamp(t.header.stamp)] = {p.x, p.y, p.z};
      }
      return false;
    });
    TakeUntil<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>(
        pose_reader, std::chrono::seconds(1), [&](const auto& p) {
          const auto& q = p.pose.pose.position;
          camera_by_stamp[stamp(p.header.stamp)] = {q.x, q.y, q.z};
          return false;
        });
    for (const auto& [t, base] : base_by_stamp) {
      const auto it = camera_by_stamp.find(t);
      if (it == camera_by_stamp.end()) continue;
      // The camera is 1.0 m above the base (the ceiling frame's z runs from the ceiling
      // down to the camera, so the base is 1.0 m further from the ceiling) and 0.3 m from
      // it horizontally.
      const auto& cam = it->second;
      const double dx = cam[0] - base[0], dy = cam[1] - base[1], dz = cam[2] - base[2];
      EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + dz * dz), std::sqrt(0.3 * 0.3 + 1.0 * 1.0), 1e-9);
      matched = true;
      break;
    }
  }
  EXPECT_TRUE(matched) << base_by_stamp.size() << " tf, " << camera_by_stamp.size() << " poses";
}

// Every ROS endpoint (rt/, rq/, rr/) of monocled's participant as this participant's
// built-in topics show it: its participant GUID, and its readers' and writers' GUIDs.
struct RemoteEndpoints {
  std::string participant;  // the GUID's 16 bytes as text
  std::set<std::string> readers, writers;
};

std::string GuidText(const unsigned char* v) {
  return std::string(reinterpret_cast<const char*>(v), 16);
}
std::string GidText(const char* data) { return std::string(data, 16); }

RemoteEndpoints MonocledEndpoints(dds_entity_t participant) {
  RemoteEndpoints out;
  for (const auto& [topic, into] : {std::pair{DDS_BUILTIN_TOPIC_DCPSPUBLICATION, &out.writers},
                                    std::pair{DDS_BUILTIN_TOPIC_DCPSSUBSCRIPTION, &out.readers}}) {
    const dds_entity_t reader = dds_create_reader(participant, topic, nullptr, nullptr);
    std::vector<void*> samples(4096, nullptr);
    std::vector<dds_sample_info_t> infos(4096);
    const int n = dds_read(reader, samples.data(), infos.data(), 4096, 4096);
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto* e = static_cast<const dds_builtintopic_endpoint_t*>(samples[i]);
      const std::string name = e->topic_name;
      // monocled's pose writer names its participant.
      if (name == "rt/monocle/sim_corner/pose") out.participant = GuidText(e->participant_key.v);
    }
    for (int i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      const auto* e = static_cast<const dds_builtintopic_endpoint_t*>(samples[i]);
      const std::string name = e->topic_name;
      const bool ros =
          name.rfind("rt/", 0) == 0 || name.rfind("rq/", 0) == 0 || name.rfind("rr/", 0) == 0;
      if (ros && GuidText(e->participant_key.v) == out.participant)
        into->insert(GuidText(e->key.v));
    }
    if (n > 0) dds_return_loan(reader, samples.data(), n);
    dds_delete(reader);
  }
  return out;
}

// ros_discovery_info as rmw_dds_common's GraphCache reads it (reliable, transient-local).
dds_entity_t DiscoveryReader(dds_entity_t participant, const dds_topic_descriptor_t* type) {
  dds_qos_t* qos = RosQos(false);
  dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
  const dds_entity_t topic =
      dds_create_topic(participant, type, "ros_discovery_info", qos, nullptr);
  const dds_entity_t reader =
      topic > 0 ? dds_create_reader(participant, topic, qos, nullptr) : topic;
  dds_delete_qos(qos);
  return reader;
}

// `ros2 node list` finds monocled: its participant's ParticipantEntitiesInfo (Iron-and-later
// layout, the default) names the node /monocled with every ROS reader and writer it has.
TEST_F(Ros2InteropTest, RosDiscoveryInfoNamesTheNodeAndEveryEndpoint) {
  const dds_entity_t reader =
      DiscoveryReader(participant_, &rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc);
  ASSERT_GT(reader, 0);
  RemoteEndpoints monocled;
  for (int i = 0; i < 400 && (monocled.participant.empty() || monocled.readers.empty()); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    monocled = MonocledEndpoints(participant_);
  }
  ASSERT_FALSE(monocled.participant.empty()) << ReadFile(dir_ / "monocled.log");
  std::set<std::string> readers, writers;
  const bool found = TakeUntil<rmw_dds_common_msg_dds__ParticipantEntitiesInfo_>(
      reader, std::chrono::seconds(40), [&](const auto& info) {
        if (GidText(info.gid.data) != monocled.participant) return false;
        EXPECT_EQ(info.node_entities_info_seq._length, 1u);
        if (info.node_entities_info_seq._length != 1) return true;
        const auto& node = info.node_entities_info_seq._buffer[0];
        EXPECT_STREQ(node.node_name, "monocled");
        EXPECT_STREQ(node.node_namespace, "/");
        for (uint32_t i = 0; i < node.reader_gid_seq._length; ++i)
          readers.insert(GidText(node.reader_gid_seq._buffer[i].data));
        for (uint32_t i = 0; i < node.writer_gid_seq._length; ++i)
          writers.insert(GidText(node.writer_gid_seq._buffer[i].data));
        return true;
      });
  ASSERT_TRUE(found) << ReadFile(dir_ / "monocled.log");
  EXPECT_EQ(writers, monocled.writers);
  EXPECT_EQ(readers, monocled.readers);
  EXPECT_GE(writers.size(), 10u);
  EXPECT_GE(readers.size(), 3u);  // the services' request readers
}

// With `ros_discovery_info: "humble"` the Gid is Humble's 24 bytes: the GUID, then zeros.
TEST_F(Ros2InteropTest, RosDiscoveryInfoInHumblesLayoutWhenConfigured) {
  for (int i = 0; i < 400 && ReadFile(dir_ / "monocled.log").find("serving on DDS domain") ==
                                 std::string::npos;
       ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_EQ(monocled_->Stop(), 0) << ReadFile(dir_ / "monocled.log");
  std::ofstream(dir_ / "state/humble.pbtxt") << R"(
ros_discovery_info: "humble"
camera { id: "sim-corner" device: "sim-corner" role: CORNER calibration: "sim-corner.pbtxt" }
)";
  monocled_ = std::make_unique<ChildProcess>(
      MonocledBinary(),
      std::vector<std::string>{"--domain", std::to_string(kDomain), "--config",
                               dir_ / "state/humble.pbtxt"},
      dir_ / "monocled.log");
  // A Humble node's type: its own layout under rmw_dds_common's type name.
  const dds_topic_descriptor_t& d = humble_msg_dds__ParticipantEntitiesInfo__desc;
  const dds_topic_descriptor_t humble = {
      d.m_size,
      d.m_align,
      d.m_flagset,
      d.m_nkeys,
      rmw_dds_common_msg_dds__ParticipantEntitiesInfo__desc.m_typename,
      d.m_keys,
      d.m_nops,
      d.m_ops,
      d.m_meta,
      {},
      {},
      d.restrict_data_representation};
  const dds_entity_t reader = DiscoveryReader(participant_, &humble);
  ASSERT_GT(reader, 0);
  RemoteEndpoints monocled;
  for (int i = 0; i < 400 && monocled.participant.empty(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    monocled = MonocledEndpoints(participant_);
  }
  ASSERT_FALSE(monocled.participant.empty()) << ReadFile(dir_ / "monocled.log");
  const bool found = TakeUntil<humble_msg_dds__ParticipantEntitiesInfo_>(
      reader, std::chrono::seconds(40), [&](const auto& info) {
        if (GidText(info.gid.data) != monocled.participant) return false;
        EXPECT_EQ(std::string(info.gid.data + 16, 8), std::string(8, '\0'));
        EXPECT_EQ(info.node_entities_info_seq._length, 1u);
        if (info.node_entities_info_seq._length == 1) {
          const auto& node = info.node_entities_info_seq._buffer[0];
          EXPECT_STREQ(node.node_name, "monocled");
          std::set<std::string> writers;
          for (uint32_t i = 0; i < node.writer_gid_seq._length; ++i)
            writers.insert(GidText(node.writer_gid_seq._buffer[i].data));
          EXPECT_EQ(writers, monocled.writers);
        }
        return true;
      });
  EXPECT_TRUE(found) << ReadFile(dir_ / "monocled.log");
}

}  // namespace
