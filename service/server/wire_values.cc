#include "service/server/wire_values.h"

namespace monocle {
namespace {

// The map_* fields of a pose (and its suspicion, when the mount disagrees with it).
void SetMapFields(const MapLocation& where, Pose* p) {
  p->map_candidates = static_cast<uint32_t>(where.consistent.size());
  if (where.suspect) {
    // The image and the mount disagree: the pose is suspect whichever frame it is given in.
    p->suspect = true;
    p->suspect_reason += (p->suspect_reason.empty() ? "" : "; ") + where.suspect_reason;
  }
  if (where.consistent.empty()) {
    p->map_status = MapStatus::kNoCornerFits;
    p->map_reason = where.why_none;
    return;
  }
  if (!where.decided()) {
    p->map_status = where.prior_contradicted ? MapStatus::kContradictsPrior : MapStatus::kAmbiguous;
    p->map_reason = std::to_string(where.consistent.size()) + " map corners fit (" +
                    where.consistent.front().corner_id;
    for (size_t i = 1; i < where.consistent.size(); ++i)
      p->map_reason += ", " + where.consistent[i].corner_id;
    p->map_reason += where.prior_contradicted ? "), none near the last pose" : ")";
    p->map_reason += ": give the robot's initial_pose in the configuration";
    return;
  }
  const MapPoseCandidate& c = where.consistent.front();
  p->map_status = MapStatus::kLocated;
  p->map_corner = c.corner_id;
  p->map_room = c.room_id;
  p->map_x_m = c.base.x_m;
  p->map_y_m = c.base.y_m;
  p->map_heading_rad = c.base.heading_rad;
  for (int i = 0; i < 9; ++i)
    p->map_covariance[static_cast<size_t>(i)] = c.base_covariance(i / 3, i % 3);
  p->map_camera_position_m = {c.map_camera.translation.x(), c.map_camera.translation.y(),
                              c.map_camera.translation.z()};
  const Eigen::Quaterniond& q = c.map_camera.rotation;
  p->map_camera_quaternion_wxyz = {q.w(), q.x(), q.y(), q.z()};
}

}  // namespace

Pose PoseOf(const CameraSetup& camera, const ProcessedFrame& frame) {
  Pose p;
  p.camera_id = camera.id;
  p.frame_id = camera.ros_parent_frame;
  p.frame_sequence = frame.sequence;
  p.capture_time_ns = frame.capture_time_ns;
  p.camera_clock = frame.camera_clock;
  p.processing_ns = frame.processing_ns;
  if (!frame.corner) {
    p.valid = false;
    p.error = frame.corner.error().message;
    return p;
  }
  const CornerLocation& c = *frame.corner;
  p.valid = true;
  p.x_m = c.pose.x_m;
  p.y_m = c.pose.y_m;
  p.z_m = c.pose.z_m;
  p.pan_rad = c.pose.pan_rad;
  p.tilt_rad = c.pose.tilt_rad;
  p.swing_rad = c.pose.swing_rad;
  p.quaternion_wxyz = {c.q_corner_camera.w(), c.q_corner_camera.x(), c.q_corner_camera.y(),
                       c.q_corner_camera.z()};
  for (int i = 0; i < 25; ++i) p.covariance[static_cast<size_t>(i)] = c.covariance(i / 5, i % 5);
  p.corner_px = {c.corner_px.x(), c.corner_px.y()};
  p.rms_px = c.rms_px;
  p.tracked = c.source == CornerSource::kTracked;
  p.suspect = c.suspect;
  p.suspect_reason = c.suspect_reason;
  if (c.level_error_rad) {
    p.level_error_rad = *c.level_error_rad;
    p.level_sigma_rad = c.level_sigma_rad;
  }
  if (c.base) {
    p.base_known = true;
    const RigidTransform& b = c.base->corner_base;
    p.base_position_m = {b.translation.x(), b.translation.y(), b.translation.z()};
    p.base_quaternion_wxyz = {b.rotation.w(), b.rotation.x(), b.rotation.y(), b.rotation.z()};
    p.base_heading_rad = c.base->heading_rad;
    for (int i = 0; i < 9; ++i)
      p.base_covariance[static_cast<size_t>(i)] = c.base->covariance(i / 3, i % 3);
  }
  if (frame.map) SetMapFields(*frame.map, &p);
  return p;
}

CameraState ToWire(SourceState state) {
  switch (state) {
    case SourceState::kStreaming:
      return CameraState::kStreaming;
    case SourceState::kReconnecting:
      return CameraState::kReconnecting;
    case SourceState::kStopped:
      return CameraState::kStopped;
    case SourceState::kFailed:
      return CameraState::kFailed;
  }
  return CameraState::kFailed;
}

CameraStatus CameraStatusOf(const CameraSetup& camera, const WorkerStatus& st,
                            const std::string& service_id, int64_t stamp_ns) {
  CameraStatus c;
  c.camera_id = camera.id;
  c.device = camera.options.device;
  c.role = ToString(camera.role);
  c.ros_namespace = camera.ros_namespace;
  c.service = service_id;
  c.state = ToWire(st.state);
  c.fps = st.fps;
  c.frames = st.frames;
  c.dropped = st.dropped;
  c.skipped = st.skipped;
  c.latency_ms = st.latency_ms;
  c.last_error = st.last_error;
  c.last_error_ns = st.last_error_ns;
  c.stamp_ns = stamp_ns;
  return c;
}

FloorPoseEstimate FloorPoseOf(const FloorCalibration& f) {
  const auto sigma = f.Sigma();
  return {f.pose.height_m,
          f.pose.pitch_rad,
          f.pose.yaw_rad,
          f.pose.roll_rad,
          {sigma[0], sigma[1], sigma[2], sigma[3]},
          f.rms_px};
}

Calibration CalibrationOf(const CameraSetup& camera, const CameraCalibration& cal,
                          uint64_t revision, int64_t updated_ns) {
  Calibration out;
  out.camera_id = camera.id;
  out.ros_namespace = camera.ros_namespace;
  out.revision = revision;
  out.updated_ns = updated_ns;
  const auto& k = cal.intrinsics;
  out.width_px = k.width_px;
  out.height_px = k.height_px;
  out.fx = k.fx;
  out.fy = k.fy;
  out.cx = k.cx;
  out.cy = k.cy;
  for (size_t i = 0; i < 8; ++i) out.distortion[i] = k.distortion[i];
  if (cal.floor) out.floor = FloorPoseOf(*cal.floor);
  out.ceiling_distance_m =
      camera.ceiling_distance_m ? camera.ceiling_distance_m : cal.ceiling_distance_m;
  out.file = camera.calibration_path;
  out.text = FormatCalibration(cal);
  return out;
}

}  // namespace monocle
