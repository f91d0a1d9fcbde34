#include "camera/ros/ros_topic_source.h"

#include <gtest/gtest.h>

namespace monocle {
namespace {

TEST(RosTopicDeviceTest, TakesAbsoluteRosTopicNamesOnly) {
  EXPECT_TRUE(IsRosTopicDevice("ros:/camera/image_raw"));
  EXPECT_FALSE(IsRosTopicDevice("sim-corner"));
  EXPECT_EQ(RosTopicOfDevice("ros:/camera/image_raw").value(), "/camera/image_raw");
  EXPECT_EQ(RosTopicOfDevice("ros:/robot_1/front_cam/image_raw").value(),
            "/robot_1/front_cam/image_raw");
  for (const char* bad :
       {"ros:", "ros:/", "ros:camera/image_raw", "ros:/camera/", "ros://image",
        "ros:/1camera/image_raw", "ros:/camera/image raw", "ros:/camera/~image", "192.168.1.2"}) {
    auto topic = RosTopicOfDevice(bad);
    ASSERT_FALSE(topic) << bad;
    EXPECT_EQ(topic.error().code, ErrorCode::kInvalidArgument);
  }
}

TEST(RosTopicDeviceTest, CameraInfoIsTheImageTopicsSibling) {
  EXPECT_EQ(SiblingCameraInfoTopic("/camera/image_raw"), "/camera/camera_info");
  EXPECT_EQ(SiblingCameraInfoTopic("/robot/front/image_rect"), "/robot/front/camera_info");
  EXPECT_EQ(SiblingCameraInfoTopic("/image_raw"), "/camera_info");
}

}  // namespace
}  // namespace monocle
