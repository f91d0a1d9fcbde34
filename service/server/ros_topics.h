// Every topic monocled publishes, in ROS 2's own terms on plain Cyclone DDS with
// rmw_cyclonedds_cpp's wire conventions (idl/protocol/wire.h). Per camera, under its
// namespace (default /monocle/<camera>):
//   <ns>/corner_pose  monocle_msgs/CornerPose, every processed frame (with or without a pose)
//   <ns>/pose         geometry_msgs/PoseWithCovarianceStamped, every valid, unsuspected pose
//   <ns>/map_pose     geometry_msgs/PoseWithCovarianceStamped, with a room map: the robot base
//                     in the map, every located, unsuspected pose
//   <ns>/camera_info  sensor_msgs/CameraInfo (plumb_bob), every status period
//   <ns>/image_raw    sensor_msgs/Image mono8, only while subscribed, at most image_max_rate_hz
// and for all cameras /tf (tf2_msgs/TFMessage, parent frame -> <camera>_optical, or with a
// configured mount parent frame -> the robot's base frame, with a room map map -> base, and
// /tf_static base -> optical),
// /diagnostics (diagnostic_msgs/DiagnosticArray, every status period), /monocle/cameras
// (monocle_msgs/CameraStatus) and /monocle/calibrations (monocle_msgs/Calibration), the last
// two with one transient-local writer per camera.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "idl/monocle_msgs.h"
#include "idl/protocol/dds.h"
#include "idl/ros2_messages.h"
#include "service/server/camera_worker.h"
#include "service/server/service_config.h"

namespace monocle {

// The map frame's name on /tf and map_pose (REP 105's "map").
inline constexpr const char* kMapFrame = "map";

class RosTopics {
 public:
  // `status_only`: cameras configured but not served (refused): only their status is
  // published, on /monocle/cameras.
  static Result<std::unique_ptr<RosTopics>> Open(const std::shared_ptr<dds::Entity>& participant,
                                                 const std::vector<CameraSetup>& cameras,
                                                 const std::vector<CameraSetup>& status_only = {});

  // The pose of a processed frame on corner_pose; and, if valid and not suspect, on pose
  // and tf.
  void PublishPose(const CameraSetup& camera, const ProcessedFrame& frame);
  void PublishStatus(const CameraSetup& camera, const CameraStatus& status);
  void PublishCalibration(const CameraSetup& camera, const Calibration& calibration);
  // The frame itself, if someone subscribes and the camera's rate limit allows.
  void PublishImage(const CameraSetup& camera, const Frame& frame);
  void PublishCameraInfo(const CameraSetup& camera, const CameraIntrinsics& k, int64_t stamp_ns);
  void PublishDiagnostics(const std::vector<std::pair<const CameraSetup*, WorkerStatus>>& cameras,
                          int64_t stamp_ns);

  // The topic names a camera's ROS 2 endpoints use on the wire, for logs and the README.
  static std::string WireTopic(const CameraSetup& camera, const std::string& leaf);

 private:
  struct PerCamera {
    std::unique_ptr<dds::Endpoint<monocle_msgs_msg_dds__CornerPose_>> corner_pose;
    std::unique_ptr<dds::Endpoint<monocle_msgs_msg_dds__CameraStatus_>> status;
    std::unique_ptr<dds::Endpoint<monocle_msgs_msg_dds__Calibration_>> calibration;
    std::unique_ptr<dds::Endpoint<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>> pose;
    // With a room map: the robot base in the map.
    std::unique_ptr<dds::Endpoint<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>> map_pose;
    std::unique_ptr<dds::Endpoint<sensor_msgs_msg_dds__CameraInfo_>> camera_info;
    std::unique_ptr<dds::Endpoint<sensor_msgs_msg_dds__Image_>> image;
    std::chrono::steady_clock::time_point last_image{};
  };
  RosTopics() = default;
  void PublishTransform(const std_msgs_msg_dds__Header_& header, const std::string& child,
                        const RigidTransform& parent_child);
  void PublishMapPose(const CameraSetup& camera, const ProcessedFrame& frame, PerCamera& topics);

  std::map<std::string, PerCamera> cameras_;  // by camera id
  std::unique_ptr<dds::Endpoint<tf2_msgs_msg_dds__TFMessage_>> tf_;
  std::unique_ptr<dds::Endpoint<tf2_msgs_msg_dds__TFMessage_>> tf_static_;  // camera mounts
  std::unique_ptr<dds::Endpoint<diagnostic_msgs_msg_dds__DiagnosticArray_>> diagnostics_;
  std::mutex image_mutex_;   // last_image of every camera
  std::mutex status_mutex_;  // status and calibration writes come from several threads
};

}  // namespace monocle
