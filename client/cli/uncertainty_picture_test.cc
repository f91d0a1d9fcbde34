#include "client/cli/uncertainty_picture.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "service/vision/chessboard.h"

namespace monocle::cli {
namespace {

const std::filesystem::path kData = "/usr/share/doc/opencv-doc/examples/data";

int Distance(const cv::Vec3b& a, const cv::Vec3b& b) {
  return std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]);
}

// OpenCV's left photos: no board came near the image's left corners. The picture must show
// them as the weakest places (the top of the scale), the middle where the boards were as sure.
TEST(UncertaintyPictureTest, OpenCvsLeftPhotosShowTheCornersNoBoardReached) {
  if (!std::filesystem::exists(kData / "left01.jpg")) {
    GTEST_SKIP() << "OpenCV's sample photos are not installed (" << kData
                 << "/left01.jpg): install the Debian package opencv-doc (scripts/setup does)";
  }
  std::vector<IntrinsicView> views;
  cv::Size size;
  for (int i = 1; i <= 14; ++i) {
    std::ostringstream name;
    name << "left" << std::setw(2) << std::setfill('0') << i << ".jpg";
    const cv::Mat grey = cv::imread((kData / name.str()).string(), cv::IMREAD_GRAYSCALE);
    if (grey.empty()) continue;  // left10.jpg is not shipped
    size = grey.size();
    if (auto board = DetectChessboard(grey, {9, 6, 0.025})) views.push_back({name.str(), *board});
  }
  const auto cal = CalibrateIntrinsics(views, size);
  ASSERT_TRUE(cal.ok()) << cal.error();
  ASSERT_FALSE(cal->uncovered_corners.empty());
  const auto map = MapProjectionUncertainty(cal->intrinsics, cal->covariance, 8);
  const cv::Mat picture = ProjectionUncertaintyPicture(map, size, views);
  ASSERT_EQ(picture.size(), size);
  const UncertaintyScale scale = UncertaintyScaleOf(map);
  const cv::Vec3b weakest = UncertaintyColour(scale.top_px, scale);
  const cv::Vec3b middle_colour = UncertaintyColour(map.relative.median_px, scale);
  // The middle of the left edge's corners, clear of the labels: top-left below the two text
  // lines, bottom-left above the footer.
  for (const cv::Point at : {cv::Point(4, 60), cv::Point(4, size.height - 30)}) {
    const double sigma = map.RelativeAt(at.x / 8, at.y / 8);
    EXPECT_GT(sigma, 5 * map.relative.median_px) << at;
    EXPECT_LT(Distance(picture.at<cv::Vec3b>(at), weakest),
              Distance(picture.at<cv::Vec3b>(at), middle_colour))
        << at;
  }
  // Where the boards were (the centre), the colour of the median, far from the weakest.
  const cv::Point centre(size.width / 2 + 5, size.height / 2 + 5);
  EXPECT_LT(Distance(picture.at<cv::Vec3b>(centre), middle_colour), 60);
  EXPECT_GT(Distance(weakest, middle_colour), 150);
}

}  // namespace
}  // namespace monocle::cli
