#include "service/server/service_config.h"

#include <cctype>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include "camera/ros/ros_topic_source.h"
#include "idl/protocol/dds.h"
#include "idl/service_config.pb.h"
#include "service/io/bounded_file.h"
#include "service/io/calibration_file.h"
#include "service/io/field_errors.h"
#include "service/io/room_map_file.h"
#include "service/io/text_proto.h"

namespace monocle {
namespace {

using google::protobuf::TextFormat;

// "cfg.pbtxt: line 7: camera[1].role must be ..." (the line of the field, or of the camera
// when the field is missing).
class ConfigErrors {
 public:
  ConfigErrors(const std::string& source, const TextFormat::ParseInfoTree& tree)
      : errors_(source, tree, proto::ServiceConfig::descriptor()) {}

  // `at_field`: the field whose line to name when it is not `field` itself.
  Error Camera(int index, const std::string& field, const std::string& why,
               const std::string& at_field = "") const {
    const std::string& line_field = at_field.empty() ? field : at_field;
    return errors_.At({{"camera", index}, {field.c_str()}}, why,
                      {{"camera", index}, {line_field.c_str()}});
  }
  Error Top(const std::string& field, const std::string& why) const {
    return errors_.At({{field.c_str()}}, why);
  }

 private:
  FieldErrors errors_;
};

}  // namespace

const char* ToString(CameraRole role) {
  switch (role) {
    case CameraRole::kCorner:
      return "corner";
    case CameraRole::kFloor:
      return "floor";
    case CameraRole::kCornerAndFloor:
      return "corner+floor";
  }
  return "?";
}

namespace {

// domain, security_dir and the periods.
Status ParseServiceWide(const proto::ServiceConfig& msg, const std::string& base_dir,
                        const ConfigErrors& errors, ServiceSetup* out_setup) {
  ServiceSetup& out = *out_setup;
  // Cyclone DDS maps a domain to UDP ports; 232 is the highest id whose ports fit.
  if (msg.domain() < 0 || msg.domain() > 232) return errors.Top("domain", "must be 0..232");
  out.domain = msg.domain();
  if (!msg.security_dir().empty()) {
    std::filesystem::path dir = msg.security_dir();
    if (dir.is_relative() && !base_dir.empty()) dir = std::filesystem::path(base_dir) / dir;
    out.security_dir = dir.string();
    if (auto c = dds::CheckSecurityDirectory(out.security_dir); !c)
      return errors.Top("security_dir", c.error().message);
    // DDS Security's governance documents name domains 0..230 (Cyclone rejects more).
    if (out.domain > 230) return errors.Top("domain", "must be 0..230 with security_dir");
  }
  if (msg.has_status_period_s()) {
    if (!(msg.status_period_s() >= 0.05 && msg.status_period_s() <= 3600))
      return errors.Top("status_period_s", "must be 0.05..3600 seconds");
    out.status_period =
        std::chrono::milliseconds(static_cast<int64_t>(msg.status_period_s() * 1000));
  }
  if (msg.has_ros_discovery_info()) {
    const std::string& v = msg.ros_discovery_info();
    if (v == "jazzy") {
      out.ros_discovery = RosDiscoveryLayout::kIronAndLater;
    } else if (v == "humble") {
      out.ros_discovery = RosDiscoveryLayout::kHumble;
    } else if (v == "off") {
      out.ros_discovery = RosDiscoveryLayout::kOff;
    } else {
      return errors.Top("ros_discovery_info",
                        "must be \"jazzy\" (Iron and later), \"humble\" or \"off\"");
    }
  }
  if (msg.has_discovery_wait_s()) {
    if (!(msg.discovery_wait_s() >= 0 && msg.discovery_wait_s() <= 60))
      return errors.Top("discovery_wait_s", "must be 0..60 seconds");
    out.discovery_wait =
        std::chrono::milliseconds(static_cast<int64_t>(msg.discovery_wait_s() * 1000));
  }
  return Ok{};
}

// A camera's name, device, role and calibration file; the id must be new to `ids`.
Status ParseCameraIdentity(const proto::CameraConfig& c, int i, const std::string& base_dir,
                           const ConfigErrors& errors, std::set<std::string>* ids,
                           CameraSetup* cam_out) {
  CameraSetup& cam = *cam_out;
  if (c.device().empty())
    return errors.Camera(i, "device",
                         "is missing: an Aravis id, IP, serial, sim-corner or ros:/image/topic");
  if (c.device().size() > kMaxNameLength)
    return errors.Camera(i, "device",
                         "is longer than " + std::to_string(kMaxNameLength) + " characters");
  if (c.id().size() > kMaxNameLength)
    return errors.Camera(i, "id",
                         "is longer than " + std::to_string(kMaxNameLength) + " characters");
  if (IsRosTopicDevice(c.device())) {
    if (auto topic = RosTopicOfDevice(c.device()); !topic)
      return errors.Camera(i, "device", topic.error().message);
    if (c.id().empty())
      return errors.Camera(i, "id", "is needed for an image topic camera: e.g. id: \"front\"",
                           "device");
  }
  cam.options.device = c.device();
  cam.id = c.id().empty() ? c.device() : c.id();
  if (!ids->insert(cam.id).second)
    return errors.Camera(i, "id", "'" + cam.id + "' names two cameras; give each its own id",
                         c.id().empty() ? "device" : "id");
  switch (c.role()) {
    case proto::CORNER:
      cam.role = CameraRole::kCorner;
      break;
    case proto::FLOOR:
      cam.role = CameraRole::kFloor;
      break;
    case proto::CORNER_AND_FLOOR:
      cam.role = CameraRole::kCornerAndFloor;
      break;
    default:
      return errors.Camera(i, "role", "is missing: CORNER, FLOOR or CORNER_AND_FLOOR");
  }
  if (c.has_ceiling_distance_m()) {
    if (!(c.ceiling_distance_m() > 0 && c.ceiling_distance_m() < 100))
      return errors.Camera(i, "ceiling_distance_m", "must be 0..100 metres");
    cam.ceiling_distance_m = c.ceiling_distance_m();
  }
  if (c.calibration().empty()) {
    // An image topic's corner camera may take its intrinsics from the driver's camera_info.
    const bool from_camera_info = IsRosTopicDevice(c.device()) && cam.role == CameraRole::kCorner;
    if (from_camera_info && cam.ceiling_distance_m) return Ok{};
    if (from_camera_info)
      return errors.Camera(i, "ceiling_distance_m",
                           "is needed when the intrinsics come from camera_info (no calibration "
                           "file): the camera's distance to the ceiling, metres",
                           "device");
    return errors.Camera(i, "calibration",
                         "is missing: the camera's calibration file (monocle intrinsics "
                         "calibrate writes one)");
  }
  std::filesystem::path path(c.calibration());
  if (path.is_relative() && !base_dir.empty()) path = std::filesystem::path(base_dir) / path;
  cam.calibration_path = path.lexically_normal().string();
  return Ok{};
}

// What the camera is opened with (AravisOptions) and how long a stalled stream is waited for.
Status ParseDeviceOptions(const proto::CameraConfig& c, int i, const ConfigErrors& errors,
                          CameraSetup* cam_out) {
  CameraSetup& cam = *cam_out;
  // The robot's camera driver owns an image topic's device: its settings are the driver's.
  if (IsRosTopicDevice(c.device()) &&
      (!c.pixel_format().empty() || c.has_exposure_us() || c.has_gain() || c.has_frame_rate_hz() ||
       c.has_packet_size_bytes() || c.has_inter_packet_delay_ticks() || c.feature_size() > 0)) {
    return errors.Camera(i, "device",
                         "is an image topic: its camera's settings (pixel_format, exposure_us, "
                         "gain, frame_rate_hz, packet sizes, feature) belong to the driver that "
                         "publishes it; remove them here");
  }
  if (!c.pixel_format().empty()) cam.options.pixel_format = c.pixel_format();
  if (c.has_exposure_us()) {
    if (!(c.exposure_us() > 0)) return errors.Camera(i, "exposure_us", "must be > 0 µs");
    cam.options.exposure_us = c.exposure_us();
  }
  if (c.has_gain()) cam.options.gain = c.gain();
  if (c.has_frame_rate_hz()) {
    if (!(c.frame_rate_hz() > 0)) return errors.Camera(i, "frame_rate_hz", "must be > 0 Hz");
    cam.options.frame_rate_hz = c.frame_rate_hz();
  }
  if (c.has_packet_size_bytes()) cam.options.packet_size_bytes = c.packet_size_bytes();
  if (c.has_inter_packet_delay_ticks())
    cam.options.inter_packet_delay_ticks = c.inter_packet_delay_ticks();
  for (const auto& f : c.feature()) {
    if (f.name().empty()) return errors.Camera(i, "feature", "has an empty name");
    cam.options.features.emplace_back(f.name(), f.value());
  }
  if (c.has_stall_timeout_s()) {
    if (!(c.stall_timeout_s() >= 0.05 && c.stall_timeout_s() <= 600))
      return errors.Camera(i, "stall_timeout_s", "must be 0.05..600 seconds");
    cam.stall_timeout = std::chrono::milliseconds(static_cast<int64_t>(c.stall_timeout_s() * 1000));
  }
  return Ok{};
}

// The camera's ROS 2 names and the live image's rate.
Status ParseRosNames(const proto::CameraConfig& c, int i, const ConfigErrors& errors,
                     CameraSetup* cam_out) {
  CameraSetup& cam = *cam_out;
  cam.ros_namespace =
      c.ros_namespace().empty() ? "/monocle/" + RosNameToken(cam.id) : c.ros_namespace();
  while (cam.ros_namespace.size() > 1 && cam.ros_namespace.back() == '/')
    cam.ros_namespace.pop_back();
  if (cam.ros_namespace.front() != '/') cam.ros_namespace = "/" + cam.ros_namespace;
  for (size_t k = 1; k < cam.ros_namespace.size(); ++k) {
    const char ch = cam.ros_namespace[k];
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '/') ||
        (ch == '/' && cam.ros_namespace[k - 1] == '/'))
      return errors.Camera(
          i, "ros_namespace",
          "'" + c.ros_namespace() + "' is not a ROS 2 namespace (letters, digits, _ and single /)");
  }
  cam.ros_parent_frame = c.ros_parent_frame().empty() ? "corner" : c.ros_parent_frame();
  cam.ros_frame = cam.ros_namespace.substr(cam.ros_namespace.find_last_of('/') + 1) + "_optical";
  if (c.has_image_max_rate_hz()) {
    if (!(c.image_max_rate_hz() > 0 && c.image_max_rate_hz() <= 1000))
      return errors.Camera(i, "image_max_rate_hz", "must be 0..1000 Hz");
    cam.image_max_rate_hz = c.image_max_rate_hz();
  }
  return Ok{};
}

// The camera on the robot.
Status ParseMount(const proto::CameraConfig& c, int i, const ConfigErrors& errors,
                  CameraSetup* cam_out) {
  CameraSetup& cam = *cam_out;
  if (c.has_mount()) {
    const auto& m = c.mount();
    if (m.base_frame().empty())
      return errors.Camera(i, "mount.base_frame", "is missing, e.g. \"base_link\"", "mount");
    if (m.translation_m_size() != 3)
      return errors.Camera(i, "mount.translation_m", "needs 3 values: x, y, z in metres", "mount");
    if (m.rotation_xyzw_size() != 4)
      return errors.Camera(i, "mount.rotation_xyzw", "needs 4 values: a quaternion x, y, z, w",
                           "mount");
    double norm2 = 0;
    for (double q : m.rotation_xyzw()) norm2 += q * q;
    if (!(std::abs(std::sqrt(norm2) - 1) < 1e-3))
      return errors.Camera(
          i, "mount.rotation_xyzw",
          "must be a unit quaternion (its norm is " + std::to_string(std::sqrt(norm2)) + ")",
          "mount");
    CameraSetup::Mount mount;
    mount.base_frame = m.base_frame();
    for (int k = 0; k < 3; ++k) mount.translation_m[static_cast<size_t>(k)] = m.translation_m(k);
    // As given: MountTransform normalizes it, as a mount file's is (room_map_file.cc).
    for (int k = 0; k < 4; ++k) mount.rotation_xyzw[static_cast<size_t>(k)] = m.rotation_xyzw(k);
    cam.mount = mount;
  }
  return Ok{};
}

// The room map, the robot's level and where it starts (each needs the mount).
Status ParseRoomMapAndLevel(const proto::CameraConfig& c, int i, const std::string& base_dir,
                            const ConfigErrors& errors, CameraSetup* cam_out) {
  CameraSetup& cam = *cam_out;
  if (!c.room_map().empty()) {
    if (!cam.mount) {
      return errors.Camera(i, "room_map",
                           "needs the camera's mount on the robot (mount { base_frame "
                           "translation_m rotation_xyzw }): its height gives each corner's "
                           "ceiling distance");
    }
    if (c.has_ceiling_distance_m()) {
      return errors.Camera(i, "ceiling_distance_m",
                           "is not used with a room_map: each corner's follows from the map's "
                           "ceiling height and the mount's height; remove it");
    }
    std::filesystem::path map_path(c.room_map());
    if (map_path.is_relative() && !base_dir.empty())
      map_path = std::filesystem::path(base_dir) / map_path;
    auto map = LoadRoomMapFile(map_path.lexically_normal().string());
    if (!map) return errors.Camera(i, "room_map", "cannot be used: " + map.error().message);
    const double height = cam.mount->translation_m[2];
    for (const auto& room : map->rooms) {
      if (!(height > 0 && height < room.ceiling_height_m - 0.1)) {
        char why[512];
        std::snprintf(why, sizeof why,
                      "puts the camera %.2f m above the floor: it must be above the floor and "
                      "0.1 m below the ceiling of room '%.40s' (%.2f m) of the room map",
                      height, room.id.c_str(), room.ceiling_height_m);
        return errors.Camera(i, "mount.translation_m", why, "mount");
      }
    }
    cam.ceiling_distance_m = map->rooms.front().ceiling_height_m - height;
    cam.room_map_path = map_path.lexically_normal().string();
    cam.room_map = std::make_shared<const RoomMap>(std::move(*map));
  }
  if (c.has_level_sigma_deg()) {
    if (!cam.mount)
      return errors.Camera(i, "level_sigma_deg",
                           "needs the camera's mount on the robot (mount { base_frame "
                           "translation_m rotation_xyzw }): the level fixes the camera's tilt "
                           "and swing through it");
    if (!(c.level_sigma_deg() >= 0.01 && c.level_sigma_deg() <= 5))
      return errors.Camera(i, "level_sigma_deg",
                           "must be how level the robot stands, 1 sigma in degrees (0.01-5)");
    cam.level_sigma_rad = c.level_sigma_deg() * std::numbers::pi / 180;
  }
  if (c.initial_pose_size() > 0) {
    if (!cam.room_map) return errors.Camera(i, "initial_pose", "needs a room_map to be a pose in");
    if (c.initial_pose_size() != 3)
      return errors.Camera(i, "initial_pose", "needs 3 values: x_m, y_m, heading_deg");
    const BasePose2d start{c.initial_pose(0), c.initial_pose(1),
                           c.initial_pose(2) * std::numbers::pi / 180};
    if (RoomContaining(*cam.room_map, {start.x_m, start.y_m}) == nullptr)
      return errors.Camera(i, "initial_pose", "lies in no room of the room map");
    cam.initial_pose = start;
  }
  return Ok{};
}

}  // namespace

Result<ServiceSetup> ParseServiceConfig(const std::string& text, const std::string& source,
                                        const std::string& base_dir) {
  proto::ServiceConfig msg;
  TextFormat::ParseInfoTree tree;
  if (auto parsed = ParseTextProto(text, source, &msg, &tree); !parsed) return parsed.error();
  const ConfigErrors errors(source, tree);
  ServiceSetup out;
  if (Status s = ParseServiceWide(msg, base_dir, errors, &out); !s) return s.error();
  if (msg.camera_size() == 0)
    return MakeError(ErrorCode::kInvalidArgument,
                     source + ": no camera { ... } configured (see monocled --print-config)");
  // One service runs a thread or two per camera and opens a dozen DDS endpoints for each:
  // past a few dozen cameras that is a configuration mistake (or an attack), not a robot.
  if (msg.camera_size() > kMaxCamerasPerService)
    return errors.Camera(kMaxCamerasPerService, "id",
                         "is one camera too many: a service serves at most " +
                             std::to_string(kMaxCamerasPerService) +
                             " cameras; run another monocled for more");
  std::set<std::string> ids;
  for (int i = 0; i < msg.camera_size(); ++i) {
    const auto& c = msg.camera(i);
    CameraSetup cam;
    // In this order: each part may rely on the ones before it (the room map on the mount).
    if (Status s = ParseCameraIdentity(c, i, base_dir, errors, &ids, &cam); !s) return s.error();
    if (Status s = ParseDeviceOptions(c, i, errors, &cam); !s) return s.error();
    if (Status s = ParseRosNames(c, i, errors, &cam); !s) return s.error();
    if (Status s = ParseMount(c, i, errors, &cam); !s) return s.error();
    if (Status s = ParseRoomMapAndLevel(c, i, base_dir, errors, &cam); !s) return s.error();
    out.cameras.push_back(std::move(cam));
  }
  return out;
}

CornerPipelineOptions CornerPipelineOptionsOf(const CameraSetup& camera) {
  CornerPipelineOptions options;
  options.ceiling_distance_m = camera.ceiling_distance_m;
  if (camera.mount) options.base_camera = MountTransform(*camera.mount);
  options.level_sigma_rad = camera.level_sigma_rad;
  options.room_map = camera.room_map;
  options.initial_pose = camera.initial_pose;
  return options;
}

RigidTransform MountTransform(const CameraSetup::Mount& m) {
  const auto& q = m.rotation_xyzw;
  // Normalized once, the same way a mount file is (LoadCameraMountFile), so monocled and
  // `monocle corner locate --mount` / `replay --mount` place poses identically.
  return {Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized(),
          Eigen::Vector3d(m.translation_m[0], m.translation_m[1], m.translation_m[2])};
}

std::string RosNameToken(const std::string& name) {
  std::string out;
  for (const char ch : name) out += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out.front()))) out = "_" + out;
  return out;
}

Result<ServiceSetup> LoadServiceConfig(const std::string& path) {
  auto text = ReadBoundedFile(path, "configuration file", kMaxTextFileBytes);
  if (!text) return text.error();
  // Relative paths in the file are the file's folder's, spelled out in full so an error
  // names the file that was tried.
  std::error_code ec;
  const auto folder = std::filesystem::absolute(path, ec).parent_path().string();
  return ParseServiceConfig(*text, path, ec ? std::string() : folder);
}

std::string EmbeddedDefaultConfig(const std::string& calibration_dir) {
  auto in_dir = [&](const std::string& file) {
    return calibration_dir.empty() ? file
                                   : (std::filesystem::path(calibration_dir) / file).string();
  };
  return "# monocled's embedded default: the two in-process simulated cameras.\n" +
         std::string(
             calibration_dir.empty()
                 ? "# Calibration paths are relative to the state directory (--state-dir).\n"
                 : "# Their calibration files are in the state directory, " + calibration_dir +
                       ".\n") +
         "domain: 0\n"
         "camera {\n"
         "  id: \"sim-corner\"\n"
         "  device: \"sim-corner\"\n"
         "  role: CORNER\n"
         "  calibration: \"" +
         in_dir("sim-corner.pbtxt") +
         "\"\n"
         "}\n"
         "camera {\n"
         "  id: \"sim-floor\"\n"
         "  device: \"sim-floor\"\n"
         "  role: FLOOR\n"
         "  calibration: \"" +
         in_dir("sim-floor.pbtxt") +
         "\"\n"
         "}\n";
}

}  // namespace monocle
