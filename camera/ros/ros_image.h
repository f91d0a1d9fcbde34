// sensor_msgs/Image pixels to the 8-bit grey every pipeline takes: the encodings camera
// drivers publish (sensor_msgs/image_encodings.hpp), checked against the message's own size
// fields before a pixel is read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "service/common/result.h"

namespace monocle {

// The fields of one sensor_msgs/Image that describe its pixels (a view: nothing is copied).
struct RosImageView {
  std::string encoding;
  uint32_t width = 0;   // pixels
  uint32_t height = 0;  // pixels
  uint32_t step = 0;    // bytes per row
  bool big_endian = false;
  const uint8_t* data = nullptr;
  size_t size = 0;  // bytes in `data`
};

// The encodings GreyOfRosImage converts, for help texts and errors.
const std::vector<std::string>& RosGreyEncodings();

// Grey pixels of their own: mono8 as is; mono16 by its high byte; rgb8, bgr8, rgba8, bgra8
// by luma (ITU-R BT.601); the four 8-bit Bayer mosaics demosaiced to luma; yuv422 (UYVY) and
// yuv422_yuy2 (YUYV) by their Y. An unknown encoding or sizes that do not add up are a
// kInvalidArgument error naming them.
Result<cv::Mat> GreyOfRosImage(const RosImageView& image);

}  // namespace monocle
