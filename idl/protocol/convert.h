// Conversions between monocle's values (monocle/types.h) and their DDS samples
// (idl/ros/monocle_msgs.idl), written once for the service and the client library.
// A sample made by ToSample points into the value it came from (strings, columns): keep that
// alive until the sample is written. FromSample copies everything out of the sample.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "idl/monocle_msgs.h"
#include "idl/protocol/values.h"
#include "service/common/result.h"

namespace monocle::wire {

using WireRequestStatus = monocle_msgs_msg_dds__RequestStatus;

// An enum field of a received sample as the integer it carries: a newer (or hostile) peer
// may send a value the enum type does not have, and loading that as the enum type is
// undefined behaviour (UBSan: "not a valid value for type"). Compare the integer instead.
template <typename WireEnum>
uint32_t EnumValue(const WireEnum& field) {
  static_assert(sizeof(WireEnum) == sizeof(uint32_t), "IDL enums are 32 bits on the wire");
  uint32_t value = 0;
  std::memcpy(&value, &field, sizeof value);
  return value;
}

builtin_interfaces_msg_dds__Time_ RosTime(int64_t unix_ns);
int64_t UnixNs(const builtin_interfaces_msg_dds__Time_& t);

void ToSample(const Pose& pose, monocle_msgs_msg_dds__CornerPose_* out);
Pose FromSample(const monocle_msgs_msg_dds__CornerPose_& s);

// `frame_id`: the camera's optical frame, for ROS tools that show it.
void ToSample(const CameraStatus& status, const std::string& frame_id,
              monocle_msgs_msg_dds__CameraStatus_* out);
CameraStatus FromSample(const monocle_msgs_msg_dds__CameraStatus_& s);

void ToSample(const Calibration& calibration, monocle_msgs_msg_dds__Calibration_* out);
Calibration FromSample(const monocle_msgs_msg_dds__Calibration_& s);

// Point queries travel as columns; these hold them while a sample points into them.
struct PointRequestColumns {
  std::vector<double> u, v, foot_u, foot_v;
};
struct PointReplyColumns {
  std::vector<monocle_msgs_msg_dds__PointStatus> status;
  std::vector<double> x, y, z, sigma_x, sigma_y, sigma_z;
  std::vector<double> covariance_xy, covariance_xz, covariance_yz;
  std::vector<monocle_msgs_msg_dds__PointError_> errors;
};

void ToSample(const std::vector<PixelQuery>& pixels, double pixel_sigma_px,
              PointRequestColumns* columns, monocle_msgs_srv_dds__MeasurePoints_Request_* out);
// The pixels of a request; an error (which column is wrong) if its columns disagree.
Result<std::vector<PixelQuery>> FromSample(const monocle_msgs_srv_dds__MeasurePoints_Request_& s);

void ToSample(WireRequestStatus status, const std::string& error,
              const std::vector<MeasuredPoint>& points, PointReplyColumns* columns,
              monocle_msgs_srv_dds__MeasurePoints_Response_* out);
// The points of an answered reply; an error if its columns disagree.
Result<std::vector<MeasuredPoint>> FromSample(
    const monocle_msgs_srv_dds__MeasurePoints_Response_& s);

// The board and what is asked beyond it; its options back from a request (the board's fields
// are read as they are, and checked by the service).
void ToSample(int board_cols, int board_rows, double square_m,
              const FloorCalibrationOptions& options,
              monocle_msgs_srv_dds__CalibrateFloor_Request_* out);
FloorCalibrationOptions OptionsFromSample(const monocle_msgs_srv_dds__CalibrateFloor_Request_& s);

// A floor calibration reply's sequences, held while a sample points into them.
struct FloorReplyStorage {
  std::vector<monocle_msgs_msg_dds__FloorAccuracy_> accuracy;
  std::vector<char*> advice;
};
void ToSample(const FloorCalibrationResult& result, FloorReplyStorage* storage,
              monocle_msgs_srv_dds__CalibrateFloor_Response_* out);
FloorCalibrationResult FromSample(const monocle_msgs_srv_dds__CalibrateFloor_Response_& s);

// A status name for messages ("invalid request").
const char* ToString(WireRequestStatus status);

}  // namespace monocle::wire
