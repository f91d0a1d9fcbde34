// Answers <floor camera namespace>/measure_points (monocle_msgs/srv/MeasurePoints): pixels of
// a floor camera -> robot-frame points with 1-sigma, from the camera's current calibration.
#pragma once

#include <memory>
#include <vector>

#include "idl/protocol/convert.h"
#include "service/server/calibration_store.h"
#include "service/server/request_server.h"

namespace monocle {

class PointQueryHandler {
 public:
  static Result<std::unique_ptr<PointQueryHandler>> Start(
      const std::shared_ptr<dds::Entity>& participant, const std::vector<CameraSetup>& cameras,
      const CalibrationStore& calibrations);

  // What the handler does with a request, without DDS (the fuzz target drives these with
  // samples decoded from fuzz bytes): the request's pixels (too many is refused before they
  // are copied), and the reply to them for floor camera `camera_id`.
  struct Query {
    Result<std::vector<PixelQuery>> pixels = std::vector<PixelQuery>{};
    double pixel_sigma_px = 0;
  };
  // The reply sample and what it points into (its strings and sequences), kept together.
  struct Reply {
    Reply() = default;
    Reply(const Reply&) = delete;
    Reply& operator=(const Reply&) = delete;
    std::string error;
    std::vector<MeasuredPoint> points;
    wire::PointReplyColumns columns;
    monocle_msgs_srv_dds__MeasurePoints_Response_ sample{};
  };
  static Query Parse(const monocle_msgs_srv_dds__MeasurePoints_Request_& request);
  static void AnswerInto(const Query& query, const std::string& camera_id,
                         const CalibrationStore& calibrations, Reply* reply);

 private:
  static constexpr size_t kQuickPoints = 1000;
  using Server = RequestServer<monocle_msgs_srv_dds__MeasurePoints_Request_,
                               monocle_msgs_srv_dds__MeasurePoints_Response_, Query>;

  explicit PointQueryHandler(const CalibrationStore& calibrations) : calibrations_(calibrations) {}
  void Answer(Server::Incoming&& in);

  const CalibrationStore& calibrations_;
  std::unique_ptr<Server> server_;  // last: its thread stops first
};

}  // namespace monocle
