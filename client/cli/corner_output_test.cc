// The corner overlay draws the edges the chosen pose predicts: with a pose turned by 2
// degrees the thin white curves leave the measured edges and run where that pose projects
// the corner's axes; with the located pose they lie on the measured edges.
#include "client/cli/corner_output.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>

#include "camera/render/corner_renderer.h"
#include "service/geometry/corner_test_scenes.h"
#include "service/geometry/test_scenes.h"
#include "service/vision/corner_tracker.h"

namespace monocle::cli {
namespace {

// Fraction of the pose's predicted edge pixels (away from the corner and the text) that are
// drawn white in `overlay`.
double WhiteAlongPrediction(const cv::Mat& overlay, const CameraIntrinsics& k,
                            const CornerLocation& location) {
  int white = 0, total = 0;
  for (int axis = 0; axis < 3; ++axis) {
    for (const auto& p : PredictEdgePx(k, location.pose, axis, 7)) {
      if ((p - location.corner_px).norm() < 40 || p.y() < 120 || p.y() > k.height_px - 40) continue;
      const cv::Vec3b c = overlay.at<cv::Vec3b>(static_cast<int>(std::lround(p.y())),
                                                static_cast<int>(std::lround(p.x())));
      white += c[0] > 110 && c[1] > 110 && c[2] > 110;
      ++total;
    }
  }
  EXPECT_GT(total, 50);
  return total > 0 ? static_cast<double>(white) / total : 0;
}

// A clean render of a corner in the paper camera, and its true pose.
struct RenderedCorner {
  CornerPose pose;
  cv::Mat image;
};
std::optional<RenderedCorner> RenderACorner(const CameraIntrinsics& k) {
  std::mt19937_64 rng(2024);
  const auto pose = testing::RandomRealisticCornerPose(rng, k, /*short_edge=*/false);
  if (!pose) return std::nullopt;
  CornerScene scene;
  scene.room_height_m = pose->z_m + 1.2;
  return RenderedCorner{*pose, RenderCornerScene(k, *pose, scene)};
}

TEST(CornerOverlayTest, DrawsTheEdgesTheChosenPosePredicts) {
  const CameraIntrinsics k = testing::PaperCamera();
  const auto rendered = RenderACorner(k);
  ASSERT_TRUE(rendered);
  const CornerPose* pose = &rendered->pose;
  const cv::Mat& image = rendered->image;
  auto located = LocateCorner(image, k, pose->z_m);
  ASSERT_TRUE(located.ok()) << located.error();

  CornerLocation turned = *located;
  turned.pose.pan_rad += testing::Deg(2);
  // Drawn on a black picture of the same size: whatever is white was drawn.
  const cv::Mat black = cv::Mat::zeros(image.size(), CV_8UC1);
  const cv::Mat drawn_turned = DrawCornerOverlay(black, k, turned);
  const cv::Mat drawn_located = DrawCornerOverlay(black, k, *located);
  // The turned pose's curves are drawn where it projects the axes...
  EXPECT_GT(WhiteAlongPrediction(drawn_turned, k, turned), 0.8);
  // ...which the located pose's picture does not paint white there.
  EXPECT_LT(WhiteAlongPrediction(drawn_located, k, turned), 0.2);
  // The located pose's own curves lie on the measured edges.
  EXPECT_GT(WhiteAlongPrediction(drawn_located, k, *located), 0.8);
}

// An error (or a suspect reason) wider than the picture is broken into lines that stay
// inside it, rather than running off its right edge.
TEST(CornerOverlayTest, ALongErrorIsWrappedInsideThePicture) {
  const CameraIntrinsics k = testing::PaperCamera();
  const cv::Mat black = cv::Mat::zeros(480, 640, CV_8UC1);
  const Result<CornerLocation> error = MakeError(
      ErrorCode::kNotFound,
      "no ceiling corner found: 3 straight edges found; 2 meet at (499, 181) px but the "
      "surfaces around them are saturated (white or black clipped), which hides the third; "
      "lower the exposure or gain");
  const cv::Mat drawn = DrawCornerOverlay(black, k, error);
  cv::Mat grey;
  cv::cvtColor(drawn, grey, cv::COLOR_BGR2GRAY);
  // Nothing drawn in the right margin...
  EXPECT_EQ(cv::countNonZero(grey.colRange(grey.cols - 8, grey.cols)), 0);
  // ...and the text runs on over several lines: drawn rows reach well below the first line.
  int lowest_drawn_row = 0;
  for (int y = 0; y < grey.rows; ++y)
    if (cv::countNonZero(grey.row(y)) > 0) lowest_drawn_row = y;
  EXPECT_GT(lowest_drawn_row, 32 + 2 * 30);
}

// Without a pose, the overlay still shows what the detector saw: its straight segments
// (orange) lie on the corner's edges, which a picture without edges does not get.
TEST(CornerOverlayTest, WithoutAPoseTheStraightSegmentsSeenAreDrawn) {
  const CameraIntrinsics k = testing::PaperCamera();
  const auto rendered = RenderACorner(k);
  ASSERT_TRUE(rendered);
  const CornerPose* pose = &rendered->pose;
  const cv::Mat& image = rendered->image;
  const Result<CornerLocation> error =
      MakeError(ErrorCode::kNotFound, "no ceiling corner found (as if)");
  auto orange_on_edges = [&](const cv::Mat& drawn) {
    int orange = 0, total = 0;
    for (int axis = 0; axis < 3; ++axis) {
      for (const auto& p : PredictEdgePx(k, *pose, axis, 7)) {
        if (p.y() < 120 || p.y() > k.height_px - 40 || p.x() < 2 || p.x() > k.width_px - 3)
          continue;
        ++total;
        // Within 2 px of the edge (the segments are drawn 2 px wide).
        bool near = false;
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const cv::Vec3b c = drawn.at<cv::Vec3b>(static_cast<int>(std::lround(p.y())) + dy,
                                                    static_cast<int>(std::lround(p.x())) + dx);
            near |= c[0] < 80 && c[1] > 150 && c[2] > 220;
          }
        orange += near;
      }
    }
    return total > 0 ? static_cast<double>(orange) / total : 0;
  };
  EXPECT_GT(orange_on_edges(DrawCornerOverlay(image, k, error)), 0.7);
  EXPECT_LT(
      orange_on_edges(DrawCornerOverlay(cv::Mat(image.size(), CV_8UC1, cv::Scalar(128)), k, error)),
      0.05);
}

}  // namespace
}  // namespace monocle::cli
