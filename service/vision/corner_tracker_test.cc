#include "service/vision/corner_tracker.h"

#include <gtest/gtest.h>

#include <random>

#include "camera/render/corner_renderer.h"
#include "service/geometry/corner_test_scenes.h"
#include "service/geometry/test_scenes.h"

namespace monocle {
namespace {

using testing::Deg;

// A robot driving under the corner: 1 cm and 0.25 degrees of pan per frame (7.5 degrees/s at
// 30 frames/s; the image moves ~8 px between frames).
std::vector<CornerPose> Trajectory(const CornerPose& start, int frames) {
  std::vector<CornerPose> out;
  for (int i = 0; i < frames; ++i) {
    CornerPose p = start;
    p.x_m += 0.01 * i;
    p.y_m -= 0.006 * i;
    p.pan_rad += Deg(0.25) * i;
    out.push_back(p);
  }
  return out;
}

cv::Mat RenderRealistic(const CameraIntrinsics& k, const CornerPose& pose, uint64_t look_seed,
                        uint64_t noise_seed) {
  CornerScene scene;
  scene.room_height_m = pose.z_m + 1.2;
  scene.realistic = RandomRealisticLook(look_seed, k);
  scene.seed = noise_seed;
  return RenderCornerScene(k, pose, scene);
}

double HorizontalError(const CornerPose& got, const CornerPose& truth) {
  return std::hypot(got.x_m - truth.x_m, got.y_m - truth.y_m) / std::hypot(truth.x_m, truth.y_m);
}

TEST(CornerTrackerTest, TracksARealisticStreamAsWellAsItDetects) {
  const CameraIntrinsics k = testing::PaperCamera();
  std::mt19937_64 rng(31);
  const auto start = testing::RandomRealisticCornerPose(rng, k, /*short_edge=*/false);
  ASSERT_TRUE(start);
  const auto truth = Trajectory(*start, 12);
  CornerTrackerOptions options;
  options.detect_every_n_frames = 6;
  CornerTracker tracker(k, start->z_m, options);
  std::vector<double> tracked_errors, detected_errors;
  std::vector<CornerSource> sources;
  for (size_t i = 0; i < truth.size(); ++i) {
    const cv::Mat frame = RenderRealistic(k, truth[i], 5, 100 + i);
    const auto got = tracker.Process(frame);
    ASSERT_TRUE(got.ok()) << "frame " << i << ": " << got.error();
    sources.push_back(got->source);
    if (!tracker.fallback_reason().empty())
      std::cout << "frame " << i << " detected: " << tracker.fallback_reason() << "\n";
    // Every frame also detected from scratch, for comparison.
    const auto detected = LocateCorner(frame, k, truth[i].z_m);
    ASSERT_TRUE(detected.ok()) << detected.error();
    detected_errors.push_back(HorizontalError(detected->pose, truth[i]));
    if (got->source == CornerSource::kTracked) {
      tracked_errors.push_back(HorizontalError(got->pose, truth[i]));
      EXPECT_NEAR(got->pose.tilt_rad, truth[i].tilt_rad, Deg(0.1)) << *got;
    }
  }
  // Frame 0 detected, then tracked, a full detection every 6 frames.
  for (size_t i = 0; i < sources.size(); ++i) {
    EXPECT_EQ(sources[i], i % 6 == 0 ? CornerSource::kDetected : CornerSource::kTracked)
        << "frame " << i;
  }
  ASSERT_GE(tracked_errors.size(), 8u);
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  const double tracked = median(tracked_errors), detected = median(detected_errors);
  std::cout << "median horizontal error: tracked " << 100 * tracked << " %, detected "
            << 100 * detected << " %\n";
  EXPECT_LT(tracked, 0.003);
  EXPECT_LT(tracked, 1.5 * detected + 0.0005);
}

TEST(CornerTrackerTest, FallsBackToDetectionWhenTheViewJumps) {
  const CameraIntrinsics k = testing::PaperCamera();
  std::mt19937_64 rng(32);
  const auto a = testing::RandomRealisticCornerPose(rng, k, false);
  ASSERT_TRUE(a);
  // Another view from the same ceiling distance (one per tracker), corner well in view.
  std::optional<CornerPose> b;
  while (!b) {
    b = testing::RandomRealisticCornerPose(rng, k, false);
    if (!b) continue;
    b->z_m = a->z_m;
    const auto lengths = testing::VisibleEdgeLengthsPx(*b, k);
    if (*std::min_element(lengths.begin(), lengths.end()) < 150) b.reset();
  }
  CornerTracker tracker(k, a->z_m);
  const auto first = tracker.Process(RenderRealistic(k, *a, 6, 1));
  ASSERT_TRUE(first.ok()) << first.error();
  EXPECT_EQ(first->source, CornerSource::kDetected);
  // A different view: the prediction finds nothing there, so the frame is detected.
  const auto second = tracker.Process(RenderRealistic(k, *b, 6, 2));
  ASSERT_TRUE(second.ok()) << second.error();
  EXPECT_EQ(second->source, CornerSource::kDetected);
  EXPECT_LT(HorizontalError(second->pose, *b), 0.01) << *second;
}

TEST(CornerTrackerTest, AFrameWithoutCornerIsAnErrorAndTheNextIsDetected) {
  const CameraIntrinsics k = testing::PaperCamera();
  std::mt19937_64 rng(33);
  const auto a = testing::RandomRealisticCornerPose(rng, k, false);
  ASSERT_TRUE(a);
  CornerTracker tracker(k, a->z_m);
  ASSERT_TRUE(tracker.Process(RenderRealistic(k, *a, 7, 1)).ok());
  const cv::Mat blank(k.height_px, k.width_px, CV_8UC1, cv::Scalar(128));
  EXPECT_FALSE(tracker.Process(blank).ok());
  const auto again = tracker.Process(RenderRealistic(k, *a, 7, 2));
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->source, CornerSource::kDetected);
}

}  // namespace
}  // namespace monocle

namespace monocle {
namespace {

// PredictEdgePx round trip: every predicted pixel, taken back through the lens
// (PixelToNormalized, the iterative inverse of the distortion PredictEdgePx applies), is a
// ray in the plane of the camera centre and the corner axis, on the axis's side of the corner.
TEST(PredictEdgePxTest, EveryPixelLooksAtTheAxisThroughTheLens) {
  for (const CameraIntrinsics& k : {testing::PaperCamera(), testing::SmallWideAngleCamera()}) {
    std::mt19937_64 rng(77);
    for (int view = 0; view < 5; ++view) {
      const auto pose = testing::RandomRealisticCornerPose(rng, k, /*short_edge=*/false);
      ASSERT_TRUE(pose);
      const Eigen::Vector3d corner_c = CornerToCamera(*pose, Eigen::Vector3d::Zero());
      for (int axis = 0; axis < 3; ++axis) {
        const Eigen::Vector3d far_c = CornerToCamera(*pose, Eigen::Vector3d::Unit(axis));
        const Eigen::Vector3d normal = corner_c.cross(far_c).normalized();
        const auto pixels = PredictEdgePx(k, *pose, axis, 5);
        ASSERT_GT(pixels.size(), 10u) << "axis " << axis << " of view " << view;
        for (const auto& px : pixels) {
          EXPECT_GE(px.x(), 0);
          EXPECT_GE(px.y(), 0);
          EXPECT_LE(px.x(), k.width_px - 1);
          EXPECT_LE(px.y(), k.height_px - 1);
          const auto n = PixelToNormalized(k, px);
          ASSERT_TRUE(n);
          const Eigen::Vector3d ray = Eigen::Vector3d(n->x(), n->y(), 1).normalized();
          // 1e-5 rad: a hundredth of a pixel at these focal lengths (the curve is resampled
          // along chords of 2 % steps, and the lens inverse is iterative).
          EXPECT_LT(std::abs(normal.dot(ray)), 1e-5) << "pixel " << px.transpose();
          // On the axis's side: the ray meets the axis at a positive distance from the corner.
          const Eigen::Vector3d across = normal.cross(far_c - corner_c);
          EXPECT_GT(ray.dot(across) * corner_c.dot(across), 0) << "pixel " << px.transpose();
        }
        // Consecutive pixels are `spacing` apart along the curve (to the chord's bending).
        for (size_t i = 1; i < pixels.size(); ++i)
          EXPECT_NEAR((pixels[i] - pixels[i - 1]).norm(), 5.0, 0.05);
      }
    }
  }
}

}  // namespace
}  // namespace monocle

namespace monocle {
namespace {

// The gate's width: the pose's uncertainty carried to pixels across each edge. Moving the
// camera along the corner's X axis slides the X edge along itself (it does not move across),
// while the Y and Z edges move; and the width grows in proportion to the uncertainty.
TEST(EdgeSigmaTest, ACameraSlidingAlongAnEdgeLeavesThatEdgeInPlace) {
  const CameraIntrinsics k = testing::PaperCamera();
  CornerPrediction prediction;
  prediction.pose = CornerPose{2.0, 1.5, 1.6, 2.2143, 0.9, 0.1};
  prediction.sigma << 0.01, 0, 0, 0, 0;  // 1 cm along x only
  const auto along_x = EdgeSigmaPx(k, prediction);
  EXPECT_LT(along_x[0], 0.01) << "the X edge";
  EXPECT_GT(along_x[1], 1.0) << "the Y edge";
  EXPECT_GT(along_x[2], 1.0) << "the Z edge";
  prediction.sigma *= 2;
  const auto doubled = EdgeSigmaPx(k, prediction);
  for (int axis = 1; axis < 3; ++axis)
    EXPECT_NEAR(doubled[axis], 2 * along_x[axis], 0.02 * along_x[axis]);
  // A turn of the camera moves every edge across itself: 0.01 rad of pan at f 1624 px is
  // up to about 16 px.
  prediction.sigma << 0, 0, 0.01, 0, 0;
  for (double px : EdgeSigmaPx(k, prediction)) {
    EXPECT_GT(px, 3);
    EXPECT_LT(px, 30);
  }
}

}  // namespace
}  // namespace monocle

namespace monocle {
namespace {

TEST(SuspectReasonKindsTest, EachReasonUpToItsFirstFigureOrColon) {
  const auto kinds = SuspectReasonKinds(
      "the edges' steps do not add up: 50.8 grey levels across one, 13.1 + 10.7 across the "
      "others; edge X found on 20 % of its visible length; edge Z contrast 2.1 grey levels");
  EXPECT_EQ(kinds, (std::set<std::string>{"the edges' steps do not add up", "edge X found on",
                                          "edge Z contrast"}));
  EXPECT_TRUE(SuspectReasonKinds("").empty());
}

}  // namespace
}  // namespace monocle
