// Answers <floor camera namespace>/measure_points (monocle_msgs/srv/MeasurePoints): pixels of
// a floor camera -> robot-frame points with 1-sigma, from the camera's current calibration.
#pragma once

#include <memory>
#include <vector>

#include "client/protocol/convert.h"
#include "service/server/calibration_store.h"
#include "service/server/request_server.h"

namespace monocle {

class PointQueryHandler {
 public:
  static Result<std::unique_ptr<PointQueryHandler>> Start(
      const std::shared_ptr<dds::Entity>& participant, const std::vector<CameraSetup>& cameras,
      const CalibrationStore& calibrations);

 private:
  static constexpr size_t kQuickPoints = 1000;
  struct Query {
    Result<std::vector<PixelQuery>> pixels = std::vector<PixelQuery>{};
    double pixel_sigma_px = 0;
  };
  using Server = RequestServer<monocle_msgs_srv_dds__MeasurePoints_Request_,
                               monocle_msgs_srv_dds__MeasurePoints_Response_, Query>;

  explicit PointQueryHandler(const CalibrationStore& calibrations) : calibrations_(calibrations) {}
  void Answer(Server::Incoming&& in);

  const CalibrationStore& calibrations_;
  std::unique_ptr<Server> server_;  // last: its thread stops first
};

}  // namespace monocle
