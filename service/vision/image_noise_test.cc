#include "service/vision/image_noise.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>

#include "service/vision/edge_test_images.h"

namespace monocle {
namespace {

using testing::StepImage;
using testing::WithNoiseAs8Bit;

TEST(ImageNoiseTest, EstimatesTheNoiseOfAFlatImage) {
  for (double sigma : {1.0, 2.0, 3.0, 4.0}) {
    const cv::Mat image = StepImage(1000, 0, 0, 0, sigma, 7);  // no edge in view
    EXPECT_NEAR(EstimateNoiseSigma(image), sigma, 0.1 * sigma + 0.15) << sigma;
  }
  // A constant image: nothing below 8-bit quantization (1/sqrt(12) = 0.29 grey) can be told.
  EXPECT_LT(EstimateNoiseSigma(cv::Mat(100, 100, CV_8UC1, cv::Scalar(50))), 0.3);
  EXPECT_EQ(EstimateNoiseSigma(cv::Mat()), 0);
}

// Compression removes the pixel-to-pixel part of the noise but not what an edge measurement
// averages over: the measurement noise of a JPEG image is its sensor noise (within 25 % down
// to quality 70), where the pixel estimate reads 2-6x low. On a raw image the two agree, and
// a shading ramp and an edge in view do not move it.
// The noise estimate counts the small differences 16 at a time and falls back to a full
// histogram when the median is beyond them: either way it must be exactly the interpolated
// median of the whole histogram, written out here the plain way, for any width (the last
// pixels of a row are counted one by one), height and noise, including images so rough that
// the median is beyond the small bins.
double PlainNoiseEstimate(const cv::Mat& grey) {
  std::array<int64_t, 256> histogram{};
  int64_t count = 0;
  for (int y = 1; y < grey.rows; y += grey.rows >= 512 ? 8 : 4) {
    for (int x = 0; x + 1 < grey.cols; ++x) {
      const int a = grey.at<uint8_t>(y, x), b = grey.at<uint8_t>(y, x + 1);
      if (a >= 253 || a <= 2 || b >= 253 || b <= 2) continue;  // saturated: left out
      ++histogram[std::abs(b - a)];
      ++count;
    }
  }
  double below = 0;
  for (int d = 0; d < 256; ++d) {
    if (below + static_cast<double>(histogram[d]) >= 0.5 * static_cast<double>(count)) {
      const double lo = d == 0 ? 0.0 : d - 0.5, width = d == 0 ? 0.5 : 1.0;
      return (lo + width * (0.5 * static_cast<double>(count) - below) /
                       std::max<double>(static_cast<double>(histogram[d]), 1)) /
             (0.6745 * std::sqrt(2.0));
    }
    below += static_cast<double>(histogram[d]);
  }
  return 0;
}

TEST(ImageNoiseTest, TheNoiseEstimateIsTheWholeHistogramsMedian) {
  cv::RNG rng(2026);
  int beyond_small_bins = 0;
  for (const auto& [cols, rows] : {std::pair{1280, 1024}, std::pair{641, 513}, std::pair{37, 40},
                                   std::pair{17, 9}, std::pair{16, 5}, std::pair{2, 600}}) {
    for (double sigma : {0.0, 0.7, 3.0, 9.0, 40.0}) {
      cv::Mat image(rows, cols, CV_8UC1, cv::Scalar(128));
      cv::Mat noise(rows, cols, CV_32F);
      rng.fill(noise, cv::RNG::NORMAL, 128, sigma);
      noise.convertTo(image, CV_8U);
      ASSERT_EQ(EstimateNoiseSigma(image), PlainNoiseEstimate(image))
          << cols << "x" << rows << " sigma " << sigma;
      beyond_small_bins += PlainNoiseEstimate(image) * 0.6745 * std::sqrt(2.0) > 7.5;
    }
  }
  EXPECT_GE(beyond_small_bins, 4) << "the fall-back to the whole histogram was not exercised";
}

TEST(ImageNoiseTest, MeasurementNoiseSurvivesCompression) {
  for (double sigma : {2.0, 3.0, 4.0}) {
    cv::Mat lit(1024, 1280, CV_32F);
    for (int v = 0; v < lit.rows; ++v)
      for (int u = 0; u < lit.cols; ++u)  // a shading ramp (0.05 grey/px) and a 12-grey edge
        lit.at<float>(v, u) = static_cast<float>(140 + 0.05 * u + (u > 700 ? 12 : 0));
    cv::Mat noise(lit.size(), CV_32F);
    cv::RNG rng(static_cast<uint64_t>(sigma * 10));
    rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
    cv::Mat raw;
    cv::Mat(lit + noise).convertTo(raw, CV_8U);
    EXPECT_NEAR(EstimateMeasurementNoiseSigma(raw), sigma, 0.08 * sigma) << sigma;
    EXPECT_NEAR(EstimateMeasurementNoiseSigma(raw), EstimateNoiseSigma(raw), 0.1 * sigma);
    for (int quality : {90, 80, 70}) {
      std::vector<uint8_t> jpeg;
      cv::imencode(".jpg", raw, jpeg, {cv::IMWRITE_JPEG_QUALITY, quality});
      const cv::Mat compressed = cv::imdecode(jpeg, cv::IMREAD_GRAYSCALE);
      const double measured = EstimateMeasurementNoiseSigma(compressed);
      EXPECT_NEAR(measured, sigma, 0.25 * sigma) << sigma << " at quality " << quality;
      EXPECT_LT(EstimateNoiseSigma(compressed), 0.8 * measured) << sigma << " at " << quality;
    }
  }
  EXPECT_LT(EstimateMeasurementNoiseSigma(cv::Mat(100, 100, CV_8UC1, cv::Scalar(50))), 0.1);
  EXPECT_EQ(EstimateMeasurementNoiseSigma(cv::Mat()), 0);
}

// Glare that clips three quarters of the frame white (seed 1500001's view 3 of the realistic
// renders, JPEG at quality 74, sensor noise 3.5) left almost every neighbouring difference 0:
// the pixel estimate read 0.32 and the measurement estimate 0.07, and every edge stood 50x out
// of that noise. Saturated pixels are left out, so both read the unclipped part's noise, raw or
// compressed, and a frame clipped everywhere reads 0.
TEST(ImageNoiseTest, TheNoiseOfAFrameMostlyClippedIsTheUnclippedPartsNoise) {
  for (double sigma : {2.0, 3.5}) {
    cv::Mat lit(1024, 1280, CV_32F);
    for (int v = 0; v < lit.rows; ++v)
      for (int u = 0; u < lit.cols; ++u)  // glare: 300 grey (clipped) left of a diagonal
        lit.at<float>(v, u) = u < 0.75 * lit.cols + 0.2 * (v - 512) ? 300.0f : 170.0f + 0.03f * u;
    cv::Mat noise(lit.size(), CV_32F);
    cv::RNG rng(static_cast<uint64_t>(sigma * 100));
    rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
    cv::Mat raw;
    cv::Mat(lit + noise).convertTo(raw, CV_8U);
    ASSERT_GT(cv::countNonZero(raw == 255), 0.7 * static_cast<double>(raw.total()));
    EXPECT_NEAR(EstimateNoiseSigma(raw), sigma, 0.1 * sigma) << sigma;
    EXPECT_NEAR(EstimateMeasurementNoiseSigma(raw), sigma, 0.1 * sigma) << sigma;
    std::vector<uint8_t> jpeg;
    cv::imencode(".jpg", raw, jpeg, {cv::IMWRITE_JPEG_QUALITY, 74});
    const cv::Mat compressed = cv::imdecode(jpeg, cv::IMREAD_GRAYSCALE);
    EXPECT_NEAR(EstimateMeasurementNoiseSigma(compressed), sigma, 0.25 * sigma) << sigma;
  }
  EXPECT_EQ(EstimateNoiseSigma(cv::Mat(64, 64, CV_8UC1, cv::Scalar(255))), 0);
  EXPECT_EQ(EstimateMeasurementNoiseSigma(cv::Mat(64, 64, CV_8UC1, cv::Scalar(255))), 0);
}

}  // namespace
}  // namespace monocle
