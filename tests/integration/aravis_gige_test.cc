// Frames through the real GigE Vision path: Aravis's simulated camera on 127.0.0.1, filled
// with our rendered scenes, read by AravisSource. Tests sharing the address never run in
// parallel (CTest RESOURCE_LOCK gige_loopback).
#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "camera/aravis/aravis_source.h"
#include "camera/aravis/reconnecting_source.h"
#include "camera/sim/sim_gv_camera.h"
#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"
#include "service/vision/corner_locator.h"

namespace monocle {
namespace {

using std::chrono::milliseconds;

SimCameraOptions SmallCorner() {
  SimCameraOptions o;
  o.scene = SimScene::kCorner;
  o.width = 640;
  o.height = 512;
  o.fps = 50;
  o.trajectory_frames = 6;
  return o;
}

TEST(AravisGigeTest, FramesMatchTheRendererAndTheGroundTruth) {
  auto sim = SimGvCamera::Start(SmallCorner());
  ASSERT_TRUE(sim.ok()) << sim.error();
  AravisOptions options;
  options.device = "127.0.0.1";
  options.region = std::array<int, 4>{0, 0, 640, 512};
  auto source = AravisSource::Open(options);
  ASSERT_TRUE(source.ok()) << source.error();
  EXPECT_EQ((*source)->info().protocol, "GigEVision");
  int compared = 0;
  uint64_t previous = 0;
  for (int i = 0; i < 12; ++i) {
    auto frame = (*source)->Next(milliseconds(3000));
    ASSERT_TRUE(frame.ok()) << frame.error();
    ASSERT_EQ(frame->grey.cols, 640);
    ASSERT_EQ(frame->grey.rows, 512);
    if (compared > 0) {
      EXPECT_GT(frame->sequence, previous);
    }
    previous = frame->sequence;
    // The pixels are exactly the frame rendered for this frame id.
    EXPECT_EQ(cv::norm(frame->grey, (*sim)->FrameFor(frame->sequence), cv::NORM_INF), 0)
        << "frame " << frame->sequence;
    EXPECT_GT(frame->capture_time_ns, 0);
    EXPECT_EQ(frame->time_source, TimeSource::kHost);
    ++compared;
  }
  // A received frame gives the pose the simulator says it shows. One pose of this short
  // trajectory puts the corner 42 px above the bottom border with its third edge out of the
  // picture (no Y to find): the first frame whose corner is 60 px or more inside is used.
  const auto corner_inside = [&](const CornerPose& pose) {
    const Eigen::Vector3d corner_camera =
        RotationCameraFromCorner(pose) * -Eigen::Vector3d(pose.x_m, pose.y_m, pose.z_m);
    const Eigen::Vector2d px = ProjectToPixel((*sim)->intrinsics(), corner_camera);
    return corner_camera.z() > 0 && px.x() >= 60 && px.y() >= 60 && px.x() <= 640 - 60 &&
           px.y() <= 512 - 60;
  };
  auto frame = (*source)->Next(milliseconds(3000));
  ASSERT_TRUE(frame.ok()) << frame.error();
  for (int i = 0; i < 12 && !corner_inside((*sim)->CornerPoseFor(frame->sequence)); ++i) {
    frame = (*source)->Next(milliseconds(3000));
    ASSERT_TRUE(frame.ok()) << frame.error();
  }
  const CornerPose truth = (*sim)->CornerPoseFor(frame->sequence);
  ASSERT_TRUE(corner_inside(truth)) << "frame " << frame->sequence;
  const auto located = LocateCorner(frame->grey, (*sim)->intrinsics(), truth.z_m);
  ASSERT_TRUE(located.ok()) << located.error();
  EXPECT_NEAR(located->pose.x_m, truth.x_m, 0.01 * truth.x_m);
  EXPECT_NEAR(located->pose.y_m, truth.y_m, 0.01 * truth.y_m);
  EXPECT_NEAR(located->pose.tilt_rad, truth.tilt_rad, 0.005);
}

struct BadConfig {
  const char* name;
  AravisOptions options;
  const char* message;
};

class AravisBadConfigTest : public ::testing::TestWithParam<BadConfig> {};

TEST_P(AravisBadConfigTest, IsAClearErrorNamingIt) {
  auto sim = SimGvCamera::Start(SmallCorner());
  ASSERT_TRUE(sim.ok()) << sim.error();
  const auto source = AravisSource::Open(GetParam().options);
  ASSERT_FALSE(source.ok());
  EXPECT_NE(source.error().message.find(GetParam().message), std::string::npos) << source.error();
}

AravisOptions With(std::function<void(AravisOptions&)> change) {
  AravisOptions o;
  o.device = "127.0.0.1";
  change(o);
  return o;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, AravisBadConfigTest,
    ::testing::Values(BadConfig{"UnknownCamera",
                                With([](AravisOptions& o) { o.device = "no-such-camera"; }),
                                "no camera 'no-such-camera'"},
                      BadConfig{"UnknownFeature", With([](AravisOptions& o) {
                                  o.features = {{"NoSuchFeature", "1"}};
                                }),
                                "unknown GenICam feature 'NoSuchFeature'"},
                      BadConfig{"FrameRateOutOfRange",
                                With([](AravisOptions& o) { o.frame_rate_hz = 5000; }),
                                "frame rate 5000 Hz is out of the camera's range"},
                      BadConfig{"RegionTooLarge", With([](AravisOptions& o) {
                                  o.region = std::array<int, 4>{0, 0, 9000, 512};
                                }),
                                "region width 9000 px is out of the camera's range"},
                      BadConfig{"UnsupportedPixelFormat",
                                With([](AravisOptions& o) { o.pixel_format = "YUV422Packed"; }),
                                "unsupported pixel format 'YUV422Packed'"}),
    [](const auto& info) { return info.param.name; });

// Issue 14: monocled stopping while its in-process simulated camera rendered its frames
// waited for all of them (over 10 s under ThreadSanitizer). The open gives up between
// frames once asked to stop: one frame rendered, not eight, and no camera.
TEST(AravisGigeTest, OpeningTheInProcessSimulatorStopsWhenCancelled) {
  int asked = 0;
  AravisOptions options;
  options.device = "sim-corner";
  options.cancelled = [&asked] { return ++asked > 1; };
  const auto source = AravisSource::Open(options);
  ASSERT_FALSE(source.ok());
  EXPECT_EQ(source.error().code, ErrorCode::kCancelled) << source.error();
  EXPECT_EQ(asked, 2);  // asked before the first frame and before the second, then gave up

  // Without the request to stop it opens and streams.
  options.cancelled = [] { return false; };
  auto opened = AravisSource::Open(options);
  ASSERT_TRUE(opened.ok()) << opened.error();
  EXPECT_TRUE((*opened)->Next(milliseconds(5000)).ok());
}

// Two cameras of one service open on two threads at start-up. Aravis parses GenICam
// descriptions with shared state: without AravisSetupMutex this crashed or left a camera
// "without" Mono8 (an empty pixel format list, taken as a configuration error for good).
TEST(AravisGigeTest, TwoCamerasOpenAtOnce) {
  for (int round = 0; round < 10; ++round) {
    std::vector<std::string> errors(2);
    std::vector<std::thread> threads;
    for (int t = 0; t < 2; ++t) {
      threads.emplace_back([&errors, t] {
        AravisOptions options;
        options.device = "sim-floor";
        auto opened = AravisSource::Open(options);
        if (!opened) {
          errors[t] = opened.error().message;
        } else if (!(*opened)->Next(milliseconds(5000))) {
          errors[t] = "no frame";
        }
      });
    }
    for (auto& th : threads) th.join();
    EXPECT_EQ(errors[0], "") << "round " << round;
    EXPECT_EQ(errors[1], "") << "round " << round;
  }
}

TEST(AravisGigeTest, LossIsReportedAndTheSameCameraResumes) {
  auto sim = SimGvCamera::Start(SmallCorner());
  ASSERT_TRUE(sim.ok()) << sim.error();
  AravisOptions options;
  options.device = "127.0.0.1";
  options.region = std::array<int, 4>{0, 0, 640, 512};
  std::vector<SourceState> states;
  std::chrono::steady_clock::time_point reported_lost{}, reported_back{};
  ReconnectingSource source(
      options,
      [&](SourceState s, const std::string& why) {
        std::cout << (s == SourceState::kStreaming ? "streaming" : "reconnecting: ") << why << "\n";
        (s == SourceState::kStreaming ? reported_back : reported_lost) =
            std::chrono::steady_clock::now();
        states.push_back(s);
      },
      milliseconds(500));
  ASSERT_TRUE(source.Next(milliseconds(5000)).ok());
  ASSERT_EQ(source.state(), SourceState::kStreaming);

  // The camera goes away mid-stream.
  const auto stopping = std::chrono::steady_clock::now();
  sim->reset();
  // Aravis's simulator takes a while to shut down its threads; it stops sending at once.
  const auto stopped = std::chrono::steady_clock::now();
  std::cout << "simulated camera shut down in "
            << std::chrono::duration<double, std::milli>(stopped - stopping).count() << " ms\n";
  while (source.state() == SourceState::kStreaming &&
         std::chrono::steady_clock::now() - stopped < std::chrono::seconds(30)) {
    (void)source.Next(milliseconds(200));
  }
  ASSERT_EQ(source.state(), SourceState::kReconnecting);

  // And comes back on the same address.
  auto restarted_sim = SimGvCamera::Start(SmallCorner());
  ASSERT_TRUE(restarted_sim.ok()) << restarted_sim.error();
  const auto restarted = std::chrono::steady_clock::now();
  Result<Frame> frame = MakeError(ErrorCode::kNotFound, "");
  while (!frame.ok() && std::chrono::steady_clock::now() - restarted < std::chrono::seconds(20)) {
    frame = source.Next(milliseconds(1000));
  }
  ASSERT_TRUE(frame.ok()) << frame.error();
  EXPECT_EQ(source.state(), SourceState::kStreaming);
  EXPECT_EQ(cv::norm(frame->grey, (*restarted_sim)->FrameFor(frame->sequence), cv::NORM_INF), 0);
  using ms = std::chrono::duration<double, std::milli>;
  std::cout << "loss reported " << ms(reported_lost - stopped).count()
            << " ms after the camera stopped; resumed " << ms(reported_back - restarted).count()
            << " ms after it returned\n";
  ASSERT_GE(states.size(), 2u);
}

}  // namespace
}  // namespace monocle
