#include "service/server/floor_calibration_handler.h"

#include <cmath>
#include <iostream>

#include "service/geometry/floor_guidance.h"
#include "service/io/image_codec.h"
#include "service/server/wire_values.h"
#include "service/vision/floor_overlay.h"

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
  return Board{r.board_cols, r.board_rows, r.square_m, wire::OptionsFromSample(r)};
}

Result<BoardSpec> FloorCalibrationHandler::CheckRequest(const Board& board) {
  const FloorCalibrationOptions& o = board.options;
  if (!std::isfinite(o.pixel_sigma_px) || o.pixel_sigma_px < 0) {
    return MakeError(
        ErrorCode::kInvalidArgument,
        "pixel_sigma_px must be a number of pixels >= 0, not " + std::to_string(o.pixel_sigma_px));
  }
  if (o.target && (!std::isfinite(o.target->sigma_m) || o.target->sigma_m <= 0 ||
                   !std::isfinite(o.target->distance_m) || o.target->distance_m <= 0)) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "the target must be a 1 sigma in metres > 0 at a distance in metres > 0 "
                     "(target_sigma_m 0: no target; target_distance_m 0: 3 m)");
  }
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
  const auto spec = CheckRequest(board);
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
  const FloorCalibration& floor = result->calibration;
  FloorCalibrationResult out;
  out.floor = FloorPoseOf(floor);
  out.corners = static_cast<uint32_t>(result->corners);
  out.frame_sequence = frame->sequence;
  const FloorCalibrationOptions& options = board.options;
  out.report = AdviseFloorCalibration(cal.intrinsics, cal.intrinsics_covariance, floor,
                                      result->board, options.pixel_sigma_px, options.target);
  if (options.overlay) {
    auto png = EncodeImage(
        DrawFloorOverlay(frame->grey, cal.intrinsics, floor, result->board, out.report), ".png");
    if (!png) return png.error();
    out.overlay_png = std::move(png).value();
  }
  // Neither is stored: a result without information, nor (unless forced) a unit slip.
  if (out.report.ill_conditioned) {
    return MakeError(ErrorCode::kDegenerate,
                     "no usable floor calibration from frame " + std::to_string(frame->sequence) +
                         ", " + camera.calibration_path +
                         " left unchanged: " + out.report.ill_conditioned_reason);
  }
  const UnitSlipWords words{"--square (square_m)", "--force (force)"};
  if (const auto slip = FloorHeightUnitSlip(floor.pose.height_m, spec->square_m, words);
      slip && !options.force) {
    return MakeError(ErrorCode::kOutOfRange,
                     *slip + " " + camera.calibration_path + " left unchanged.");
  }
  cal.floor = floor;
  if (auto stored = Store(camera, *worker, cal, &out); !stored) return stored.error();
  *status = monocle_msgs_msg_dds__REQUEST_OK;
  return out;
}

Status FloorCalibrationHandler::Store(const CameraSetup& camera, CameraWorker& worker,
                                      const CameraCalibration& cal, FloorCalibrationResult* out) {
  auto revision = calibrations_.Replace(camera.id, camera.calibration_path, cal);
  if (!revision) return revision.error();
  worker.SetCalibration(cal);
  on_calibrated_(camera, cal, *revision);
  out->file = camera.calibration_path;
  out->revision = *revision;
  return Ok{};
}

void FloorCalibrationHandler::Answer(Server::Incoming&& in) {
  monocle_msgs_msg_dds__RequestStatus status{};
  const auto result = Calibrate(*in.camera, in.value, &status);
  monocle_msgs_srv_dds__CalibrateFloor_Response_ reply{};
  reply.status = status;
  static const char kEmpty[] = "";
  reply.error = const_cast<char*>(result ? kEmpty : result.error().message.c_str());
  reply.file = const_cast<char*>(kEmpty);
  wire::FloorReplyStorage storage;
  if (result) wire::ToSample(*result, &storage, &reply);
  if (auto s = in.server->SendReply(reply, in.header); !s)
    std::cerr << "monocled: " << s.error() << "\n";
}

}  // namespace monocle
