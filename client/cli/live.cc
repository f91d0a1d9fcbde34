#include "client/cli/live.h"

#include <cmath>
#include <cstdlib>
#include <numbers>

#include "client/cli/commands.h"
#include "client/cli/corner_output.h"

namespace monocle::cli {

int Fail(const ClientError& error) { return Fail(error.message, kExitFailure); }

Result<CameraStatus> FindServiceCamera(Client& client, const std::string& name, int domain,
                                       const std::string& role) {
  auto cameras = client.status();
  if (!cameras) return MakeError(ErrorCode::kIo, cameras.error().message);
  std::string known, of_role;
  std::optional<CameraStatus> found;
  for (const CameraStatus& c : *cameras) {
    known += (known.empty() ? "" : ", ") + c.camera_id + " (" + c.role + ")";
    const bool fits = role.empty() || c.role.find(role) != std::string::npos;
    if (fits) of_role += (of_role.empty() ? "" : ", ") + c.camera_id;
    if (c.camera_id == name || c.ros_namespace == name) found = c;
  }
  if (!found) {
    return MakeError(ErrorCode::kNotFound,
                     "no camera '" + name + "' on DDS domain " + std::to_string(domain) +
                         (known.empty() ? " (no service answered)" : " (cameras: " + known + ")"));
  }
  if (!role.empty() && found->role.find(role) == std::string::npos) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "camera '" + name + "' is a " + found->role + " camera, not a " + role +
                         " camera (" + role + " cameras: " + (of_role.empty() ? "none" : of_role) +
                         ")");
  }
  return *found;
}

proto::LivePoseOutput ToLiveOutput(const Pose& s) {
  proto::LivePoseOutput out;
  out.set_camera(s.camera_id);
  out.set_sequence(s.frame_sequence);
  out.set_capture_time_ns(s.capture_time_ns);
  out.set_time_source(s.camera_clock ? "camera" : "host");
  auto* p = out.mutable_pose();
  if (!s.valid) {
    p->set_error(s.error);
    return out;
  }
  p->set_x(s.x_m);
  p->set_y(s.y_m);
  p->set_z(s.z_m);
  p->set_pan(s.pan_rad);
  p->set_tilt(s.tilt_rad);
  p->set_swing(s.swing_rad);
  for (double q : s.quaternion_wxyz) p->add_quaternion(q);
  p->add_corner_px(s.corner_px[0]);
  p->add_corner_px(s.corner_px[1]);
  p->set_rms_px(s.rms_px);
  p->set_source(s.tracked ? "tracked" : "detected");
  p->set_suspect(s.suspect);
  if (s.suspect) p->set_suspect_reason(s.suspect_reason);
  auto* sigma = p->mutable_sigma();
  sigma->set_x(std::sqrt(s.covariance[0]));
  sigma->set_y(std::sqrt(s.covariance[6]));
  sigma->set_pan(std::sqrt(s.covariance[12]));
  sigma->set_tilt(std::sqrt(s.covariance[18]));
  sigma->set_swing(std::sqrt(s.covariance[24]));
  if (s.level_sigma_rad > 0) {  // monocled combined the pose with the mount's level
    p->set_level_error_deg(s.level_error_rad * 180 / std::numbers::pi);
    p->set_level_sigma_deg(s.level_sigma_rad * 180 / std::numbers::pi);
  }
  if (s.base_known) {
    *p->mutable_base() = ToBaseOutput(s.base_position_m, s.base_quaternion_wxyz, s.base_heading_rad,
                                      s.base_covariance);
  }
  if (s.map_status != MapStatus::kNone) {
    // The same "map" object as `corner locate --map` (the service sends no candidate list,
    // only how many fit).
    auto* m = p->mutable_map();
    m->set_status(ToString(s.map_status));
    if (s.map_status == MapStatus::kLocated) {
      auto* at = m->mutable_pose();
      at->set_corner(s.map_corner);
      at->set_room(s.map_room);
      at->set_x(s.map_x_m);
      at->set_y(s.map_y_m);
      at->set_heading_deg(s.map_heading_rad * 180 / std::numbers::pi);
      at->mutable_sigma()->set_x(std::sqrt(s.map_covariance[0]));
      at->mutable_sigma()->set_y(std::sqrt(s.map_covariance[4]));
      at->mutable_sigma()->set_heading_deg(std::sqrt(s.map_covariance[8]) * 180 / std::numbers::pi);
      for (double v : s.map_camera_position_m) at->add_camera_position(v);
      for (double v : s.map_camera_quaternion_wxyz) at->add_camera_quaternion(v);
    } else {
      m->set_reason(s.map_reason);
    }
  }
  return out;
}

}  // namespace monocle::cli
