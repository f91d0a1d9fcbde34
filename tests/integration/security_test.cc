// DDS Security end to end: a keystore made here by `monocle security init` (a fresh CA per
// run), monocled in its own process with its identity, and clients with and without one.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <linux/if_ether.h>
#include <linux/if_packet.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <mutex>
#include <thread>

#include "camera/sim/sim_gv_camera.h"
#include "idl/protocol/convert.h"
#include "idl/protocol/service_endpoints.h"
#include "idl/protocol/wire.h"
#include "monocle/client.h"
#include "service/io/calibration_file.h"
#include "tests/integration/service_process.h"

namespace monocle {
namespace {

using namespace std::chrono_literals;
using testing::ReadFile;
using testing::RunMonocle;
using testing::TempDir;

constexpr int kDomain = 51;

class SecurityTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir("monocle_security");
    const auto made = RunMonocle(
        *dir_, "security init " + *dir_ / "keys" + " --client op:operator --client viewer:reader");
    ASSERT_EQ(made.exit_code, 0) << made.err;
    // A second CA: its identities are well-formed but foreign to the service.
    const auto other =
        RunMonocle(*dir_, "security init " + *dir_ / "other" + " --client mallory:operator");
    ASSERT_EQ(other.exit_code, 0) << other.err;
    CameraCalibration floor;
    floor.intrinsics = SimIntrinsics(1280, 1024);
    floor.floor = FloorCalibration{};
    floor.floor->pose = SimFloorPose();
    ASSERT_TRUE(SaveCalibrationFileAtomically(*dir_ / "floor.pbtxt", floor).ok());
    CameraCalibration corner;
    corner.intrinsics = SimIntrinsics(1280, 1024);
    ASSERT_TRUE(SaveCalibrationFileAtomically(*dir_ / "corner.pbtxt", corner).ok());
    monocled_ = testing::StartMonocled(*dir_, "domain: " + std::to_string(kDomain) + R"(
security_dir: "keys/monocled"
status_period_s: 0.25
camera { id: "floor" device: "sim-floor" role: FLOOR calibration: "floor.pbtxt" }
camera { id: "corner" device: "sim-corner" role: CORNER calibration: "corner.pbtxt"
         ceiling_distance_m: 1.6 }
)")
                    .release();
  }
  static void TearDownTestSuite() {
    if (monocled_ != nullptr) {
      EXPECT_EQ(monocled_->Stop(), 0) << ReadFile(*dir_ / "monocled.log");
      delete monocled_;
    }
    delete dir_;
  }

  static ClientResult<Client> Open(const std::string& identity, std::chrono::milliseconds t) {
    Client::Options o;
    o.domain = kDomain;
    o.timeout = t;
    if (!identity.empty()) o.security_dir = *dir_ / identity;
    return Client::open(o);
  }

  // Until the service's cameras stream (their simulators start slowly on a loaded machine).
  static void WaitForStreaming(Client& client) {
    const auto deadline = std::chrono::steady_clock::now() + 60s;
    while (std::chrono::steady_clock::now() < deadline) {
      auto st = client.status();
      size_t streaming = 0;
      if (st.ok()) {
        for (const auto& c : *st) streaming += c.state == CameraState::kStreaming && c.frames > 0;
      }
      if (streaming == 2) return;
      std::this_thread::sleep_for(200ms);
    }
    ADD_FAILURE() << "cameras not streaming: " << ReadFile(*dir_ / "monocled.log");
  }

  static TempDir* dir_;
  static testing::ChildProcess* monocled_;
};
TempDir* SecurityTest::dir_ = nullptr;
testing::ChildProcess* SecurityTest::monocled_ = nullptr;

TEST_F(SecurityTest, KeystoreHoldsEveryFileAndKeysArePrivate) {
  for (const char* id : {"monocled", "op", "viewer"}) {
    for (const char* f : {"identity_ca.pem", "permissions_ca.pem", "governance.p7s", "cert.pem",
                          "key.pem", "permissions.p7s"}) {
      EXPECT_TRUE(std::filesystem::is_regular_file(*dir_ / "keys" + "/" + id + "/" + f))
          << id << "/" << f;
    }
    const auto perms =
        std::filesystem::status(*dir_ / "keys" + "/" + id + "/key.pem").permissions();
    EXPECT_EQ(perms & (std::filesystem::perms::group_all | std::filesystem::perms::others_all),
              std::filesystem::perms::none)
        << id;
  }
  EXPECT_NE(ReadFile(*dir_ / "keys/viewer/permissions.p7s").find("get_poseRequest"),
            std::string::npos);
  EXPECT_EQ(ReadFile(*dir_ / "keys/viewer/permissions.p7s").find("calibrate_floorRequest"),
            std::string::npos);
  // Never overwritten.
  const auto again = RunMonocle(*dir_, "security init " + *dir_ / "keys" + " --client viewer");
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.err.find("exists already"), std::string::npos) << again.err;
}

TEST_F(SecurityTest, ReaderGetsPosesAndPointsButItsCalibrationIsRefusedAndTheFileUntouched) {
  auto viewer = Open("keys/viewer", 30s);
  ASSERT_TRUE(viewer.ok()) << viewer.error();
  WaitForStreaming(*viewer);
  auto pose = viewer->pose("corner", PoseWhich::kNextFrame);
  ASSERT_TRUE(pose.ok()) << pose.error() << ReadFile(*dir_ / "monocled.log");
  EXPECT_TRUE(pose->valid);
  auto points = viewer->measure("floor", {{640, 900, {}}});
  ASSERT_TRUE(points.ok()) << points.error();
  EXPECT_TRUE((*points)[0].ok());

  const std::string before = ReadFile(*dir_ / "floor.pbtxt");
  // The issue's attack: a wrong square size would have rewritten the height 10x.
  auto refused = viewer->calibrate_floor("floor", 11, 8, 0.5);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().code, ClientError::Code::kNotPermitted) << refused.error();
  EXPECT_NE(refused.error().message.find("operator"), std::string::npos) << refused.error();
  std::this_thread::sleep_for(500ms);
  EXPECT_EQ(ReadFile(*dir_ / "floor.pbtxt"), before);
  // The command line says the same.
  const auto cli = RunMonocle(*dir_,
                              "floor calibrate --camera floor --board 11x8 --square 0.5 "
                              "--timeout 20 --domain " +
                                  std::to_string(kDomain) + " --security " + *dir_ / "keys/viewer");
  EXPECT_EQ(cli.exit_code, 1);
  EXPECT_NE(cli.err.find("permissions"), std::string::npos) << cli.err;
  EXPECT_EQ(ReadFile(*dir_ / "floor.pbtxt"), before);
}

TEST_F(SecurityTest, OperatorMayCalibrate) {
  auto op = Open("keys/op", 30s);
  ASSERT_TRUE(op.ok()) << op.error();
  WaitForStreaming(*op);
  auto r = op->calibrate_floor("floor", 11, 8, 0.05);
  ASSERT_TRUE(r.ok()) << r.error() << ReadFile(*dir_ / "monocled.log");
  EXPECT_NEAR(r->floor.height_m, SimFloorPose().height_m, 0.01);
}

TEST_F(SecurityTest, ParticipantsWithoutAnIdentityOfThisCaSeeNothingAndGetNoAnswer) {
  // The monocle client without security, and one with a foreign CA's operator identity.
  for (const std::string identity : {"", "other/mallory"}) {
    auto c = Open(identity, 1500ms);
    ASSERT_TRUE(c.ok()) << c.error();
    auto st = c->status();
    EXPECT_TRUE(!st.ok() || st->empty()) << identity;
    auto r = c->measure("floor", {{640, 900, {}}});
    ASSERT_FALSE(r.ok()) << identity;
    EXPECT_EQ(r.error().code, ClientError::Code::kNoService) << identity << ": " << r.error();
  }
  // Raw DDS, as a hostile participant would: readers of every monocle topic receive nothing,
  // a request written on the service's request topic gets no reply.
  auto participant = dds::CreateParticipant(kDomain);
  ASSERT_TRUE(participant.ok());
  auto cameras = dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>::Open(
      *participant, &monocle_msgs_msg_dds__CameraStatus__desc, wire::kCamerasTopic, false, true,
      wire::kDirectoryReaderQos);
  auto calibrations = dds::Endpoint<monocle_msgs_msg_dds__Calibration_>::Open(
      *participant, &monocle_msgs_msg_dds__Calibration__desc, wire::kCalibrationsTopic, false, true,
      wire::kDirectoryReaderQos);
  auto poses = dds::Endpoint<monocle_msgs_msg_dds__CornerPose_>::Open(
      *participant, &monocle_msgs_msg_dds__CornerPose__desc,
      wire::CornerPoseTopic("/monocle/corner").c_str(), false, true, wire::kRosDefaultQos);
  ASSERT_TRUE(cameras.ok() && calibrations.ok() && poses.ok());
  auto points = dds::ServiceClient<monocle_msgs_srv_dds__MeasurePoints_Request_,
                                   monocle_msgs_srv_dds__MeasurePoints_Response_>::
      Open(*participant, &monocle_msgs_srv_dds__MeasurePoints_Request__desc,
           &monocle_msgs_srv_dds__MeasurePoints_Response__desc, "/monocle/floor",
           wire::kMeasurePoints);
  ASSERT_TRUE(points.ok());
  EXPECT_FALSE(points->WaitForService(1s));
  wire::PointRequestColumns columns;
  monocle_msgs_srv_dds__MeasurePoints_Request_ request{};
  wire::ToSample({{640, 900, {}}}, 0, &columns, &request);
  auto reply = points->Call<int>(
      request, 1s, [](const auto&) { return 1; }, 0ms);
  ASSERT_TRUE(reply.ok());
  EXPECT_FALSE(reply->has_value());
  size_t received = 0;
  const auto count = [](const auto&) { return 1; };
  for (int i = 0; i < 10; ++i) {
    received += cameras->Take<int>(50ms, count)->size();
    received += calibrations->Take<int>(50ms, count)->size();
    received += poses->Take<int>(50ms, count)->size();
  }
  EXPECT_EQ(received, 0u);
  EXPECT_FALSE(cameras->HasWriters());
}

// Every packet on the loopback interface, as a plain observer with a packet socket sees it.
class LoopbackSniffer {
 public:
  LoopbackSniffer() {
    fd_ = socket(AF_PACKET, SOCK_RAW, htons(ETH_P_ALL));
    if (fd_ < 0) return;
    sockaddr_ll addr{};
    addr.sll_family = AF_PACKET;
    addr.sll_protocol = htons(ETH_P_ALL);
    addr.sll_ifindex = static_cast<int>(if_nametoindex("lo"));
    timeval tv{0, 100000};
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    if (bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      close(fd_);
      fd_ = -1;
      return;
    }
    thread_ = std::thread([this] {
      std::vector<char> buf(1 << 16);
      while (!stop_) {
        const ssize_t n = recv(fd_, buf.data(), buf.size(), 0);
        if (n <= 0) continue;
        std::lock_guard<std::mutex> lock(mutex_);
        packets_.emplace_back(buf.data(), static_cast<size_t>(n));
      }
    });
  }
  ~LoopbackSniffer() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    if (fd_ >= 0) close(fd_);
  }
  bool ok() const { return fd_ >= 0; }
  std::vector<std::string> packets() {
    std::lock_guard<std::mutex> lock(mutex_);
    return packets_;
  }

 private:
  int fd_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::mutex mutex_;
  std::vector<std::string> packets_;
};

TEST_F(SecurityTest, NothingReadableOnTheWire) {
  LoopbackSniffer sniffer;
  ASSERT_TRUE(sniffer.ok()) << "a packet socket needs CAP_NET_RAW (run the tests as root)";
  // The sniffer sees plain text when there is some: a datagram of our own.
  {
    const int s = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(9);  // discard
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const std::string probe = "plain text probe: /monocle/floor sim-floor";
    sendto(s, probe.data(), probe.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
    close(s);
  }
  // A new client's whole life: discovery, status, a pose, points, the calibrations.
  {
    auto viewer = Open("keys/viewer", 30s);
    ASSERT_TRUE(viewer.ok()) << viewer.error();
    WaitForStreaming(*viewer);
    ASSERT_TRUE(viewer->pose("corner", PoseWhich::kNextFrame).ok());
    ASSERT_TRUE(viewer->measure("floor", {{640, 900, {}}}).ok());
    ASSERT_TRUE(viewer->calibrations().ok());
  }
  std::this_thread::sleep_for(300ms);
  const auto packets = sniffer.packets();
  // The authentication handshake carries each identity's certificate and signed permissions
  // in clear, as DDS Security specifies (they are public, the CA's signature is what counts);
  // everything else must be unreadable.
  size_t rtps = 0, probes = 0, handshakes = 0;
  std::vector<std::string> others;
  // Only this domain's packets: other tests' plain services may share the loopback. Cyclone
  // maps domain d to UDP ports 7400 + 250 d ... + 249 (Ethernet 14 bytes, IPv4, UDP).
  const auto in_domain = [](const std::string& p) {
    if (p.size() < 14 + 20 + 8 || static_cast<unsigned char>(p[12]) != 0x08 || p[13] != 0 ||
        p[14 + 9] != 17)
      return false;
    const size_t udp = 14 + 4 * (static_cast<unsigned char>(p[14]) & 0x0f);
    if (p.size() < udp + 8) return false;
    const int port =
        (static_cast<unsigned char>(p[udp + 2]) << 8) | static_cast<unsigned char>(p[udp + 3]);
    return port >= 7400 + 250 * kDomain && port < 7400 + 250 * (kDomain + 1);
  };
  for (const auto& p : packets) {
    if (p.find("plain text probe") != std::string::npos) {
      ++probes;
    } else if (!in_domain(p)) {
      continue;
    } else if (p.find("DDS:Auth:PKI-DH") != std::string::npos) {
      ++handshakes;
    } else {
      if (p.find("RTPS") != std::string::npos) ++rtps;
      others.push_back(p);
    }
  }
  EXPECT_GT(handshakes, 0u);
  EXPECT_GT(probes, 0u);
  EXPECT_GT(rtps, 20u);
  // Names of topics, cameras and namespaces, and the calibration's frame: all encrypted.
  for (const std::string needle : {"monocle/", "sim-floor", "sim-corner", "measure_points",
                                   "corner_pose", "floor.pbtxt", "sim_floor_optical"}) {
    size_t seen = 0;
    for (const auto& p : others) {
      if (p.find(needle) != std::string::npos) {
        if (seen++ == 0) {
          std::string printable;
          for (char c : p) printable += (c >= 32 && c < 127) ? c : '.';
          ADD_FAILURE() << "'" << needle << "' in a packet: " << printable;
        }
      }
    }
    EXPECT_EQ(seen, 0u) << "'" << needle << "' readable in " << seen << " of " << rtps
                        << " RTPS packets";
  }
}

}  // namespace
}  // namespace monocle
