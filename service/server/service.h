// The monocle service: its cameras (one CameraWorker each) and everything it says and answers
// over DDS, in ROS 2's conventions (idl/protocol/wire.h): poses, status, calibrations and
// the camera's image on topics (ros_topics.h), and per camera the services measure_points,
// get_pose and calibrate_floor, each served by its own handler.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "idl/protocol/dds.h"
#include "service/server/calibration_store.h"
#include "service/server/camera_worker.h"
#include "service/server/duplicate_watch.h"
#include "service/server/floor_calibration_handler.h"
#include "service/server/point_query_handler.h"
#include "service/server/pose_query_handler.h"
#include "service/server/ros_discovery_info.h"
#include "service/server/ros_topics.h"
#include "service/server/service_config.h"

namespace monocle {

class Service {
 public:
  // Loads every camera's calibration, opens DDS, starts the cameras and request handlers.
  // Errors name the camera and the file. `stop_requested` is asked between the steps of
  // start-up (and between cameras); when it says yes, Start undoes what it did and fails
  // with kCancelled, so a stop signal is obeyed during start-up too. `before_cameras` runs
  // once DDS and the topics are up and before any camera delivers a frame (monocled
  // --record starts its recorder there, so the recording holds every frame processed); an
  // error from it ends start-up with that error.
  static Result<std::unique_ptr<Service>> Start(
      const ServiceSetup& setup, const std::function<bool()>& stop_requested = [] { return false; },
      const std::function<Status(Service&)>& before_cameras = {});
  ~Service();
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  // Publishes every camera's status; call once per status period. Also reports (once) any
  // other monocled on the domain serving one of our camera namespaces.
  void PublishStatus();
  // Stops the cameras and the handlers, then publishes the cameras' stopped status.
  void Stop();
  // This monocled on the domain: host/pid.
  const std::string& id() const { return service_id_; }
  // The cameras it serves: the configuration's, less those refused at start (another
  // monocled on the domain already serves their namespace).
  const std::vector<CameraSetup>& served_cameras() const { return setup_.cameras; }
  // The service's DDS participant, for in-process subscribers (monocled --record).
  const std::shared_ptr<dds::Entity>& participant() const { return participant_; }

 private:
  Service() = default;
  void OnProcessed(const CameraSetup& camera, const ProcessedFrame& frame);
  WorkerStatus PublishStatusOf(CameraWorker& worker, bool new_period);  // and returns it
  void PublishCalibration(const CameraSetup& camera, const CameraCalibration& calibration,
                          uint64_t revision);
  CameraWorker* Find(const std::string& camera_id);

  ServiceSetup setup_;  // the cameras served; handlers and topics keep pointers to them
  struct Refused {
    CameraSetup camera;
    WorkerStatus status;  // failed, and why
  };
  std::vector<Refused> refused_;  // configured, but another service serves their namespace
  std::mutex notes_mutex_;
  // Per namespace: another service seen on it, and when (Unix ns).
  std::map<std::string, std::pair<std::string, int64_t>> notes_;
  std::string service_id_;
  std::shared_ptr<dds::Entity> participant_;
  CalibrationStore calibrations_;
  std::unique_ptr<RosTopics> topics_;
  std::unique_ptr<RosDiscoveryInfo> ros_discovery_;  // monocled in `ros2 node list`
  std::unique_ptr<DuplicateWatch> duplicates_;
  std::mutex intrinsics_mutex_;
  std::map<std::string, CameraIntrinsics> intrinsics_;  // for camera_info, by camera
  std::vector<std::unique_ptr<CameraWorker>> workers_;
  std::unique_ptr<PointQueryHandler> point_queries_;
  std::unique_ptr<PoseQueryHandler> pose_queries_;
  std::unique_ptr<FloorCalibrationHandler> floor_calibration_;
  std::atomic<bool> stop_{false};
};

}  // namespace monocle
