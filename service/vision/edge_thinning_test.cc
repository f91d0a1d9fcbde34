#include "service/vision/edge_thinning.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "service/vision/edge_test_images.h"

namespace monocle::corner_detection {
namespace {

// The detector smooths the frame (Gaussian, sigma 1) before thinning it; so do these tests.
cv::Mat Smoothed(const cv::Mat& grey) {
  cv::Mat smooth;
  cv::GaussianBlur(grey, smooth, cv::Size(7, 7), 1.0, 1.0, cv::BORDER_REPLICATE);
  return smooth;
}

// A vertical step thins to one pixel per row, on the step, with its gradient across it.
TEST(EdgeThinningTest, AStepThinsToOnePixelPerRowOnTheStep) {
  const cv::Mat grey = testing::HalfPlaneStep(160, 120, 0, 80.0, 80, 160, 1.0, 2.0, 1);
  const auto edges = ThinEdges(Smoothed(grey), CornerDetectorOptions{});
  std::vector<int> per_row(120, 0);
  size_t off_step = 0;
  for (const EdgePixel& e : edges) {
    EXPECT_GE(e.vote_half_window, kMinVoteHalfWindow);
    EXPECT_LE(e.vote_half_window, kMaxVoteHalfWindow);
    if (std::abs(e.x - 80) > 1) {
      ++off_step;  // noise passing the threshold here and there: the Hough sorts it out
      continue;
    }
    EXPECT_GT(e.nx, 0.95f) << "on the step the gradient points across it, dark to bright";
    ++per_row[static_cast<int>(e.y)];
  }
  int rows_with_one = 0;
  for (int y = 4; y < 116; ++y) rows_with_one += per_row[y] == 1;
  EXPECT_GE(rows_with_one, 108) << "one edge pixel per row away from the image's border";
  EXPECT_LT(off_step, 160u * 120u / 50) << "noise passes the threshold rarely";
}

// The threshold follows the image's noise: noise alone passes it at about the same small rate
// whatever its level above the floor of min_edge_gradient (a fixed threshold would pass four
// times the noise everywhere).
TEST(EdgeThinningTest, NoiseAlonePassesAtTheSameSmallRateAtAnyLevel) {
  std::vector<size_t> counts;
  for (double noise : {3.0, 6.0, 12.0}) {
    const cv::Mat grey = testing::HalfPlaneStep(160, 120, 0, 1000.0, 100, 100, 1.0, noise, 2);
    counts.push_back(ThinEdges(Smoothed(grey), CornerDetectorOptions{}).size());
    EXPECT_LT(counts.back(), 160u * 120u / 40) << "noise sigma " << noise;
  }
  EXPECT_LT(counts[2], 3 * counts[0] + 30) << counts[0] << " at sigma 3, " << counts[2] << " at 12";
  EXPECT_LT(counts[0], 3 * counts[2] + 30) << counts[0] << " at sigma 3, " << counts[2] << " at 12";
}

// A faint step among strong noise is an edge where the noise is low, not where it is high.
TEST(EdgeThinningTest, AFaintStepStandsOutOnlyAboveTheNoise) {
  const cv::Mat quiet = testing::HalfPlaneStep(160, 120, 0, 80.0, 100, 112, 1.0, 0.5, 3);
  const cv::Mat loud = testing::HalfPlaneStep(160, 120, 0, 80.0, 100, 112, 1.0, 12.0, 3);
  auto on_step = [](const std::vector<EdgePixel>& edges) {
    int n = 0;
    for (const auto& e : edges) n += std::abs(e.x - 80) <= 1;
    return n;
  };
  EXPECT_GE(on_step(ThinEdges(Smoothed(quiet), CornerDetectorOptions{})), 100);
  EXPECT_LT(on_step(ThinEdges(Smoothed(loud), CornerDetectorOptions{})), 60);
}

}  // namespace
}  // namespace monocle::corner_detection
