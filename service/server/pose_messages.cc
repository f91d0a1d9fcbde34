#include "service/server/pose_messages.h"

#include <cstring>

namespace monocle::dds {

void ToSample(const std::string& camera_id, uint64_t sequence, int64_t capture_time_ns,
              bool camera_clock, const Result<CornerLocation>& pose, int64_t processing_ns,
              monocle_dds_CornerPose* out, std::string* error) {
  std::memset(out, 0, sizeof(*out));
  out->camera_id = const_cast<char*>(camera_id.c_str());
  out->frame_sequence = sequence;
  out->capture_time_ns = capture_time_ns;
  out->time_source = camera_clock ? 1 : 0;
  out->processing_ns = processing_ns;
  static const char kEmpty[] = "";
  out->suspect_reason = const_cast<char*>(kEmpty);
  if (!pose) {
    out->status = 1;
    *error = pose.error().message;
    out->error = const_cast<char*>(error->c_str());
    return;
  }
  error->clear();
  out->error = const_cast<char*>(error->c_str());
  const auto& p = pose->pose;
  out->x = p.x_m;
  out->y = p.y_m;
  out->z = p.z_m;
  out->pan = p.pan_rad;
  out->tilt = p.tilt_rad;
  out->swing = p.swing_rad;
  const auto& q = pose->q_corner_camera;
  out->quaternion[0] = q.w();
  out->quaternion[1] = q.x();
  out->quaternion[2] = q.y();
  out->quaternion[3] = q.z();
  for (int i = 0; i < 25; ++i) out->covariance[i] = pose->covariance(i / 5, i % 5);
  out->corner_px[0] = pose->corner_px.x();
  out->corner_px[1] = pose->corner_px.y();
  out->rms_px = pose->rms_px;
  out->tracked = pose->source == CornerSource::kTracked;
  out->suspect = pose->suspect;
  out->suspect_reason = const_cast<char*>(pose->suspect_reason.c_str());
}

}  // namespace monocle::dds
