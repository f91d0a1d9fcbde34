// HalveImage against cv::resize(INTER_AREA) pixel for pixel: frame sizes, widths that are
// not a multiple of the 8 pixels done at once, a region of a larger image (rows not
// contiguous), odd sizes (handed to OpenCV), and every grey level at the rounding's edges.
#include "service/vision/halve_image.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace monocle {
namespace {

void ExpectSameAsOpenCv(const cv::Mat& src, const std::string& what) {
  cv::Mat ours, theirs;
  HalveImage(src, &ours);
  cv::resize(src, theirs, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  ASSERT_EQ(ours.size(), theirs.size()) << what;
  EXPECT_EQ(cv::norm(ours, theirs, cv::NORM_INF), 0) << what;
}

TEST(HalveImageTest, GivesOpenCvsAreaHalving) {
  cv::RNG rng(11);
  for (const auto& [cols, rows] :
       {std::pair{1280, 1024}, std::pair{640, 512}, std::pair{2, 2}, std::pair{18, 6},
        std::pair{30, 34}, std::pair{646, 20}, std::pair{17, 10}, std::pair{20, 11}}) {
    cv::Mat image(rows, cols, CV_8UC1);
    rng.fill(image, cv::RNG::UNIFORM, 0, 256);
    ExpectSameAsOpenCv(image, std::to_string(cols) + "x" + std::to_string(rows));
  }
  // Only 0 and 255, and sums just around each rounding step.
  cv::Mat extremes(64, 64, CV_8UC1);
  rng.fill(extremes, cv::RNG::UNIFORM, 0, 2);
  ExpectSameAsOpenCv(extremes * 255, "0 and 255");
  cv::Mat steps(64, 256, CV_8UC1);
  for (int y = 0; y < steps.rows; ++y)
    for (int x = 0; x < steps.cols; ++x)
      steps.at<uint8_t>(y, x) = static_cast<uint8_t>(x + (y & 1) * (x % 4));
  ExpectSameAsOpenCv(steps, "rounding steps");
  // A region whose rows are not contiguous in memory.
  cv::Mat large(100, 300, CV_8UC1);
  rng.fill(large, cv::RNG::UNIFORM, 0, 256);
  ExpectSameAsOpenCv(large(cv::Rect(3, 5, 90, 40)), "region");
}

}  // namespace
}  // namespace monocle
