// Tracking the corner while the robot drives (issue 62): realistic 1280x1024 sequences at
// 30 fps of an upward camera on a robot at 0.3, 0.6 and 1.0 m/s turning 10-45 deg/s, each
// frame blurred over a 4 ms exposure, through a narrow (f ~ 1600 px) and a wide (f 700 px)
// lens. Goals: >= 80 % of frames tracked at every speed, >= 95 % with a pose, tracked poses as
// accurate as detected ones (median and p95), nothing more than 5 % off unflagged.
// MONOCLE_DRIVING_SEED=N renders and judges another seed.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "camera/render/corner_renderer.h"
#include "camera/render/driving_path.h"
#include "camera/sim/sim_gv_camera.h"
#include "service/geometry/test_scenes.h"
#include "service/vision/corner_tracker.h"

namespace monocle {
namespace {

constexpr double kFps = 30, kExposureS = 0.004;
constexpr int kFrames = 60;

struct Drive {
  double speed_mps, turn_deg_per_s;
};
constexpr Drive kDrives[] = {{0.3, 10}, {0.6, 25}, {1.0, 45}};

struct SequenceStats {
  int frames = 0, tracked = 0, with_pose = 0, unflagged_over_5pct = 0;
  std::vector<double> tracked_rel, detected_rel;  // horizontal error / distance
  double track_ms = 0;
  int track_calls = 0;
};

double HorizontalRelError(const CornerPose& got, const CornerPose& truth) {
  return std::hypot(got.x_m - truth.x_m, got.y_m - truth.y_m) / std::hypot(truth.x_m, truth.y_m);
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))];
}

SequenceStats RunSequence(const CameraIntrinsics& k, const Drive& drive, uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  DrivingPath path;
  path.speed_mps = drive.speed_mps;
  path.turn_deg_per_s = drive.turn_deg_per_s;
  path.loop_bearing_rad = uniform(0.55, 1.0);
  path.loop_centre_distance_m = uniform(2.3, 2.9);
  path.start_s = uniform(0, 20);
  CornerScene scene;
  scene.room_height_m = path.ceiling_distance_m + 1.2;
  scene.realistic = RandomRealisticLook(seed, k);
  scene.motion_samples = 3;
  CornerTracker tracker(k, path.ceiling_distance_m);
  SequenceStats s;
  for (int i = 0; i < kFrames; ++i) {
    const double t = i / kFps;
    const CornerPose truth = DrivingPoseAt(path, t);
    scene.exposure_end_pose = DrivingPoseAt(path, t + kExposureS / 2);
    scene.seed = seed * 1000 + i;
    const cv::Mat frame = RenderCornerScene(k, DrivingPoseAt(path, t - kExposureS / 2), scene);
    const auto start = std::chrono::steady_clock::now();
    const auto got = tracker.Process(frame, t);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    ++s.frames;
    const auto detected = LocateCorner(frame, k, path.ceiling_distance_m);
    if (detected) s.detected_rel.push_back(HorizontalRelError(detected->pose, truth));
    if (!got) {
      std::cout << "  frame " << i << ": no pose: " << got.error().message << "\n";
      continue;
    }
    ++s.with_pose;
    const double rel = HorizontalRelError(got->pose, truth);
    if (rel > 0.05 && !got->suspect) ++s.unflagged_over_5pct;
    if (got->source == CornerSource::kTracked) {
      ++s.tracked;
      s.tracked_rel.push_back(rel);
      s.track_ms += ms;
      ++s.track_calls;
    } else if (i > 0 && i % CornerTrackerOptions{}.detect_every_n_frames != 0) {
      std::cout << "  frame " << i << " detected: " << tracker.fallback_reason() << "\n";
    }
  }
  return s;
}

void JudgeSeed(uint64_t seed) {
  const CameraIntrinsics lenses[] = {testing::PaperCamera(), SimRoomIntrinsics(1280, 1024)};
  const char* lens_names[] = {"narrow f 1624 px", "wide f 700 px"};
  for (int lens = 0; lens < 2; ++lens) {
    for (const Drive& drive : kDrives) {
      const SequenceStats s = RunSequence(lenses[lens], drive, seed + 7 * lens);
      // Frame 0 and every 30th are detections by design: they count as not tracked.
      const double tracked = static_cast<double>(s.tracked) / s.frames;
      const double posed = static_cast<double>(s.with_pose) / s.frames;
      std::cout << lens_names[lens] << ", " << drive.speed_mps << " m/s, " << drive.turn_deg_per_s
                << " deg/s: tracked " << 100 * tracked << " %, pose " << 100 * posed
                << " %, horizontal error median/p95 tracked "
                << 100 * Percentile(s.tracked_rel, 0.5) << " / "
                << 100 * Percentile(s.tracked_rel, 0.95) << " %, detected "
                << 100 * Percentile(s.detected_rel, 0.5) << " / "
                << 100 * Percentile(s.detected_rel, 0.95) << " %, tracking "
                << (s.track_calls ? s.track_ms / s.track_calls : 0) << " ms/frame\n";
      SCOPED_TRACE(std::string(lens_names[lens]) + " at " + std::to_string(drive.speed_mps) +
                   " m/s");
      EXPECT_GE(tracked, 0.80);
      EXPECT_GE(posed, 0.95);
      EXPECT_EQ(s.unflagged_over_5pct, 0);
      // As accurate as detection: within a quarter (or 0.05 % of the distance) of it.
      EXPECT_LE(Percentile(s.tracked_rel, 0.5), 1.25 * Percentile(s.detected_rel, 0.5) + 0.0005);
      EXPECT_LE(Percentile(s.tracked_rel, 0.95), 1.25 * Percentile(s.detected_rel, 0.95) + 0.0005);
    }
  }
}

TEST(CornerDrivingTest, TracksAtDrivingSpeed) { JudgeSeed(6201); }

TEST(CornerDrivingTest, FreshSeedOnDemand) {
  const char* text = std::getenv("MONOCLE_DRIVING_SEED");
  if (text == nullptr || *text == '\0')
    GTEST_SKIP() << "set MONOCLE_DRIVING_SEED=N to render and judge another seed";
  JudgeSeed(std::strtoull(text, nullptr, 10));
}

}  // namespace
}  // namespace monocle
