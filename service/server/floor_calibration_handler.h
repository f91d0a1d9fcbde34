// Answers <floor camera namespace>/calibrate_floor (monocle_msgs/srv/CalibrateFloor): takes
// the camera's next frame, finds the chessboard lying on the floor, calibrates (Xu et al.
// 2017, full model) and reports how good the result is (floor_guidance.h, with the picture
// when asked); then saves the calibration file atomically, hands it to the camera and
// announces it (on_calibrated publishes it on /monocle/calibrations). A result that carries
// no information, or whose height is no robot's (a unit slip, unless forced), is not stored.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "idl/protocol/convert.h"
#include "service/server/calibration_store.h"
#include "service/server/camera_worker.h"
#include "service/server/request_server.h"
#include "service/vision/floor_calibrator.h"

namespace monocle {

class FloorCalibrationHandler {
 public:
  static constexpr std::chrono::milliseconds kFrameWait{5000};
  using FindWorker = std::function<CameraWorker*(const std::string& camera_id)>;
  using OnCalibrated =
      std::function<void(const CameraSetup&, const CameraCalibration&, uint64_t revision)>;

  static Result<std::unique_ptr<FloorCalibrationHandler>> Start(
      const std::shared_ptr<dds::Entity>& participant, const std::vector<CameraSetup>& cameras,
      CalibrationStore& calibrations, FindWorker find_worker, OnCalibrated on_calibrated);

  // What the handler does with a request, without DDS or camera (the fuzz target drives
  // these): the board it names and what is asked beyond it, whether those are valid (an
  // invalid request if not), and the calibration from one frame with it (the frame's
  // sequence named in the error).
  struct Board {
    int32_t cols = 0, rows = 0;
    double square_m = 0;
    FloorCalibrationOptions options;
  };
  static Board Parse(const monocle_msgs_srv_dds__CalibrateFloor_Request_& request);
  static Result<BoardSpec> CheckRequest(const Board& board);
  static Result<FloorCalibrationFromImage> CalibrateFrame(const Frame& frame,
                                                          const CameraCalibration& calibration,
                                                          const BoardSpec& board);

 private:
  using Server = RequestServer<monocle_msgs_srv_dds__CalibrateFloor_Request_,
                               monocle_msgs_srv_dds__CalibrateFloor_Response_, Board>;

  explicit FloorCalibrationHandler(CalibrationStore& calibrations) : calibrations_(calibrations) {}
  void Answer(Server::Incoming&& in);
  // The calibration result, or the status and message of the failure.
  Result<FloorCalibrationResult> Calibrate(const CameraSetup& camera, const Board& board,
                                           monocle_msgs_msg_dds__RequestStatus* status);
  // Stores `cal` with its new floor section and announces it: the file and revision.
  Status Store(const CameraSetup& camera, CameraWorker& worker, const CameraCalibration& cal,
               FloorCalibrationResult* out);

  CalibrationStore& calibrations_;
  FindWorker find_worker_;
  OnCalibrated on_calibrated_;
  std::unique_ptr<Server> server_;  // last: its thread stops first
};

}  // namespace monocle
