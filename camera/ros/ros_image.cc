#include "camera/ros/ros_image.h"

#include <opencv2/imgproc.hpp>

namespace monocle {
namespace {

// How a row is stored: 8-bit channels only, so any step in bytes makes a valid cv::Mat.
enum class Packing { kGrey, kHighByteOf16, kColour, kMosaic };

struct EncodingLayout {
  const char* name;
  int cv_type;  // 8-bit channels per pixel as stored
  Packing packing;
  int to_grey;  // cv::cvtColor code for kColour and kMosaic
};

// ROS names a Bayer mosaic by its first row and column; OpenCV by the second row's second
// and third pixel: ROS rggb is OpenCV's BG (cv_bridge's table says the same).
constexpr EncodingLayout kLayouts[] = {
    {"mono8", CV_8UC1, Packing::kGrey, 0},
    {"8UC1", CV_8UC1, Packing::kGrey, 0},
    {"mono16", CV_8UC2, Packing::kHighByteOf16, 0},
    {"16UC1", CV_8UC2, Packing::kHighByteOf16, 0},
    {"rgb8", CV_8UC3, Packing::kColour, cv::COLOR_RGB2GRAY},
    {"bgr8", CV_8UC3, Packing::kColour, cv::COLOR_BGR2GRAY},
    {"rgba8", CV_8UC4, Packing::kColour, cv::COLOR_RGBA2GRAY},
    {"bgra8", CV_8UC4, Packing::kColour, cv::COLOR_BGRA2GRAY},
    {"bayer_rggb8", CV_8UC1, Packing::kMosaic, cv::COLOR_BayerBG2GRAY},
    {"bayer_bggr8", CV_8UC1, Packing::kMosaic, cv::COLOR_BayerRG2GRAY},
    {"bayer_gbrg8", CV_8UC1, Packing::kMosaic, cv::COLOR_BayerGR2GRAY},
    {"bayer_grbg8", CV_8UC1, Packing::kMosaic, cv::COLOR_BayerGB2GRAY},
    {"yuv422", CV_8UC2, Packing::kMosaic, cv::COLOR_YUV2GRAY_UYVY},
    {"uyvy", CV_8UC2, Packing::kMosaic, cv::COLOR_YUV2GRAY_UYVY},
    {"yuv422_yuy2", CV_8UC2, Packing::kMosaic, cv::COLOR_YUV2GRAY_YUY2},
    {"yuyv", CV_8UC2, Packing::kMosaic, cv::COLOR_YUV2GRAY_YUY2},
};

constexpr uint32_t kMaxSidePx = 65535;

Error Invalid(const std::string& why) { return MakeError(ErrorCode::kInvalidArgument, why); }

// mono16's high byte, in the message's byte order.
cv::Mat GreyOfMono16(const cv::Mat& pixels, bool big_endian) {
  cv::Mat grey(pixels.rows, pixels.cols, CV_8UC1);
  const int high = big_endian ? 0 : 1;
  for (int r = 0; r < pixels.rows; ++r) {
    const uint8_t* in = pixels.ptr<uint8_t>(r);
    uint8_t* out = grey.ptr<uint8_t>(r);
    for (int c = 0; c < pixels.cols; ++c) out[c] = in[2 * c + high];
  }
  return grey;
}

}  // namespace

const std::vector<std::string>& RosGreyEncodings() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& l : kLayouts) out.emplace_back(l.name);
    return out;
  }();
  return names;
}

Result<cv::Mat> GreyOfRosImage(const RosImageView& image) {
  const EncodingLayout* layout = nullptr;
  for (const auto& l : kLayouts) {
    if (image.encoding == l.name) layout = &l;
  }
  if (layout == nullptr) {
    std::string known;
    for (const auto& name : RosGreyEncodings()) known += (known.empty() ? "" : ", ") + name;
    return Invalid("image encoding '" + image.encoding + "' is not one monocle converts (" + known +
                   ")");
  }
  const std::string size = std::to_string(image.width) + "x" + std::to_string(image.height) + " " +
                           image.encoding + ", step " + std::to_string(image.step);
  if (image.width == 0 || image.height == 0 || image.width > kMaxSidePx ||
      image.height > kMaxSidePx) {
    return Invalid("image size " + size + " is outside 1..65535 pixels a side");
  }
  const uint64_t row_bytes = uint64_t{image.width} * CV_MAT_CN(layout->cv_type);
  if (image.step < row_bytes) {
    return Invalid("image " + size + ": a row needs " + std::to_string(row_bytes) + " bytes");
  }
  if (uint64_t{image.step} * image.height > image.size || image.data == nullptr) {
    return Invalid("image " + size + " needs " +
                   std::to_string(uint64_t{image.step} * image.height) + " bytes but has " +
                   std::to_string(image.size));
  }
  if (layout->packing == Packing::kMosaic && (image.width % 2 != 0 || image.height % 2 != 0)) {
    return Invalid("image " + size + ": a mosaic or 4:2:2 image needs even sides");
  }
  // OpenCV reads the message's buffer in place; every branch below returns a copy.
  const cv::Mat pixels(static_cast<int>(image.height), static_cast<int>(image.width),
                       layout->cv_type, const_cast<uint8_t*>(image.data), image.step);
  if (layout->packing == Packing::kHighByteOf16) return GreyOfMono16(pixels, image.big_endian);
  if (layout->packing == Packing::kGrey) return pixels.clone();
  cv::Mat grey;
  cv::cvtColor(pixels, grey, layout->to_grey);
  return grey;
}

}  // namespace monocle
