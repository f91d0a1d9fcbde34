#include "camera/ros/ros_image.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace monocle {
namespace {

RosImageView View(const std::string& encoding, uint32_t width, uint32_t height, uint32_t step,
                  const std::vector<uint8_t>& bytes, bool big_endian = false) {
  return RosImageView{encoding, width, height, step, big_endian, bytes.data(), bytes.size()};
}

// ITU-R BT.601 luma, written out here rather than asked of OpenCV.
double Luma(double r, double g, double b) { return 0.299 * r + 0.587 * g + 0.114 * b; }

TEST(RosImageTest, Mono8WithPaddedRowsKeepsOnlyThePixels) {
  std::vector<uint8_t> bytes(3 * 8, 0xEE);  // 5 pixels and 3 bytes of padding per row
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 5; ++c) bytes[r * 8 + c] = static_cast<uint8_t>(10 * r + c);
  auto grey = GreyOfRosImage(View("mono8", 5, 3, 8, bytes));
  ASSERT_TRUE(grey) << grey.error();
  ASSERT_EQ(grey->cols, 5);
  ASSERT_EQ(grey->rows, 3);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 5; ++c) EXPECT_EQ(grey->at<uint8_t>(r, c), 10 * r + c);
  bytes.assign(bytes.size(), 0);  // the result owns its pixels
  EXPECT_EQ(grey->at<uint8_t>(2, 4), 24);
}

TEST(RosImageTest, Mono16TakesTheHighByteInEitherByteOrder) {
  const std::vector<uint8_t> little = {0x12, 0xAB, 0xFF, 0x01};
  const std::vector<uint8_t> big = {0xAB, 0x12, 0x01, 0xFF};
  auto from_little = GreyOfRosImage(View("mono16", 2, 1, 4, little));
  auto from_big = GreyOfRosImage(View("mono16", 2, 1, 4, big, true));
  ASSERT_TRUE(from_little && from_big);
  EXPECT_EQ(from_little->at<uint8_t>(0, 0), 0xAB);
  EXPECT_EQ(from_little->at<uint8_t>(0, 1), 0x01);
  EXPECT_EQ(from_big->at<uint8_t>(0, 0), 0xAB);
  EXPECT_EQ(from_big->at<uint8_t>(0, 1), 0x01);
}

TEST(RosImageTest, ColourEncodingsGiveLumaInTheirChannelOrder) {
  const uint8_t r = 200, g = 90, b = 30;
  const double expected = Luma(r, g, b);
  struct Case {
    std::string encoding;
    std::vector<uint8_t> pixel;
  };
  for (const Case& c : {Case{"rgb8", {r, g, b}}, Case{"bgr8", {b, g, r}},
                        Case{"rgba8", {r, g, b, 255}}, Case{"bgra8", {b, g, r, 255}}}) {
    std::vector<uint8_t> bytes;
    for (int i = 0; i < 4 * 2; ++i) bytes.insert(bytes.end(), c.pixel.begin(), c.pixel.end());
    const uint32_t step = static_cast<uint32_t>(4 * c.pixel.size());
    auto grey = GreyOfRosImage(View(c.encoding, 4, 2, step, bytes));
    ASSERT_TRUE(grey) << c.encoding << ": " << grey.error();
    EXPECT_NEAR(grey->at<uint8_t>(1, 3), expected, 1.0) << c.encoding;
  }
}

// A mosaic of a flat colour, laid out as ROS names it (first row, then second): demosaiced,
// its interior has the colour's luma. A wrong pattern mapping swaps red and blue or takes
// green for either, which moves the luma by tens of levels.
TEST(RosImageTest, BayerMosaicsAreReadInTheirNamedPattern) {
  const double rgb[3] = {220, 120, 20};
  const double expected = Luma(rgb[0], rgb[1], rgb[2]);
  for (const std::string pattern : {"rggb", "bggr", "gbrg", "grbg"}) {
    const int w = 16, h = 12;
    std::vector<uint8_t> bytes(w * h);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const char channel = pattern[2 * (y % 2) + (x % 2)];
        bytes[y * w + x] = static_cast<uint8_t>(rgb[channel == 'r' ? 0 : channel == 'g' ? 1 : 2]);
      }
    }
    auto grey = GreyOfRosImage(View("bayer_" + pattern + "8", w, h, w, bytes));
    ASSERT_TRUE(grey) << pattern << ": " << grey.error();
    for (int y = 2; y < h - 2; ++y)
      for (int x = 2; x < w - 2; ++x)
        ASSERT_NEAR(grey->at<uint8_t>(y, x), expected, 3.0) << pattern << " at " << x << "," << y;
  }
}

TEST(RosImageTest, Yuv422EncodingsGiveTheirLumaSamples) {
  // Two pixels: Y0 = 40, Y1 = 210, with U = 90, V = 160 shared.
  const std::vector<uint8_t> uyvy = {90, 40, 160, 210};
  const std::vector<uint8_t> yuyv = {40, 90, 210, 160};
  for (const auto& [encoding, bytes] :
       {std::pair{std::string("yuv422"), uyvy}, std::pair{std::string("yuv422_yuy2"), yuyv}}) {
    std::vector<uint8_t> two_rows = bytes;
    two_rows.insert(two_rows.end(), bytes.begin(), bytes.end());
    auto grey = GreyOfRosImage(View(encoding, 2, 2, 4, two_rows));
    ASSERT_TRUE(grey) << encoding << ": " << grey.error();
    EXPECT_EQ(grey->at<uint8_t>(1, 0), 40) << encoding;
    EXPECT_EQ(grey->at<uint8_t>(1, 1), 210) << encoding;
  }
}

TEST(RosImageTest, RefusesWhatDoesNotAddUpAndSaysWhy) {
  const std::vector<uint8_t> bytes(100, 0);
  auto unknown = GreyOfRosImage(View("jpeg", 10, 10, 10, bytes));
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().message.find("'jpeg'"), std::string::npos);
  EXPECT_NE(unknown.error().message.find("bayer_rggb8"), std::string::npos);

  auto short_data = GreyOfRosImage(View("mono8", 10, 11, 10, bytes));
  ASSERT_FALSE(short_data);
  EXPECT_NE(short_data.error().message.find("needs 110 bytes but has 100"), std::string::npos);

  auto short_step = GreyOfRosImage(View("rgb8", 10, 3, 20, bytes));
  ASSERT_FALSE(short_step);
  EXPECT_NE(short_step.error().message.find("a row needs 30 bytes"), std::string::npos);

  EXPECT_FALSE(GreyOfRosImage(View("mono8", 0, 10, 10, bytes)));
  EXPECT_FALSE(GreyOfRosImage(View("bayer_rggb8", 9, 10, 9, bytes)));
  EXPECT_FALSE(GreyOfRosImage(View("mono8", 70000, 1, 70000, bytes)));
  EXPECT_TRUE(GreyOfRosImage(View("mono8", 10, 10, 10, bytes)));
}

}  // namespace
}  // namespace monocle
