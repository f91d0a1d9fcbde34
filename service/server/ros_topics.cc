#include "service/server/ros_topics.h"

#include <cstring>
#include <iostream>

#include "idl/protocol/convert.h"
#include "idl/protocol/wire.h"
#include "service/geometry/pose_covariance.h"
#include "service/geometry/robot_frames.h"
#include "service/server/wire_values.h"

namespace monocle {
namespace {

using wire::RosTime;

char* Chars(const std::string& s) { return const_cast<char*>(s.c_str()); }
// A sample borrows the characters until it is written: never those of a temporary (a
// `const char*` turned into a std::string for the call once left the map pose's frame_id
// pointing at freed stack, found by AddressSanitizer).
char* Chars(std::string&&) = delete;
char* Chars(const char* s) { return const_cast<char*>(s); }

template <typename T>
Result<std::unique_ptr<dds::Endpoint<T>>> OpenWriter(const std::shared_ptr<dds::Entity>& p,
                                                     const dds_topic_descriptor_t* type,
                                                     const std::string& topic,
                                                     dds::EndpointQos qos = wire::kRosDefaultQos) {
  auto ep = dds::Endpoint<T>::Open(p, type, topic.c_str(), true, false, qos);
  if (!ep) return ep.error();
  return std::make_unique<dds::Endpoint<T>>(std::move(ep).value());
}

void Report(const Status& s) {
  if (!s) std::cerr << "monocled: ROS 2 topic: " << s.error() << "\n";
}

}  // namespace

std::string RosTopics::WireTopic(const CameraSetup& camera, const std::string& leaf) {
  return wire::RosTopic(camera.ros_namespace, leaf);
}

Result<std::unique_ptr<RosTopics>> RosTopics::Open(const std::shared_ptr<dds::Entity>& p,
                                                   const std::vector<CameraSetup>& cameras,
                                                   const std::vector<CameraSetup>& status_only) {
  std::unique_ptr<RosTopics> r(new RosTopics());
  for (const auto& cam : status_only) {
    auto status = OpenWriter<monocle_msgs_msg_dds__CameraStatus_>(
        p, &monocle_msgs_msg_dds__CameraStatus__desc, wire::kCamerasTopic,
        wire::kDirectoryWriterQos);
    if (!status) return status.error();
    r->cameras_[cam.id].status = std::move(status).value();
  }
  for (const auto& cam : cameras) {
    PerCamera& c = r->cameras_[cam.id];
    auto status = OpenWriter<monocle_msgs_msg_dds__CameraStatus_>(
        p, &monocle_msgs_msg_dds__CameraStatus__desc, wire::kCamerasTopic,
        wire::kDirectoryWriterQos);
    if (!status) return status.error();
    c.status = std::move(status).value();
    auto calibration = OpenWriter<monocle_msgs_msg_dds__Calibration_>(
        p, &monocle_msgs_msg_dds__Calibration__desc, wire::kCalibrationsTopic,
        wire::kDirectoryWriterQos);
    if (!calibration) return calibration.error();
    c.calibration = std::move(calibration).value();
    if (cam.corner()) {
      auto corner_pose = OpenWriter<monocle_msgs_msg_dds__CornerPose_>(
          p, &monocle_msgs_msg_dds__CornerPose__desc, wire::CornerPoseTopic(cam.ros_namespace));
      if (!corner_pose) return corner_pose.error();
      c.corner_pose = std::move(corner_pose).value();
      auto pose = OpenWriter<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>(
          p, &geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc, WireTopic(cam, "pose"));
      if (!pose) return pose.error();
      c.pose = std::move(pose).value();
      if (cam.room_map) {
        auto map_pose = OpenWriter<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>(
            p, &geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc, WireTopic(cam, "map_pose"));
        if (!map_pose) return map_pose.error();
        c.map_pose = std::move(map_pose).value();
      }
    }
    auto info = OpenWriter<sensor_msgs_msg_dds__CameraInfo_>(
        p, &sensor_msgs_msg_dds__CameraInfo__desc, WireTopic(cam, "camera_info"));
    if (!info) return info.error();
    c.camera_info = std::move(info).value();
    auto image = OpenWriter<sensor_msgs_msg_dds__Image_>(p, &sensor_msgs_msg_dds__Image__desc,
                                                         WireTopic(cam, "image_raw"));
    if (!image) return image.error();
    c.image = std::move(image).value();
  }
  auto tf =
      OpenWriter<tf2_msgs_msg_dds__TFMessage_>(p, &tf2_msgs_msg_dds__TFMessage__desc, "rt/tf");
  if (!tf) return tf.error();
  r->tf_ = std::move(tf).value();
  // /tf_static: each mounted camera on its robot, once, kept for late readers (ROS's static
  // tf QoS: reliable, transient-local, keep-last 1).
  std::vector<geometry_msgs_msg_dds__TransformStamped_> mounts;
  for (const auto& cam : cameras) {
    if (!cam.mount) continue;
    geometry_msgs_msg_dds__TransformStamped_ t{};
    t.header.frame_id = Chars(cam.mount->base_frame);
    t.child_frame_id = Chars(cam.ros_frame);
    const RigidTransform mount = MountTransform(*cam.mount);  // the rotation normalized
    t.transform.translation = {mount.translation.x(), mount.translation.y(), mount.translation.z()};
    t.transform.rotation = {mount.rotation.x(), mount.rotation.y(), mount.rotation.z(),
                            mount.rotation.w()};
    mounts.push_back(t);
  }
  if (!mounts.empty()) {
    auto tf_static = OpenWriter<tf2_msgs_msg_dds__TFMessage_>(
        p, &tf2_msgs_msg_dds__TFMessage__desc, "rt/tf_static", dds::EndpointQos{1, true});
    if (!tf_static) return tf_static.error();
    r->tf_static_ = std::move(tf_static).value();
    tf2_msgs_msg_dds__TFMessage_ message{};
    message.transforms._buffer = mounts.data();
    message.transforms._length = message.transforms._maximum = static_cast<uint32_t>(mounts.size());
    message.transforms._release = false;
    Report(r->tf_static_->Write(message));
  }
  auto diagnostics = OpenWriter<diagnostic_msgs_msg_dds__DiagnosticArray_>(
      p, &diagnostic_msgs_msg_dds__DiagnosticArray__desc, "rt/diagnostics");
  if (!diagnostics) return diagnostics.error();
  r->diagnostics_ = std::move(diagnostics).value();
  return r;
}

void RosTopics::PublishStatus(const CameraSetup& camera, const CameraStatus& status) {
  const auto it = cameras_.find(camera.id);
  if (it == cameras_.end()) return;
  monocle_msgs_msg_dds__CameraStatus_ sample;
  wire::ToSample(status, camera.ros_frame, &sample);
  std::lock_guard<std::mutex> lock(status_mutex_);
  Report(it->second.status->Write(sample));
}

void RosTopics::PublishCalibration(const CameraSetup& camera, const Calibration& calibration) {
  const auto it = cameras_.find(camera.id);
  if (it == cameras_.end()) return;
  monocle_msgs_msg_dds__Calibration_ sample;
  wire::ToSample(calibration, &sample);
  std::lock_guard<std::mutex> lock(status_mutex_);
  Report(it->second.calibration->Write(sample));
}

void RosTopics::PublishPose(const CameraSetup& camera, const ProcessedFrame& frame) {
  const auto it = cameras_.find(camera.id);
  if (it == cameras_.end() || !it->second.corner_pose) return;
  {
    const Pose value = PoseOf(camera, frame);
    monocle_msgs_msg_dds__CornerPose_ sample;
    wire::ToSample(value, &sample);
    Report(it->second.corner_pose->Write(sample));
  }
  // A suspect pose is published on corner_pose with its reason; a ROS consumer fusing
  // poses from pose or tf cannot see that flag, so it is not given one.
  if (!frame.corner || frame.corner->suspect) return;
  const CornerLocation& c = *frame.corner;
  const Eigen::Vector3d position = CameraPosition(c.pose);
  const Eigen::Matrix<double, 6, 6> covariance = RosPoseCovariance(c.pose, c.covariance);

  geometry_msgs_msg_dds__PoseWithCovarianceStamped_ pose{};
  pose.header.stamp = RosTime(frame.capture_time_ns);
  pose.header.frame_id = Chars(camera.ros_parent_frame);
  pose.pose.pose.position = {position.x(), position.y(), position.z()};
  pose.pose.pose.orientation = {c.q_corner_camera.x(), c.q_corner_camera.y(), c.q_corner_camera.z(),
                                c.q_corner_camera.w()};
  for (int i = 0; i < 36; ++i) pose.pose.covariance[i] = covariance(i / 6, i % 6);
  Report(it->second.pose->Write(pose));

  // tf: the camera, or (with a mount) the robot's base, in the parent frame; with a room map
  // the base in the map instead (one parent per frame in tf: the corner frame jumps from
  // corner to corner, the map does not).
  if (camera.room_map) {
    PublishMapPose(camera, frame, it->second);
    return;
  }
  RigidTransform shown{c.q_corner_camera, position};
  if (camera.mount) shown = BaseInParent(shown, MountTransform(*camera.mount));
  PublishTransform(pose.header, camera.mount ? camera.mount->base_frame : camera.ros_frame, shown);
}

void RosTopics::PublishTransform(const std_msgs_msg_dds__Header_& header, const std::string& child,
                                 const RigidTransform& parent_child) {
  geometry_msgs_msg_dds__TransformStamped_ transform{};
  transform.header = header;
  transform.child_frame_id = Chars(child);
  transform.transform.translation = {parent_child.translation.x(), parent_child.translation.y(),
                                     parent_child.translation.z()};
  transform.transform.rotation = {parent_child.rotation.x(), parent_child.rotation.y(),
                                  parent_child.rotation.z(), parent_child.rotation.w()};
  tf2_msgs_msg_dds__TFMessage_ tf{};
  tf.transforms._buffer = &transform;
  tf.transforms._length = tf.transforms._maximum = 1;
  tf.transforms._release = false;
  Report(tf_->Write(tf));
}

void RosTopics::PublishMapPose(const CameraSetup& camera, const ProcessedFrame& frame,
                               PerCamera& topics) {
  // Only a located pose that nothing makes suspect: a ROS consumer cannot see the flags.
  if (!frame.map || !frame.map->decided() || frame.map->suspect || !topics.map_pose ||
      !camera.mount)
    return;
  const MapPoseCandidate& c = frame.map->consistent.front();
  const RigidTransform map_base{
      Eigen::Quaterniond(Eigen::AngleAxisd(c.base.heading_rad, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(c.base.x_m, c.base.y_m, 0)};
  geometry_msgs_msg_dds__PoseWithCovarianceStamped_ pose{};
  pose.header.stamp = RosTime(frame.capture_time_ns);
  pose.header.frame_id = Chars(kMapFrame);
  pose.pose.pose.position = {map_base.translation.x(), map_base.translation.y(), 0};
  pose.pose.pose.orientation = {map_base.rotation.x(), map_base.rotation.y(), map_base.rotation.z(),
                                map_base.rotation.w()};
  // ROS order x, y, z, roll, pitch, yaw. The base stands on the floor: z, roll and pitch are
  // known to the level the map assumes (MapCheckOptions::level_sigma_rad).
  const double level_sigma = MapCheckOptions{}.level_sigma_rad;
  const int from[3] = {0, 1, 5};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      pose.pose.covariance[from[a] * 6 + from[b]] = c.base_covariance(a, b);
  pose.pose.covariance[2 * 6 + 2] = 1e-6;
  pose.pose.covariance[3 * 6 + 3] = pose.pose.covariance[4 * 6 + 4] = level_sigma * level_sigma;
  Report(topics.map_pose->Write(pose));
  PublishTransform(pose.header, camera.mount->base_frame, map_base);
}

void RosTopics::PublishImage(const CameraSetup& camera, const Frame& frame) {
  const auto it = cameras_.find(camera.id);
  if (it == cameras_.end() || frame.grey.empty() || frame.grey.type() != CV_8UC1) return;
  PerCamera& c = it->second;
  // Nobody looking costs one matched-status read per frame: no copy, no write.
  if (!c.image->HasReaders()) return;
  {
    const auto now = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> lock(image_mutex_);
    if (now - c.last_image < std::chrono::duration<double>(1.0 / camera.image_max_rate_hz)) return;
    c.last_image = now;
  }
  // The sample points into the frame's own rows when they are contiguous (no copy here;
  // Cyclone serialises it during the write).
  cv::Mat pixels = frame.grey.isContinuous() ? frame.grey : frame.grey.clone();
  sensor_msgs_msg_dds__Image_ image{};
  image.header.stamp = RosTime(frame.capture_time_ns);
  // An image topic's frames keep the driver's frame id: they are the same optical frame.
  image.header.frame_id = Chars(frame.frame_id.empty() ? camera.ros_frame : frame.frame_id);
  image.height = static_cast<uint32_t>(pixels.rows);
  image.width = static_cast<uint32_t>(pixels.cols);
  static const char kMono8[] = "mono8";
  image.encoding = const_cast<char*>(kMono8);
  image.is_bigendian = 0;
  image.step = static_cast<uint32_t>(pixels.cols);
  image.data._buffer = pixels.data;
  image.data._length = image.data._maximum = static_cast<uint32_t>(pixels.total());
  image.data._release = false;
  Report(c.image->Write(image));
}

void RosTopics::PublishCameraInfo(const CameraSetup& camera, const CameraIntrinsics& k,
                                  int64_t stamp_ns) {
  const auto it = cameras_.find(camera.id);
  if (it == cameras_.end()) return;
  sensor_msgs_msg_dds__CameraInfo_ info{};
  info.header.stamp = RosTime(stamp_ns);
  info.header.frame_id = Chars(camera.ros_frame);
  info.height = static_cast<uint32_t>(k.height_px);
  info.width = static_cast<uint32_t>(k.width_px);
  static const char kPlumbBob[] = "plumb_bob";
  info.distortion_model = const_cast<char*>(kPlumbBob);
  // plumb_bob is OpenCV's k1 k2 p1 p2 k3.
  double d[5];
  for (int i = 0; i < 5; ++i) d[i] = k.distortion[i];
  info.d._buffer = d;
  info.d._length = info.d._maximum = 5;
  info.d._release = false;
  const double kk[9] = {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
  std::memcpy(info.k, kk, sizeof kk);
  const double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::memcpy(info.r, r, sizeof r);
  const double p[12] = {k.fx, 0, k.cx, 0, 0, k.fy, k.cy, 0, 0, 0, 1, 0};
  std::memcpy(info.p, p, sizeof p);
  Report(it->second.camera_info->Write(info));
}

void RosTopics::PublishDiagnostics(
    const std::vector<std::pair<const CameraSetup*, WorkerStatus>>& cameras, int64_t stamp_ns) {
  constexpr int kValues = 7;
  std::vector<diagnostic_msgs_msg_dds__DiagnosticStatus_> status(cameras.size());
  std::vector<std::array<diagnostic_msgs_msg_dds__KeyValue_, kValues>> values(cameras.size());
  std::vector<std::array<std::string, kValues + 2>> text(cameras.size());
  for (size_t i = 0; i < cameras.size(); ++i) {
    const auto& [setup, st] = cameras[i];
    auto& s = status[i];
    auto& t = text[i];
    // OK while streaming; ERROR while the camera is lost or failed (no measurements); STALE
    // once stopped.
    s.level = st.state == SourceState::kStreaming ? 0 : st.state == SourceState::kStopped ? 3 : 2;
    t[0] = "monocle: " + setup->id;
    t[1] = ToString(st.state);
    if (st.state != SourceState::kStreaming && st.state != SourceState::kStopped &&
        !st.last_error.empty())
      t[1] += ": " + st.last_error;
    s.name = Chars(t[0]);
    s.message = Chars(t[1]);
    s.hardware_id = Chars(setup->options.device);
    const std::pair<const char*, std::string> kv[kValues] = {
        {"role", ToString(setup->role)},
        {"fps", std::to_string(st.fps)},
        {"frames", std::to_string(st.frames)},
        {"dropped", std::to_string(st.dropped)},
        {"skipped", std::to_string(st.skipped)},
        {"latency_ms", std::to_string(st.latency_ms)},
        {"last_error", st.last_error}};
    for (int v = 0; v < kValues; ++v) {
      t[2 + v] = kv[v].second;
      values[i][v].key = const_cast<char*>(kv[v].first);
      values[i][v].value = Chars(t[2 + v]);
    }
    s.values._buffer = values[i].data();
    s.values._length = s.values._maximum = kValues;
    s.values._release = false;
  }
  diagnostic_msgs_msg_dds__DiagnosticArray_ array{};
  array.header.stamp = RosTime(stamp_ns);
  static const char kEmpty[] = "";
  array.header.frame_id = const_cast<char*>(kEmpty);
  array.status._buffer = status.data();
  array.status._length = array.status._maximum = static_cast<uint32_t>(status.size());
  array.status._release = false;
  Report(diagnostics_->Write(array));
}

}  // namespace monocle
