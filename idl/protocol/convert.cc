#include "idl/protocol/convert.h"

#include <cmath>
#include <cstring>
#include <optional>

namespace monocle::wire {
namespace {

std::string Text(const char* s) { return s != nullptr ? s : ""; }
char* Chars(const std::string& s) { return const_cast<char*>(s.c_str()); }
// A sample borrows the characters until it is written: never those of a temporary.
char* Chars(std::string&&) = delete;

// A sequence that borrows `v`'s buffer (not released by DDS).
template <typename Seq, typename T>
void Borrow(std::vector<T>& v, Seq* seq) {
  seq->_buffer = v.data();
  seq->_length = seq->_maximum = static_cast<uint32_t>(v.size());
  seq->_release = false;
}

template <typename Seq>
std::vector<double> Column(const Seq& seq) {
  return std::vector<double>(seq._buffer, seq._buffer + seq._length);
}

// The core's point status and the wire's POINT_* carry the same numbers.
static_assert(static_cast<int>(PointStatus::kMeasured) == monocle_msgs_msg_dds__POINT_MEASURED);
static_assert(static_cast<int>(PointStatus::kInvalidPixel) ==
              monocle_msgs_msg_dds__POINT_INVALID_PIXEL);
static_assert(static_cast<int>(PointStatus::kNotMeasurable) ==
              monocle_msgs_msg_dds__POINT_NOT_MEASURABLE);

monocle_msgs_msg_dds__PointStatus ToWire(PointStatus status) {
  return static_cast<monocle_msgs_msg_dds__PointStatus>(status);
}

// Empty for a value this build does not know (a newer or hostile peer's).
std::optional<PointStatus> PointStatusFromWire(uint32_t value) {
  if (value > monocle_msgs_msg_dds__POINT_NOT_MEASURABLE) return std::nullopt;
  return static_cast<PointStatus>(value);
}

}  // namespace

builtin_interfaces_msg_dds__Time_ RosTime(int64_t unix_ns) {
  builtin_interfaces_msg_dds__Time_ t{};
  // Floor division: ROS time has a non-negative nanosec part.
  int64_t sec = unix_ns / 1'000'000'000, nsec = unix_ns % 1'000'000'000;
  if (nsec < 0) {
    nsec += 1'000'000'000;
    --sec;
  }
  t.sec = static_cast<int32_t>(sec);
  t.nanosec = static_cast<uint32_t>(nsec);
  return t;
}

int64_t UnixNs(const builtin_interfaces_msg_dds__Time_& t) {
  return static_cast<int64_t>(t.sec) * 1'000'000'000 + t.nanosec;
}

void ToSample(const Pose& p, monocle_msgs_msg_dds__CornerPose_* out) {
  std::memset(out, 0, sizeof(*out));
  out->header.stamp = RosTime(p.capture_time_ns);
  out->header.frame_id = Chars(p.frame_id);
  out->camera = Chars(p.camera_id);
  out->frame_sequence = p.frame_sequence;
  out->time_source = p.camera_clock ? monocle_msgs_msg_dds__TIME_CAMERA_CLOCK
                                    : monocle_msgs_msg_dds__TIME_HOST_CLOCK;
  out->status = p.valid ? monocle_msgs_msg_dds__POSE_VALID : monocle_msgs_msg_dds__POSE_NO_CORNER;
  out->error = Chars(p.error);
  out->position = {p.x_m, p.y_m, p.z_m};
  out->pan = p.pan_rad;
  out->tilt = p.tilt_rad;
  out->swing = p.swing_rad;
  const auto& q = p.quaternion_wxyz;
  out->orientation = {q[1], q[2], q[3], q[0]};  // ROS order: x, y, z, w
  std::copy(p.covariance.begin(), p.covariance.end(), out->covariance);
  out->corner_px[0] = p.corner_px[0];
  out->corner_px[1] = p.corner_px[1];
  out->rms_px = p.rms_px;
  out->processing_ns = p.processing_ns;
  out->tracked = p.tracked;
  out->suspect = p.suspect;
  out->suspect_reason = Chars(p.suspect_reason);
  out->map_status = static_cast<monocle_msgs_msg_dds__MapStatus>(p.map_status);
  out->map_corner = Chars(p.map_corner);
  out->map_room = Chars(p.map_room);
  out->map_x = p.map_x_m;
  out->map_y = p.map_y_m;
  out->map_heading = p.map_heading_rad;
  std::copy(p.map_covariance.begin(), p.map_covariance.end(), out->map_covariance);
  const auto& c = p.map_camera_position_m;
  const auto& r = p.map_camera_quaternion_wxyz;
  out->map_camera.position = {c[0], c[1], c[2]};
  out->map_camera.orientation = {r[1], r[2], r[3], r[0]};  // ROS order: x, y, z, w
  out->map_candidates = p.map_candidates;
  out->map_reason = Chars(p.map_reason);
  out->level_error = p.level_error_rad;
  out->level_sigma = p.level_sigma_rad;
  out->base_known = p.base_known;
  const auto& b = p.base_position_m;
  const auto& bq = p.base_quaternion_wxyz;
  out->base.position = {b[0], b[1], b[2]};
  out->base.orientation = {bq[1], bq[2], bq[3], bq[0]};  // ROS order: x, y, z, w
  out->base_heading = p.base_heading_rad;
  std::copy(p.base_covariance.begin(), p.base_covariance.end(), out->base_covariance);
}

Pose FromSample(const monocle_msgs_msg_dds__CornerPose_& s) {
  Pose p;
  p.camera_id = Text(s.camera);
  p.frame_id = Text(s.header.frame_id);
  p.frame_sequence = s.frame_sequence;
  p.capture_time_ns = UnixNs(s.header.stamp);
  p.camera_clock = EnumValue(s.time_source) == monocle_msgs_msg_dds__TIME_CAMERA_CLOCK;
  p.valid = EnumValue(s.status) == monocle_msgs_msg_dds__POSE_VALID;
  p.error = Text(s.error);
  p.x_m = s.position.x;
  p.y_m = s.position.y;
  p.z_m = s.position.z;
  p.pan_rad = s.pan;
  p.tilt_rad = s.tilt;
  p.swing_rad = s.swing;
  p.quaternion_wxyz = {s.orientation.w, s.orientation.x, s.orientation.y, s.orientation.z};
  std::copy(std::begin(s.covariance), std::end(s.covariance), p.covariance.begin());
  p.corner_px = {s.corner_px[0], s.corner_px[1]};
  p.rms_px = s.rms_px;
  p.processing_ns = s.processing_ns;
  p.tracked = s.tracked;
  p.suspect = s.suspect;
  p.suspect_reason = Text(s.suspect_reason);
  // An unknown status (a newer service) reads as no map rather than as a wrong one.
  const uint32_t map_status = EnumValue(s.map_status);
  p.map_status = map_status <= monocle_msgs_msg_dds__MAP_NO_CORNER_FITS
                     ? static_cast<MapStatus>(map_status)
                     : MapStatus::kNone;
  p.map_corner = Text(s.map_corner);
  p.map_room = Text(s.map_room);
  p.map_x_m = s.map_x;
  p.map_y_m = s.map_y;
  p.map_heading_rad = s.map_heading;
  std::copy(std::begin(s.map_covariance), std::end(s.map_covariance), p.map_covariance.begin());
  p.map_camera_position_m = {s.map_camera.position.x, s.map_camera.position.y,
                             s.map_camera.position.z};
  p.map_camera_quaternion_wxyz = {s.map_camera.orientation.w, s.map_camera.orientation.x,
                                  s.map_camera.orientation.y, s.map_camera.orientation.z};
  p.map_candidates = s.map_candidates;
  p.map_reason = Text(s.map_reason);
  p.level_error_rad = s.level_error;
  p.level_sigma_rad = s.level_sigma;
  p.base_known = s.base_known;
  p.base_position_m = {s.base.position.x, s.base.position.y, s.base.position.z};
  p.base_quaternion_wxyz = {s.base.orientation.w, s.base.orientation.x, s.base.orientation.y,
                            s.base.orientation.z};
  p.base_heading_rad = s.base_heading;
  std::copy(std::begin(s.base_covariance), std::end(s.base_covariance), p.base_covariance.begin());
  return p;
}

void ToSample(const CameraStatus& c, const std::string& frame_id,
              monocle_msgs_msg_dds__CameraStatus_* out) {
  std::memset(out, 0, sizeof(*out));
  out->header.stamp = RosTime(c.stamp_ns);
  out->header.frame_id = Chars(frame_id);
  out->camera = Chars(c.camera_id);
  out->ros_namespace = Chars(c.ros_namespace);
  out->service = Chars(c.service);
  out->device = Chars(c.device);
  out->role = Chars(c.role);
  out->state = static_cast<monocle_msgs_msg_dds__CameraState>(c.state);
  out->fps = c.fps;
  out->frames = c.frames;
  out->dropped = c.dropped;
  out->skipped = c.skipped;
  out->latency_ms = c.latency_ms;
  out->last_error = Chars(c.last_error);
  out->last_error_ns = c.last_error_ns;
}

CameraStatus FromSample(const monocle_msgs_msg_dds__CameraStatus_& s) {
  CameraStatus c;
  c.camera_id = Text(s.camera);
  c.ros_namespace = Text(s.ros_namespace);
  c.service = Text(s.service);
  c.device = Text(s.device);
  c.role = Text(s.role);
  switch (EnumValue(s.state)) {
    case monocle_msgs_msg_dds__CAMERA_STREAMING:
      c.state = CameraState::kStreaming;
      break;
    case monocle_msgs_msg_dds__CAMERA_RECONNECTING:
      c.state = CameraState::kReconnecting;
      break;
    case monocle_msgs_msg_dds__CAMERA_STOPPED:
      c.state = CameraState::kStopped;
      break;
    case monocle_msgs_msg_dds__CAMERA_FAILED:
      c.state = CameraState::kFailed;
      break;
  }
  c.fps = s.fps;
  c.frames = s.frames;
  c.dropped = s.dropped;
  c.skipped = s.skipped;
  c.latency_ms = s.latency_ms;
  c.last_error = Text(s.last_error);
  c.last_error_ns = s.last_error_ns;
  c.stamp_ns = UnixNs(s.header.stamp);
  return c;
}

void ToSample(const Calibration& c, monocle_msgs_msg_dds__Calibration_* out) {
  std::memset(out, 0, sizeof(*out));
  out->header.stamp = RosTime(c.updated_ns);
  static const char kNoFrame[] = "";
  out->header.frame_id = const_cast<char*>(kNoFrame);
  out->camera = Chars(c.camera_id);
  out->ros_namespace = Chars(c.ros_namespace);
  out->revision = c.revision;
  out->width_px = static_cast<uint32_t>(c.width_px);
  out->height_px = static_cast<uint32_t>(c.height_px);
  out->fx = c.fx;
  out->fy = c.fy;
  out->cx = c.cx;
  out->cy = c.cy;
  std::copy(c.distortion.begin(), c.distortion.end(), out->distortion);
  out->has_floor = c.floor.has_value();
  if (c.floor) {
    out->floor_height_m = c.floor->height_m;
    out->floor_pitch = c.floor->pitch_rad;
    out->floor_yaw = c.floor->yaw_rad;
    out->floor_roll = c.floor->roll_rad;
    std::copy(c.floor->sigma.begin(), c.floor->sigma.end(), out->floor_sigma);
    out->floor_rms_px = c.floor->rms_px;
  }
  out->has_ceiling = c.ceiling_distance_m.has_value();
  out->ceiling_distance_m = c.ceiling_distance_m.value_or(0);
  out->file = Chars(c.file);
  out->text = Chars(c.text);
}

Calibration FromSample(const monocle_msgs_msg_dds__Calibration_& s) {
  Calibration c;
  c.camera_id = Text(s.camera);
  c.ros_namespace = Text(s.ros_namespace);
  c.revision = s.revision;
  c.updated_ns = UnixNs(s.header.stamp);
  c.width_px = static_cast<int>(s.width_px);
  c.height_px = static_cast<int>(s.height_px);
  c.fx = s.fx;
  c.fy = s.fy;
  c.cx = s.cx;
  c.cy = s.cy;
  std::copy(std::begin(s.distortion), std::end(s.distortion), c.distortion.begin());
  if (s.has_floor) {
    c.floor =
        FloorPoseEstimate{s.floor_height_m,
                          s.floor_pitch,
                          s.floor_yaw,
                          s.floor_roll,
                          {s.floor_sigma[0], s.floor_sigma[1], s.floor_sigma[2], s.floor_sigma[3]},
                          s.floor_rms_px};
  }
  if (s.has_ceiling) c.ceiling_distance_m = s.ceiling_distance_m;
  c.file = Text(s.file);
  c.text = Text(s.text);
  return c;
}

void ToSample(const std::vector<PixelQuery>& pixels, double pixel_sigma_px,
              PointRequestColumns* columns, monocle_msgs_srv_dds__MeasurePoints_Request_* out) {
  std::memset(out, 0, sizeof(*out));
  out->pixel_sigma_px = pixel_sigma_px;
  auto& c = *columns;
  c = {};
  c.u.reserve(pixels.size());
  c.v.reserve(pixels.size());
  bool any_foot = false;
  for (const auto& p : pixels) {
    c.u.push_back(p.u);
    c.v.push_back(p.v);
    any_foot = any_foot || p.foot_px.has_value();
  }
  // Foot columns only when some point stands above another (floor pixels need none).
  if (any_foot) {
    for (const auto& p : pixels) {
      c.foot_u.push_back(p.foot_px ? (*p.foot_px)[0] : std::nan(""));
      c.foot_v.push_back(p.foot_px ? (*p.foot_px)[1] : std::nan(""));
    }
  }
  Borrow(c.u, &out->u);
  Borrow(c.v, &out->v);
  Borrow(c.foot_u, &out->foot_u);
  Borrow(c.foot_v, &out->foot_v);
}

Result<std::vector<PixelQuery>> FromSample(const monocle_msgs_srv_dds__MeasurePoints_Request_& s) {
  const uint32_t n = s.u._length;
  if (s.v._length != n) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "u has " + std::to_string(n) + " pixels but v has " +
                         std::to_string(s.v._length) + ": give one v per u");
  }
  if (s.foot_u._length != s.foot_v._length || (s.foot_u._length != 0 && s.foot_u._length != n)) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "foot_u and foot_v must both be empty or have one value per pixel (" +
                         std::to_string(n) + "); they have " + std::to_string(s.foot_u._length) +
                         " and " + std::to_string(s.foot_v._length));
  }
  std::vector<PixelQuery> out(n);
  for (uint32_t i = 0; i < n; ++i) {
    out[i].u = s.u._buffer[i];
    out[i].v = s.v._buffer[i];
    // A foot with either coordinate NaN means "a floor pixel"; a foot half given is not
    // silently read as one: it reaches the measurement and is rejected there as invalid.
    if (s.foot_u._length != 0 &&
        !(std::isnan(s.foot_u._buffer[i]) && std::isnan(s.foot_v._buffer[i])))
      out[i].foot_px = std::array<double, 2>{s.foot_u._buffer[i], s.foot_v._buffer[i]};
  }
  return out;
}

void ToSample(WireRequestStatus status, const std::string& error,
              const std::vector<MeasuredPoint>& points, PointReplyColumns* columns,
              monocle_msgs_srv_dds__MeasurePoints_Response_* out) {
  std::memset(out, 0, sizeof(*out));
  out->status = status;
  out->error = Chars(error);
  auto& c = *columns;
  const size_t n = points.size();
  for (auto* col : {&c.x, &c.y, &c.z, &c.sigma_x, &c.sigma_y, &c.sigma_z, &c.covariance_xy,
                    &c.covariance_xz, &c.covariance_yz})
    col->resize(n);
  c.status.resize(n);
  c.errors.clear();
  for (size_t i = 0; i < n; ++i) {
    const auto& p = points[i];
    c.status[i] = ToWire(p.status);
    c.x[i] = p.p_robot_m[0];
    c.y[i] = p.p_robot_m[1];
    c.z[i] = p.p_robot_m[2];
    c.sigma_x[i] = p.sigma_m[0];
    c.sigma_y[i] = p.sigma_m[1];
    c.sigma_z[i] = p.sigma_m[2];
    c.covariance_xy[i] = p.covariance[1];
    c.covariance_xz[i] = p.covariance[2];
    c.covariance_yz[i] = p.covariance[5];
    if (!p.ok()) c.errors.push_back({static_cast<uint32_t>(i), Chars(p.error)});
  }
  Borrow(c.status, &out->point_status);
  Borrow(c.x, &out->x);
  Borrow(c.y, &out->y);
  Borrow(c.z, &out->z);
  Borrow(c.sigma_x, &out->sigma_x);
  Borrow(c.sigma_y, &out->sigma_y);
  Borrow(c.sigma_z, &out->sigma_z);
  Borrow(c.covariance_xy, &out->covariance_xy);
  Borrow(c.covariance_xz, &out->covariance_xz);
  Borrow(c.covariance_yz, &out->covariance_yz);
  Borrow(c.errors, &out->point_errors);
}

Result<std::vector<MeasuredPoint>> FromSample(
    const monocle_msgs_srv_dds__MeasurePoints_Response_& s) {
  const uint32_t n = s.point_status._length;
  for (uint32_t len : {s.x._length, s.y._length, s.z._length, s.sigma_x._length, s.sigma_y._length,
                       s.sigma_z._length, s.covariance_xy._length, s.covariance_xz._length,
                       s.covariance_yz._length}) {
    if (len != n)
      return MakeError(ErrorCode::kIo, "a malformed reply: its columns have different lengths");
  }
  std::vector<MeasuredPoint> out(n);
  for (uint32_t i = 0; i < n; ++i) {
    auto& p = out[i];
    const uint32_t status = EnumValue(s.point_status._buffer[i]);
    const auto known = PointStatusFromWire(status);
    p.status = known.value_or(PointStatus::kNotMeasurable);
    if (!known)
      p.error = "unknown point status " + std::to_string(status) + " (from a newer service?)";
    p.p_robot_m = {s.x._buffer[i], s.y._buffer[i], s.z._buffer[i]};
    const double sx = s.sigma_x._buffer[i], sy = s.sigma_y._buffer[i], sz = s.sigma_z._buffer[i];
    const double xy = s.covariance_xy._buffer[i], xz = s.covariance_xz._buffer[i],
                 yz = s.covariance_yz._buffer[i];
    p.SetCovariance({sx * sx, xy, xz, xy, sy * sy, yz, xz, yz, sz * sz});
    p.sigma_m = {sx, sy, sz};  // as sent, not squared and rooted again
  }
  for (uint32_t i = 0; i < s.point_errors._length; ++i) {
    const auto& e = s.point_errors._buffer[i];
    if (e.index < n) out[e.index].error = Text(e.message);
  }
  return out;
}

void ToSample(int board_cols, int board_rows, double square_m,
              const FloorCalibrationOptions& options,
              monocle_msgs_srv_dds__CalibrateFloor_Request_* out) {
  out->board_cols = board_cols;
  out->board_rows = board_rows;
  out->square_m = square_m;
  out->pixel_sigma_px = options.pixel_sigma_px;
  out->target_sigma_m = options.target ? options.target->sigma_m : 0;
  out->target_distance_m = options.target ? options.target->distance_m : 0;
  out->force = options.force;
  out->overlay = options.overlay;
}

FloorCalibrationOptions OptionsFromSample(const monocle_msgs_srv_dds__CalibrateFloor_Request_& s) {
  FloorCalibrationOptions o;
  o.pixel_sigma_px = s.pixel_sigma_px;
  if (s.target_sigma_m != 0) {
    o.target =
        FloorAccuracyTarget{s.target_sigma_m, s.target_distance_m != 0 ? s.target_distance_m : 3.0};
  }
  o.force = s.force;
  o.overlay = s.overlay;
  return o;
}

void ToSample(const FloorCalibrationResult& r, FloorReplyStorage* storage,
              monocle_msgs_srv_dds__CalibrateFloor_Response_* out) {
  out->height_m = r.floor.height_m;
  out->pitch = r.floor.pitch_rad;
  out->yaw = r.floor.yaw_rad;
  out->roll = r.floor.roll_rad;
  std::copy(r.floor.sigma.begin(), r.floor.sigma.end(), out->sigma);
  out->rms_px = r.floor.rms_px;
  out->corners = r.corners;
  out->frame_sequence = r.frame_sequence;
  out->file = Chars(r.file);
  out->revision = r.revision;
  const FloorGuidance& g = r.report;
  out->board_distance_m = g.board.distance_m;
  out->board_depth_span_m = g.board.depth_span_m;
  out->board_image_fraction = g.board.image_fraction;
  out->board_sight_angle_deg = g.board.sight_angle_deg;
  storage->accuracy.clear();
  for (const FloorAccuracyAt& a : g.accuracy) {
    storage->accuracy.push_back({a.distance_m, a.in_image, a.sigma_m, a.calibration_sigma_m,
                                 a.intrinsics_sigma_m, a.pixel_sigma_m});
  }
  Borrow(storage->accuracy, &out->accuracy);
  out->ill_conditioned = g.ill_conditioned;
  out->explanation = Chars(g.ill_conditioned_reason);
  out->target_met = g.target_met;
  out->target_met_out_to_m = g.target_met_out_to_m;
  storage->advice.clear();
  for (const std::string& a : g.advice) storage->advice.push_back(Chars(a));
  Borrow(storage->advice, &out->advice);
  out->overlay_png._buffer = const_cast<uint8_t*>(r.overlay_png.data());  // only read
  out->overlay_png._length = out->overlay_png._maximum =
      static_cast<uint32_t>(r.overlay_png.size());
  out->overlay_png._release = false;
}

FloorCalibrationResult FromSample(const monocle_msgs_srv_dds__CalibrateFloor_Response_& s) {
  FloorCalibrationResult r;
  r.floor = {s.height_m, s.pitch, s.yaw, s.roll, {s.sigma[0], s.sigma[1], s.sigma[2], s.sigma[3]},
             s.rms_px};
  r.corners = s.corners;
  r.frame_sequence = s.frame_sequence;
  r.file = Text(s.file);
  r.revision = s.revision;
  FloorGuidance& g = r.report;
  g.board = {s.board_distance_m, s.board_depth_span_m, s.board_image_fraction,
             s.board_sight_angle_deg};
  for (uint32_t i = 0; i < s.accuracy._length; ++i) {
    const auto& a = s.accuracy._buffer[i];
    g.accuracy.push_back({a.distance_m, a.in_image, a.sigma_m, a.calibration_sigma_m,
                          a.intrinsics_sigma_m, a.pixel_sigma_m});
  }
  g.ill_conditioned = s.ill_conditioned;
  g.ill_conditioned_reason = Text(s.explanation);
  g.target_met = s.target_met;
  g.target_met_out_to_m = s.target_met_out_to_m;
  for (uint32_t i = 0; i < s.advice._length; ++i) g.advice.push_back(Text(s.advice._buffer[i]));
  r.overlay_png.assign(s.overlay_png._buffer, s.overlay_png._buffer + s.overlay_png._length);
  return r;
}

const char* ToString(WireRequestStatus status) {
  switch (status) {
    case monocle_msgs_msg_dds__REQUEST_OK:
      return "ok";
    case monocle_msgs_msg_dds__REQUEST_INVALID:
      return "invalid request";
    case monocle_msgs_msg_dds__REQUEST_FAILED:
      return "failed";
  }
  return "unknown status";
}

}  // namespace monocle::wire
