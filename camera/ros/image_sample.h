// A received or recorded sensor_msgs/Image sample (Cyclone's C type) as what monocle reads of
// it: its pixels' description and its stamp.
#pragma once

#include <cstdint>
#include <string>

#include "camera/ros/ros_image.h"
#include "idl/ros2_messages.h"

namespace monocle {

inline std::string StringOf(const char* s) { return s == nullptr ? std::string() : s; }

// builtin_interfaces/Time in nanoseconds.
inline int64_t StampNs(const builtin_interfaces_msg_dds__Time_& t) {
  return static_cast<int64_t>(t.sec) * 1000000000 + static_cast<int64_t>(t.nanosec);
}

// A view of the sample's pixels; valid while the sample is.
inline RosImageView ViewOf(const sensor_msgs_msg_dds__Image_& image) {
  return RosImageView{StringOf(image.encoding), image.width,        image.height,      image.step,
                      image.is_bigendian != 0,  image.data._buffer, image.data._length};
}

}  // namespace monocle
