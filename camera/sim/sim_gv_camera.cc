#include "camera/sim/sim_gv_camera.h"

#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <mutex>
#include <numbers>
#include <sstream>

#include "camera/aravis/aravis_source.h"
#include "camera/aravis/tsan_handoff.h"
#include "camera/render/corner_renderer.h"
#include "camera/render/driving_path.h"
#include "camera/render/floor_renderer.h"
#include "camera/render/reference_camera.h"
#include "camera/render/room_renderer.h"
#include "service/io/bounded_file.h"

namespace monocle {

std::optional<RealisticLook> SimRealisticLook(const SimCameraOptions& o,
                                              const CameraIntrinsics& k) {
  if (!o.realistic) return std::nullopt;
  RealisticLook look = RandomRealisticLook(o.look_seed, k);
  if (o.raw) look.jpeg_quality = 0;
  return look;
}

Result<std::vector<CornerPose>> ReadTrajectoryFile(const std::string& path) {
  auto text = ReadBoundedFile(path, "trajectory file", kMaxTextFileBytes);
  if (!text) return text.error();
  std::istringstream in(*text);
  std::vector<CornerPose> out;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos ||
        line[line.find_first_not_of(" \t")] == '#')
      continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream ss(line);
    CornerPose p;
    std::string extra;
    if (!(ss >> p.x_m >> p.y_m >> p.z_m >> p.pan_rad >> p.tilt_rad >> p.swing_rad) ||
        (ss >> extra)) {
      return MakeError(ErrorCode::kInvalidArgument,
                       path + ": line " + std::to_string(number) +
                           ": expected x,y,z,pan,tilt,swing (metres, radians)");
    }
    if (!(p.x_m > 0 && p.y_m > 0 && p.z_m > 0)) {
      return MakeError(ErrorCode::kOutOfRange,
                       path + ": line " + std::to_string(number) +
                           ": the camera must be inside the room (x, y, z > 0)");
    }
    out.push_back(p);
  }
  if (out.empty()) return MakeError(ErrorCode::kInvalidArgument, path + ": no poses");
  return out;
}

FloorPose SimFloorPose() { return FloorPose{1.05, 2.0595, 0.0698, 0.0262}; }

CameraIntrinsics SimIntrinsics(int width, int height) {
  const double s = width / 1280.0;
  CameraIntrinsics k;
  k.width_px = width;
  k.height_px = height;
  k.fx = 1624.34 * s;
  k.fy = 1623.04 * s;
  k.cx = (width - 1) / 2.0;
  k.cy = (height - 1) / 2.0;
  k.distortion = {-0.07021, 0.07348, -0.00112, 0.00267, 0, 0, 0, 0};
  return k;
}

CameraIntrinsics SimRoomIntrinsics(int width, int height) {
  const double s = width / 1280.0;
  CameraIntrinsics k;
  k.width_px = width;
  k.height_px = height;
  k.fx = k.fy = 700 * s;
  k.cx = (width - 1) / 2.0;
  k.cy = (height - 1) / 2.0;
  k.distortion = {-0.04, 0.01, 0, 0, 0, 0, 0, 0};
  return k;
}

namespace {

// One frame of the room scene: the base at `b`, the camera on the mount (built with Eigen's
// AngleAxis, apart from the code the locator places poses in the map with).
Result<cv::Mat> RenderRoomFrame(const CameraIntrinsics& k, const SimCameraOptions& o,
                                const BasePose2d& b, uint64_t noise_seed) {
  Eigen::Isometry3d map_camera = Eigen::Isometry3d::Identity();
  map_camera.translate(Eigen::Vector3d(b.x_m, b.y_m, 0));
  map_camera.rotate(Eigen::AngleAxisd(b.heading_rad, Eigen::Vector3d::UnitZ()));
  map_camera.translate(o.mount.translation);
  map_camera.rotate(o.mount.rotation);
  const MapRoom* room = RoomContaining(o.room_map, map_camera.translation().head<2>(), 0.01);
  if (room == nullptr) {
    std::ostringstream os;
    os << "the camera on the robot at " << b << " stands in no room of the map";
    return MakeError(ErrorCode::kOutOfRange, os.str());
  }
  RoomScene scene;
  scene.seed = noise_seed;
  scene.realistic = SimRealisticLook(o, k);
  return RenderRoomView(k, *room, map_camera, scene);
}

Error RenderCancelled() {
  return {ErrorCode::kCancelled, "stopped while the simulated camera rendered its frames"};
}

}  // namespace

Result<std::shared_ptr<SimScenes>> SimScenes::Render(const SimCameraOptions& o) {
  if (o.width < 64 || o.height < 64 || o.width > 4096 || o.height > 4096) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "simulated camera size must be 64..4096 pixels each way");
  }
  if (!(o.fps > 0 && o.fps <= 1000))
    return MakeError(ErrorCode::kInvalidArgument, "--fps must be in (0, 1000]");
  if (!(o.speed_mps >= 0 && o.speed_mps <= 5))
    return MakeError(ErrorCode::kInvalidArgument, "--speed must be 0 to 5 m/s");
  if (!(o.turn_deg_per_s >= 0 && o.turn_deg_per_s <= 180))
    return MakeError(ErrorCode::kInvalidArgument, "--turn must be 0 to 180 deg/s");
  // Aravis's fake cameras keep the serial in a 16-byte GenICam register (with its NUL); a
  // longer one leaves the device without GenICam data and Aravis only logs criticals.
  if (o.serial.empty() || o.serial.size() > 15) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "--serial '" + o.serial.substr(0, 40) + "' must be 1 to 15 characters");
  }
  // Rendering takes tens of MB of working images (the undistortion grid, the supersampled
  // edges), free once done; a service keeps freed memory (monocled's mallopt): given back.
  struct GiveBackOnReturn {
    ~GiveBackOnReturn() { malloc_trim(0); }
  } give_back;
  const reference::PixelGridCacheScope grids;  // ends before give_back: the grids go too
  std::shared_ptr<SimScenes> cam(new SimScenes());
  cam->options_ = o;
  if (o.scene == SimScene::kRoom) {
    if (o.room_map.rooms.empty() || o.base_trajectory.empty()) {
      return MakeError(ErrorCode::kInvalidArgument,
                       "the room scene needs a map, a mount and a trajectory (--map, --mount, "
                       "--trajectory)");
    }
    cam->intrinsics_ = SimRoomIntrinsics(o.width, o.height);
    cam->floor_pose_ = SimFloorPose();
    for (size_t i = 0; i < o.base_trajectory.size(); ++i) {
      if (o.cancelled && o.cancelled()) return RenderCancelled();
      auto frame = RenderRoomFrame(cam->intrinsics_, o, o.base_trajectory[i], 100 + i);
      if (!frame) {
        return MakeError(frame.error().code,
                         "trajectory pose " + std::to_string(i + 1) + ": " + frame.error().message);
      }
      cam->frames_.push_back(std::move(*frame));
    }
    return cam;
  }
  cam->intrinsics_ = SimIntrinsics(o.width, o.height);
  const int n = o.trajectory.empty() ? std::max(o.trajectory_frames, 1)
                                     : static_cast<int>(o.trajectory.size());
  // A robot driving a lap under the corner, 1.6 m below the ceiling, camera aimed near it.
  DrivingPath path = ClosedDrivingPath(o.speed_mps, o.turn_deg_per_s, n / o.fps);
  path.ceiling_distance_m = kSimCeilingDistanceM;
  for (int i = 0; i < n; ++i) {
    cam->corner_poses_.push_back(o.trajectory.empty() ? DrivingPoseAt(path, i / o.fps)
                                                      : o.trajectory[i]);
  }
  cam->floor_pose_ = SimFloorPose();
  for (int i = 0; i < (o.scene == SimScene::kCorner ? n : 2); ++i) {
    if (o.cancelled && o.cancelled()) return RenderCancelled();
    if (o.scene == SimScene::kCorner) {
      CornerScene scene;
      scene.noise_sigma = o.noise_sigma;
      scene.seed = 100 + i;
      scene.realistic = SimRealisticLook(o, cam->intrinsics_);
      cam->frames_.push_back(RenderCornerScene(cam->intrinsics_, cam->corner_poses_[i], scene));
    } else {
      FloorScene scene;
      scene.board_cols = 11;
      scene.board_rows = 8;
      scene.square_m = 0.05;
      scene.board_origin_robot_m = CenteredBoardOrigin(cam->floor_pose_, 11, 8, 0.05);
      scene.boxes.push_back(FloorBox{{0.45, 2.3}, {0.3, 0.3}, 0.5});
      scene.noise_sigma = o.noise_sigma;
      scene.seed = 100 + i;
      cam->frames_.push_back(RenderFloorScene(cam->intrinsics_, cam->floor_pose_, scene));
    }
  }
  return cam;
}

void SimScenes::Attach(ArvFakeCamera* fake) {
  arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_WIDTH,
                                 static_cast<guint32>(options_.width));
  arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_HEIGHT,
                                 static_cast<guint32>(options_.height));
  arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_ACQUISITION_FRAME_PERIOD_US,
                                 static_cast<guint32>(std::lround(1e6 / options_.fps)));
  arv_fake_camera_set_fill_pattern(fake, &SimScenes::Fill, this);
}

void SimScenes::Detach(ArvFakeCamera* fake) {
  arv_fake_camera_set_fill_pattern(fake, nullptr, nullptr);
}

Result<std::unique_ptr<SimGvCamera>> SimGvCamera::Start(const SimCameraOptions& o) {
  auto scenes = SimScenes::Render(o);
  if (!scenes) return scenes.error();
  std::unique_ptr<SimGvCamera> cam(new SimGvCamera());
  cam->scenes_ = *scenes;
  std::lock_guard<std::mutex> lock(AravisSetupMutex());
  cam->camera_ =
      GObjectPtr<ArvGvFakeCamera>(arv_gv_fake_camera_new(o.ip.c_str(), o.serial.c_str()));
  if (!cam->camera_ || !arv_gv_fake_camera_is_running(cam->camera_.get())) {
    return MakeError(ErrorCode::kIo, "cannot serve a simulated GigE Vision camera on " + o.ip +
                                         " (is another one already running there? ports 3956/udp)");
  }
  cam->scenes_->Attach(arv_gv_fake_camera_get_fake_camera(cam->camera_.get()));
  return cam;
}

SimGvCamera::~SimGvCamera() {
  if (camera_) {
    // Stop filling from the scenes before they may go away, then stop serving.
    SimScenes::Detach(arv_gv_fake_camera_get_fake_camera(camera_.get()));
    camera_.reset();
  }
}

void SimScenes::Fill(ArvBuffer* buffer, void* self_ptr, guint32, guint32, ArvPixelFormat format) {
  auto* self = static_cast<SimScenes*>(self_ptr);
  BufferTakenOver(buffer);
  // Inside the fill callback the buffer's data size reads 0 (nothing received yet): size the
  // copy by the image width and height the camera set, which its payload always covers.
  auto* data = static_cast<uint8_t*>(const_cast<void*>(arv_buffer_get_data(buffer, nullptr)));
  const int w = arv_buffer_get_image_width(buffer), h = arv_buffer_get_image_height(buffer);
  if (data == nullptr || format != ARV_PIXEL_FORMAT_MONO_8 || w <= 0 || h <= 0) return;
  const cv::Mat& src = self->FrameFor(arv_buffer_get_frame_id(buffer));
  std::memset(data, 0, static_cast<size_t>(w) * h);
  const int rows = std::min(h, src.rows), cols = std::min(w, src.cols);
  for (int y = 0; y < rows; ++y)
    std::memcpy(data + static_cast<size_t>(y) * w, src.ptr<uint8_t>(y), cols);
  // Aravis's fake camera stamps the buffer before this copy (0.1-0.2 ms for 1.2 MB); the
  // simulated frame exists only once copied, so it is complete now: stamp it so, as a real
  // camera's frame is stamped when its data arrives, not before our own copying.
  arv_buffer_set_system_timestamp(buffer, static_cast<guint64>(g_get_real_time()) * 1000);
  BufferHandedOver(buffer);
}

}  // namespace monocle
