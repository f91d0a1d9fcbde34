// The monocle service: its cameras (one CameraWorker each) and everything it says and answers
// over DDS: poses, calibrations, status, and the point, pose and floor calibration requests.
// See README "The service over DDS" for the topics.
#pragma once

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <thread>
#include <vector>

#include "idl/monocle.h"
#include "service/server/camera_worker.h"
#include "service/server/dds.h"
#include "service/server/reply_publisher.h"
#include "service/server/ros_topics.h"
#include "service/server/service_config.h"

namespace monocle {

class Service {
 public:
  // Loads every camera's calibration, opens DDS, starts the cameras and request handlers.
  // Errors name the camera and the file.
  static Result<std::unique_ptr<Service>> Start(const ServiceSetup& setup);
  ~Service();
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  // Publishes every camera's status; call once per status period.
  void PublishStatus();
  // Stops the handlers and the cameras, then publishes their stopped status.
  void Stop();

 private:
  struct PendingPose {
    std::string client_id, camera_id;
    uint64_t request_id = 0;
    std::chrono::steady_clock::time_point deadline;
  };

  Service() = default;
  void OnProcessed(const std::string& camera_id, const ProcessedFrame& frame);
  WorkerStatus PublishStatusOf(CameraWorker& worker, bool new_period);  // and returns it
  void PublishCalibration(const std::string& camera_id, const CameraCalibration& calibration);
  void ServePointRequests();
  void ServePoseRequests();
  void ServeFloorCalibrationRequests();
  void ReplyPose(const std::string& client_id, uint64_t request_id, uint8_t status,
                 const std::string& error, const std::string& camera_id,
                 const ProcessedFrame* frame);
  CameraWorker* Find(const std::string& camera_id);

  ServiceSetup setup_;
  std::shared_ptr<dds::Entity> participant_;
  std::unique_ptr<dds::Endpoint<monocle_dds_CornerPose>> poses_;
  std::unique_ptr<dds::Endpoint<monocle_dds_Calibration>> calibrations_;
  std::unique_ptr<dds::Endpoint<monocle_dds_CameraStatus>> status_;
  std::unique_ptr<dds::Endpoint<monocle_dds_PointRequest>> point_requests_;
  std::unique_ptr<dds::ReplyPublisher<monocle_dds_PointReply>> point_replies_;
  std::unique_ptr<dds::Endpoint<monocle_dds_PoseRequest>> pose_requests_;
  std::unique_ptr<dds::ReplyPublisher<monocle_dds_PoseReply>> pose_replies_;
  std::unique_ptr<dds::Endpoint<monocle_dds_FloorCalibrationRequest>> floor_requests_;
  std::unique_ptr<dds::ReplyPublisher<monocle_dds_FloorCalibrationReply>> floor_replies_;

  // The same measurements in ROS 2's terms (ros_topics.h).
  std::unique_ptr<RosTopics> ros_;
  std::mutex ros_intrinsics_mutex_;
  std::map<std::string, CameraIntrinsics> ros_intrinsics_;  // for camera_info, by camera

  std::vector<std::unique_ptr<CameraWorker>> workers_;

  // Floor calibrations for point queries; replaced by floor calibration commands.
  std::shared_mutex floor_mutex_;
  std::map<std::string, CameraCalibration> floor_calibrations_;
  std::mutex calibration_mutex_;  // serialises calibration changes and their revisions
  std::map<std::string, uint64_t> revisions_;

  std::mutex pose_mutex_;
  std::map<std::string, ProcessedFrame> latest_pose_;
  std::vector<PendingPose> pending_next_;

  std::mutex status_mutex_;
  std::atomic<bool> stop_{false};
  std::thread point_thread_, pose_thread_, floor_thread_;
};

}  // namespace monocle
