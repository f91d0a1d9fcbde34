#include "service/vision/edge_profile.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <utility>

#include "service/vision/edge_test_images.h"

namespace monocle {
namespace {

using testing::StepImage;
using testing::WithNoiseAs8Bit;

// A bright wall under a lamp saturates the camera: the blurred step from 225 to 290 grey is
// cut at 255, and its steepest rise moves ~0.8 px towards the dark side. Such points are not
// measured at all; the same step below saturation is measured where it is.
TEST(EdgeProfileTest, RefusesAnEdgeBesideAClippedSurface) {
  const double edge_x = 200.3;
  const Eigen::Vector2d down(0, 1);
  const Eigen::Vector2d start(edge_x + 1, 60);
  const cv::Mat unclipped = StepImage(edge_x, 0, 65, 1.3, 2, 5, 150);
  const auto found = MeasureEdgeStretch(unclipped, start, down, 140, 2, 4, 0, 3);
  ASSERT_GT(found.size(), 120u);
  double mean_offset = 0;
  for (const auto& p : found) mean_offset += (p.point_px.x() - edge_x) / found.size();
  EXPECT_NEAR(mean_offset, 0, 0.05);

  const cv::Mat clipped = StepImage(edge_x, 0, 65, 1.3, 2, 5, 225);
  EXPECT_TRUE(MeasureEdgeStretch(clipped, start, down, 140, 2, 4, 0, 3).empty());
  std::vector<Eigen::Vector2d> positions, normals;
  for (int y = 60; y < 340; y += 2) {
    positions.emplace_back(edge_x + 1, y);
    normals.emplace_back(1, 0);
  }
  EXPECT_TRUE(MeasureEdgePoints(clipped, positions, normals, 4, 0, 3).empty());
  // Black clipping likewise: a step from -30 (cut at 0) to 35.
  const cv::Mat black = StepImage(edge_x, 0, 65, 1.3, 2, 5, -30);
  EXPECT_TRUE(MeasureEdgeStretch(black, start, down, 140, 2, 4, 0, 3).empty());
}

TEST(EdgeProfileTest, FindsAFaintEdgeAtItsSubpixelPlace) {
  // 6 grey levels at noise 3, blur 1.2 px: what a wall-wall edge in a white room looks like.
  const double edge_x = 200.37, angle = 0.2;
  const cv::Mat image = StepImage(edge_x, angle, 6, 1.2, 3, 11);
  const Eigen::Vector2d normal(std::cos(angle), -std::sin(angle));
  const Eigen::Vector2d along(normal.y(), -normal.x());  // so that `normal` is its left normal
  const Eigen::Vector2d start = Eigen::Vector2d(edge_x + 2, 200) - 120 * along;  // 2 px off
  const auto points = MeasureEdgeStretch(image, start, along, 120, 2, 4, 0, 3);
  ASSERT_GT(points.size(), 80u) << "most places find the edge";
  double sum = 0, sum2 = 0;
  for (const auto& p : points) {
    const double offset = (p.point_px - Eigen::Vector2d(edge_x, 200)).dot(normal);
    sum += offset;
    sum2 += offset * offset;
    EXPECT_GT(p.step_grey, 0) << "dark to bright along the normal";
  }
  const double mean = sum / points.size();
  const double scatter = std::sqrt(sum2 / points.size() - mean * mean);
  EXPECT_LT(scatter, 1.0) << "under a pixel at a contrast of twice the noise";
  // Unbiased within 3 standard errors (2 of every 7 points are independent: each averages
  // 7 px along the edge); a half-pixel convention error would be far outside.
  const double standard_error = scatter / std::sqrt(points.size() * 2.0 / 7.0);
  EXPECT_LT(std::abs(mean), 3 * standard_error) << "mean offset " << mean << " px";
  // The asked-for polarity only: the opposite finds (almost) nothing.
  EXPECT_LT(MeasureEdgeStretch(image, start, along, 120, 2, 4, -1, 3).size(), 10u);
}

// The blur of an edge is read off its samples: a step S blurred by sigma rises at most
// S / (sigma sqrt(2 pi)). The render's sigma is hypot(blur, 0.3) (a pixel's extent).
TEST(EdgeProfileTest, MeasuresTheBlurOfAnEdge) {
  const double angle = 0.2;
  const Eigen::Vector2d normal(std::cos(angle), -std::sin(angle));
  const Eigen::Vector2d along(normal.y(), -normal.x());
  for (double blur : {0.8, 1.2, 1.6, 2.0}) {
    const cv::Mat image = StepImage(200.4, angle, 30, blur, 1, 3);
    const Eigen::Vector2d start = Eigen::Vector2d(200.4, 200) - 120 * along;
    const double measured =
        EdgeBlurSigmaPx(MeasureEdgeStretch(image, start, along, 120, 2, 4, 0, 3));
    const double truth = std::hypot(blur, 0.3);
    EXPECT_NEAR(measured, truth, 0.15 * truth) << "blur " << blur;
  }
  EXPECT_EQ(EdgeBlurSigmaPx({}), 0);
  EXPECT_EQ(EdgeDerivativeSigmaPx(0.6), 0) << "a sharp edge keeps the default filter";
  EXPECT_DOUBLE_EQ(EdgeDerivativeSigmaPx(1.4), 1.6 * 1.4);
}

// A faint blurred edge (8 grey levels at noise 3, blur 1.5 px) measured with the default
// filter, the filter matched to its blur, and the one the locator uses (1.6x the blur): all
// unbiased on flat surfaces; the matched filter's points scatter less than the default's, and
// the wider filter's less again. (The matched filter is the best detector of a blurred step,
// but its peak is located with about a third of the pixels' information.)
TEST(EdgeProfileTest, AWiderFilterMeasuresABlurredEdgeMorePrecisely) {
  const double edge_x = 200.37, angle = 0.2, blur = 1.5;
  const Eigen::Vector2d normal(std::cos(angle), -std::sin(angle));
  const Eigen::Vector2d along(normal.y(), -normal.x());
  const Eigen::Vector2d start = Eigen::Vector2d(edge_x + 1, 200) - 120 * along;
  const double measured_blur = std::hypot(blur, 0.3);  // with the pixel's area
  const std::array<double, 3> filter_sigma_px{0.0, measured_blur,
                                              EdgeDerivativeSigmaPx(measured_blur)};
  std::array<double, 3> sum{}, sum2{};
  std::array<int, 3> count{};
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    const cv::Mat image = StepImage(edge_x, angle, 8, blur, 3, seed);
    for (int f = 0; f < 3; ++f) {
      for (const auto& p :
           MeasureEdgeStretch(image, start, along, 120, 2, 4, +1, 3, filter_sigma_px[f])) {
        const double offset = (p.point_px - Eigen::Vector2d(edge_x, 200)).dot(normal);
        sum[f] += offset;
        sum2[f] += offset * offset;
        ++count[f];
      }
    }
  }
  std::array<double, 3> scatter{};
  for (int f = 0; f < 3; ++f) {
    ASSERT_GT(count[f], 800) << "most places find the edge";
    const double mean = sum[f] / count[f];
    scatter[f] = std::sqrt(sum2[f] / count[f] - mean * mean);
    const double standard_error = scatter[f] / std::sqrt(count[f] * 2.0 / 7.0);
    EXPECT_LT(std::abs(mean), 3 * standard_error) << "filter " << f << " mean " << mean;
  }
  std::cout << "scatter: default " << scatter[0] << ", matched " << scatter[1] << ", 1.6x "
            << scatter[2] << " px\n";
  EXPECT_LT(scatter[1], 0.85 * scatter[0]);
  EXPECT_LT(scatter[2], 0.9 * scatter[1]);
}

// A vertical step edge at edge_x, blurred by `blur` (with a pixel's extent), whose two
// surfaces are shaded: the left one changes by `slope_left` grey levels a pixel towards the
// edge, the right one by `slope_right` away from it (grey levels per pixel along +x). The
// slopes are blurred with the step, as a lens blurs a room.
cv::Mat ShadedStepImage(double edge_x, double step, double blur, double slope_left,
                        double slope_right, double noise, uint64_t seed) {
  cv::Mat image(300, 400, CV_32F);
  const double sigma = std::hypot(blur, 0.3);
  for (int u = 0; u < image.cols; ++u) {
    const double d = u - edge_x, z = d / sigma;
    const double cdf = 0.5 * (1 + std::erf(z / std::sqrt(2.0)));
    const double pdf = std::exp(-0.5 * z * z) / std::sqrt(2 * std::numbers::pi);
    const double ramp_right = d * cdf + sigma * pdf;  // max(d, 0), blurred
    const double ramp_left = d - ramp_right;          // min(d, 0), blurred
    const float v =
        static_cast<float>(120 + step * cdf + slope_right * ramp_right + slope_left * ramp_left);
    for (int row = 0; row < image.rows; ++row) image.at<float>(row, u) = v;
  }
  return WithNoiseAs8Bit(image, noise, seed);
}

// A faint edge (6 grey levels) with one surface brightening away from it and the other flat,
// as a wall seen at a grazing angle beside a ceiling: the derivative's peak leaves the edge
// by (slope difference) s^2 / step. Measured on the rendered edge, the points' mean offset is
// what ShadingPeakShiftPx predicts from the slopes MeasureShadingAcrossStretch reads beside it.
TEST(EdgeProfileTest, AOneSidedShadingSlopeMovesThePeakAsPredicted) {
  const double edge_x = 200.3, step = 6, blur = 1.2;
  const Eigen::Vector2d along(0, 1), normal(-1, 0);  // normal: the left normal of `along`
  for (const auto& [left, right] : {std::pair{0.0, 0.15}, std::pair{-0.1, 0.05}, {0.0, 0.0}}) {
    double offset_sum = 0, predicted_sum = 0, left_sum = 0, right_sum = 0;
    int points = 0, stretches = 0;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
      const cv::Mat image = ShadedStepImage(edge_x, step, blur, left, right, 1.0, seed);
      const double measured_blur = std::hypot(blur, 0.3);
      const double filter = EdgeDerivativeSigmaPx(measured_blur);
      for (int y = 20; y + 32 < 280; y += 32) {
        const Eigen::Vector2d start(edge_x + 0.7, y);
        for (const auto& p : MeasureEdgeStretch(image, start, along, 16, 2, 2.5, 0, 2, filter)) {
          offset_sum += (p.point_px.x() - edge_x) * -normal.x();  // +x: along -normal
          ++points;
        }
        const auto shading = MeasureShadingAcrossStretch(image, start, along, 30, 10, 24);
        ASSERT_TRUE(shading.has_value());
        // Along the normal (-x) the image falls: right there is left here, slopes negated.
        predicted_sum += -ShadingPeakShiftPx(*shading, measured_blur, filter);
        left_sum += -shading->slope_right, right_sum += -shading->slope_left;
        ++stretches;
      }
    }
    const double offset = offset_sum / points, predicted = predicted_sum / stretches;
    EXPECT_NEAR(left_sum / stretches, left, 0.01);
    EXPECT_NEAR(right_sum / stretches, right, 0.01);
    const double exact = (right - left) *
                         (std::pow(std::hypot(blur, 0.3), 2) +
                          std::pow(EdgeDerivativeSigmaPx(std::hypot(blur, 0.3)), 2) + 1.0 / 6) /
                         step;
    std::cout << "slopes " << left << ", " << right << ": peak moved " << offset
              << " px, predicted from the image " << predicted << ", from the truth " << exact
              << "\n";
    EXPECT_NEAR(predicted, exact, 0.02 + 0.1 * std::abs(exact));
    EXPECT_NEAR(offset, predicted, 0.02 + 0.15 * std::abs(exact));
  }
  const cv::Mat flat = ShadedStepImage(200.3, 6, 1.2, 0, 0, 1.0, 1);
  EXPECT_FALSE(MeasureShadingAcrossStretch(flat, {390, 20}, along, 30, 10, 24).has_value())
      << "rows off the image";
}

// What MeasureEdgePoints finds, a point at a time, at the places MeasureEdgeStretch(image,
// start, along, count, spacing_px, 4, +1, 5) measures: `count` positions `spacing_px` apart,
// each across the left normal of `along`.
std::vector<EdgePointSample> PointSamplerAlong(const cv::Mat& image, const Eigen::Vector2d& start,
                                               const Eigen::Vector2d& along, int count,
                                               int spacing_px) {
  std::vector<Eigen::Vector2d> positions, normals;
  for (int i = 0; i < count; ++i) {
    positions.push_back(start + 1.0 * spacing_px * i * along);
    normals.emplace_back(-along.y(), along.x());
  }
  return MeasureEdgePoints(image, positions, normals, 4, +1, 5);
}

// Spaced closer than a profile is wide (its columns shared), and wider (columns between
// profiles skipped): each profile must read its own pixels either way.
TEST(EdgeProfileTest, StretchAndPointSamplersAgree) {
  const double angle = -0.4;
  const cv::Mat image = StepImage(180.6, angle, 30, 1.0, 1, 5);
  const Eigen::Vector2d normal(std::cos(angle), -std::sin(angle));
  const Eigen::Vector2d along(normal.y(), -normal.x());  // so that `normal` is its left normal
  const Eigen::Vector2d start = Eigen::Vector2d(181.5, 200) - 60 * along;
  for (int spacing_px : {3, 8, 12}) {
    SCOPED_TRACE("profiles " + std::to_string(spacing_px) + " px apart");
    const int count = 120 / spacing_px;
    const auto stretch = MeasureEdgeStretch(image, start, along, count, spacing_px, 4, +1, 5);
    const auto points = PointSamplerAlong(image, start, along, count, spacing_px);
    ASSERT_EQ(stretch.size(), points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      EXPECT_LT((stretch[i].point_px - points[i].point_px).norm(), 0.01);
      EXPECT_NEAR(stretch[i].step_grey, points[i].step_grey, 0.05);
    }
  }
}

// A stretch that starts outside the image and leaves it again (an edge running off the frame,
// as most of a Y's edges do): its patch is sampled with the border's pixels repeated, and the
// points it gives are still the per-point sampler's, up to a few pixels from each border.
TEST(EdgeProfileTest, AStretchAcrossTheBordersAgreesWithThePointSampler) {
  for (double angle : {-0.4, 1.2}) {  // leaving by the top and bottom, by the left and right
    SCOPED_TRACE("edge at " + std::to_string(angle) + " rad");
    const cv::Mat image = StepImage(180.6, angle, 30, 1.0, 1, 7);
    const Eigen::Vector2d normal(std::cos(angle), -std::sin(angle));
    const Eigen::Vector2d along(normal.y(), -normal.x());
    const Eigen::Vector2d start = Eigen::Vector2d(181.5, 200) - 300 * along;
    const int spacing_px = 3, count = 600 / spacing_px;
    const auto stretch = MeasureEdgeStretch(image, start, along, count, spacing_px, 4, +1, 5);
    const auto points = PointSamplerAlong(image, start, along, count, spacing_px);
    ASSERT_GT(points.size(), 100u);  // the edge crosses the 400 px image
    ASSERT_EQ(stretch.size(), points.size());
    for (size_t i = 0; i < points.size(); ++i)
      EXPECT_LT((stretch[i].point_px - points[i].point_px).norm(), 0.01);
  }
}

// A frame of 16 MB and more (a pixel's offset no longer exact in float): its pixels are read
// where they are, as in a small frame. The 400 px step image is set into a 4200 x 4400 frame
// at (3600, 4000), where offsets pass 2^24 bytes.
TEST(EdgeProfileTest, ALargeFrameIsReadWhereItsPixelsAre) {
  const double angle = -0.4;
  const cv::Mat small = StepImage(180.6, angle, 30, 1.0, 1, 9);
  cv::Mat large(4400, 4200, CV_8UC1, cv::Scalar(135));
  ASSERT_GT(static_cast<double>(large.rows) * large.step[0], 1 << 24);
  const cv::Point2i at(3600, 4000);
  small.copyTo(large(cv::Rect(at, small.size())));
  const Eigen::Vector2d normal(std::cos(angle), -std::sin(angle));
  const Eigen::Vector2d along(normal.y(), -normal.x());
  const Eigen::Vector2d start = Eigen::Vector2d(181.5, 200) - 60 * along;
  const Eigen::Vector2d shift(at.x, at.y);
  const auto in_small = MeasureEdgeStretch(small, start, along, 30, 4, 4, +1, 5);
  const auto in_large = MeasureEdgeStretch(large, start + shift, along, 30, 4, 4, +1, 5);
  ASSERT_EQ(in_small.size(), 30u);
  ASSERT_EQ(in_large.size(), in_small.size());
  for (size_t i = 0; i < in_small.size(); ++i)
    EXPECT_LT((in_large[i].point_px - shift - in_small[i].point_px).norm(), 1e-3);
}

// A point must not depend on where along the normal its profile was sampled: the locator
// samples along a first fit that is off the edge by a few hundredths of a pixel, differently
// at each end. A noiseless blurred step is measured from lines shifted across it by 0 to
// 1 px in tenths (every subpixel phase); the points' mean offset from the edge must not follow
// the shift. (A parabola through the derivative's values made it swing by 0.018-0.049 px over
// these blurs and filters; through their logarithms it swings 0.0002-0.0025 px.)
TEST(EdgeProfileTest, APointDoesNotLeanTowardsTheLineItWasSampledAlong) {
  // Askew of the pixel grid, so that the grid's own phase and the 8-bit rounding average out
  // along the edge and what is left is the sampling line's phase against the edge.
  const double edge_x = 200.3, angle = 0.2;
  const Eigen::Vector2d normal(std::cos(angle), -std::sin(angle));
  const Eigen::Vector2d along(-normal.y(), normal.x());
  for (double blur : {0.9, 1.2, 1.6}) {
    const cv::Mat image = StepImage(edge_x, angle, 60, blur, 0, 1);
    for (double sigma_px : {0.0, EdgeDerivativeSigmaPx(blur)}) {
      double lowest = 1e9, highest = -1e9;
      for (double shift = 0; shift <= 1.0001; shift += 0.1) {
        const Eigen::Vector2d start = Eigen::Vector2d(edge_x, 200) - 100 * along + shift * normal;
        const auto found = MeasureEdgeStretch(image, start, along, 100, 2, 2.5, 0, 3, sigma_px);
        ASSERT_EQ(found.size(), 100u);
        double mean_offset = 0;
        for (const auto& f : found)
          mean_offset += normal.dot(f.point_px - Eigen::Vector2d(edge_x, 200)) / found.size();
        lowest = std::min(lowest, mean_offset);
        highest = std::max(highest, mean_offset);
      }
      std::cout << "blur " << blur << " px, filter sigma " << sigma_px << " px: mean offset "
                << lowest << " to " << highest << " px\n";
      EXPECT_LT(highest - lowest, 0.01) << "blur " << blur << " px, filter sigma " << sigma_px;
      EXPECT_LT(std::max(std::abs(lowest), std::abs(highest)), 0.01) << "blur " << blur;
    }
  }
}

TEST(EdgeProfileTest, MajoritySignKeepsTheAgreeingPoints) {
  std::vector<EdgePointSample> samples;
  for (double s : {5.0, 6.0, -4.0, 7.0, 5.5}) samples.push_back({Eigen::Vector2d::Zero(), s});
  const auto kept = MajoritySign(samples);
  ASSERT_EQ(kept.size(), 4u);
  for (const auto& k : kept) EXPECT_GT(k.step_grey, 0);
  EXPECT_TRUE(MajoritySign({{Eigen::Vector2d::Zero(), 5}, {Eigen::Vector2d::Zero(), 6}}).empty())
      << "two points are noise, not a stretch of edge";
}

}  // namespace
}  // namespace monocle
