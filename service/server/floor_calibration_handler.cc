#include "service/server/floor_calibration_handler.h"

#include <iostream>

#include "service/server/wire_values.h"

namespace monocle {

Result<std::unique_ptr<FloorCalibrationHandler>> FloorCalibrationHandler::Start(
    const std::shared_ptr<dds::Entity>& participant, const std::vector<CameraSetup>& cameras,
    CalibrationStore& calibrations, FindWorker find_worker, OnCalibrated on_calibrated) {
  std::unique_ptr<FloorCalibrationHandler> h(new FloorCalibrationHandler(calibrations));
  h->find_worker_ = std::move(find_worker);
  h->on_calibrated_ = std::move(on_calibrated);
  auto server =
      Server::Start(participant, CamerasWith(cameras, &CameraSetup::floor),
                    &monocle_msgs_srv_dds__CalibrateFloor_Request__desc,
                    &monocle_msgs_srv_dds__CalibrateFloor_Response__desc, wire::kCalibrateFloor,
                    &FloorCalibrationHandler::Parse,
                    [self = h.get()](Server::Incoming&& in) { self->Answer(std::move(in)); });
  if (!server) return server.error();
  h->server_ = std::move(server).value();
  return h;
}

FloorCalibrationHandler::Board FloorCalibrationHandler::Parse(
    const monocle_msgs_srv_dds__CalibrateFloor_Request_& r) {
  return Board{r.board_cols, r.board_rows, r.square_m};
}

Result<BoardSpec> FloorCalibrationHandler::CheckBoard(const Board& board) {
  return ParseBoardSize(std::to_string(board.cols) + "x" + std::to_string(board.rows),
                        board.square_m);
}

Result<FloorCalibrationFromImage> FloorCalibrationHandler::CalibrateFrame(
    const Frame& frame, const CameraCalibration& cal, const BoardSpec& board) {
  auto result = CalibrateFloorFromImage(frame.grey, cal.intrinsics, board,
                                        FloorCalibrationMethod::kFull, cal.intrinsics_covariance);
  if (!result) {
    return MakeError(result.error().code,
                     "frame " + std::to_string(frame.sequence) + ": " + result.error().message);
  }
  return result;
}

Result<FloorCalibrationResult> FloorCalibrationHandler::Calibrate(
    const CameraSetup& camera, const Board& board, monocle_msgs_msg_dds__RequestStatus* status) {
  *status = monocle_msgs_msg_dds__REQUEST_INVALID;
  const auto spec = CheckBoard(board);
  if (!spec) return spec.error();
  *status = monocle_msgs_msg_dds__REQUEST_FAILED;
  CameraWorker* worker = find_worker_(camera.id);
  if (worker == nullptr)
    return MakeError(ErrorCode::kNotFound, "camera '" + camera.id + "' is gone");
  auto frame = worker->NextFrame(kFrameWait);
  if (!frame) return frame.error();
  CameraCalibration cal = worker->calibration();
  const auto result = CalibrateFrame(*frame, cal, *spec);
  if (!result) return result.error();
  cal.floor = result->calibration;
  auto revision = calibrations_.Replace(camera.id, camera.calibration_path, cal);
  if (!revision) return revision.error();
  worker->SetCalibration(cal);
  on_calibrated_(camera, cal, *revision);
  *status = monocle_msgs_msg_dds__REQUEST_OK;
  FloorCalibrationResult out;
  out.floor = FloorPoseOf(result->calibration);
  out.corners = static_cast<uint32_t>(result->corners);
  out.frame_sequence = frame->sequence;
  out.file = camera.calibration_path;
  out.revision = *revision;
  return out;
}

void FloorCalibrationHandler::Answer(Server::Incoming&& in) {
  monocle_msgs_msg_dds__RequestStatus status{};
  const auto result = Calibrate(*in.camera, in.value, &status);
  monocle_msgs_srv_dds__CalibrateFloor_Response_ reply{};
  reply.status = status;
  static const char kEmpty[] = "";
  reply.error = const_cast<char*>(result ? kEmpty : result.error().message.c_str());
  reply.file = const_cast<char*>(kEmpty);
  if (result) wire::ToSample(*result, &reply);
  if (auto s = in.server->SendReply(reply, in.header); !s)
    std::cerr << "monocled: " << s.error() << "\n";
}

}  // namespace monocle
