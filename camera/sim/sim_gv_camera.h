// A simulated GigE Vision camera on a local address: Aravis's own ArvGvFakeCamera, its
// frames filled with scenes we render (a ceiling corner seen from a moving robot, or a
// floor with a chessboard and a box). Clients reach it through the real GigE Vision path.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "camera/aravis/glib_handles.h"
#include "camera/render/corner_renderer.h"
#include "service/common/result.h"
#include "service/geometry/camera_model.h"
#include "service/geometry/corner_pose.h"
#include "service/geometry/floor_model.h"
#include "service/geometry/map_pose.h"
#include "service/geometry/robot_frames.h"
#include "service/geometry/room_map.h"

namespace monocle {

enum class SimScene { kCorner, kFloor, kRoom };

struct SimCameraOptions {
  SimScene scene = SimScene::kCorner;
  std::string ip = "127.0.0.1";        // loopback; two simulated cameras cannot share an address
  std::string serial = "MONOCLE-SIM";  // 1 to 15 characters (a 16-byte register)
  int width = 1280, height = 1024;
  double fps = 30;
  // Corner scene: the built-in trajectory is a robot driving a closed loop under the corner at
  // this speed, turning this fast on its own, one lap in `trajectory_frames` frames at `fps`:
  // frame id k shows pose k mod trajectory_frames, and the motion runs on smoothly past the lap.
  int trajectory_frames = 16;
  double speed_mps = 0.3;
  double turn_deg_per_s = 10;
  double noise_sigma = 2;
  // Corner scene: a white-painted room as cameras photograph it (RealisticLook, drawn once
  // from `look_seed`: one room, new sensor noise in every frame) instead of the clean look.
  bool realistic = false;
  uint64_t look_seed = 1;
  // Realistic: frames as a machine-vision camera delivers them, without the JPEG step.
  bool raw = false;
  // Corner scene: poses to drive through instead of the built-in trajectory.
  std::vector<CornerPose> trajectory;
  // Room scene: the robot drives `base_trajectory` (map frame) through `room_map` with its
  // camera on `mount`; a wide lens (SimRoomIntrinsics). Frame id k shows pose k mod N.
  RoomMap room_map;
  RigidTransform mount;
  std::vector<BasePose2d> base_trajectory;
  // Checked between rendered frames: true makes Render give up with kCancelled.
  std::function<bool()> cancelled;
};

// The room scene's lens: focal length 700 px at 1280 px wide (about 85 degrees across), a
// little barrel distortion (idl/examples/wide_camera.pbtxt at 1280 x 1024).
CameraIntrinsics SimRoomIntrinsics(int width, int height);

// The look of a realistic simulated camera with lens `k` (nothing when `options` asks for the
// clean look): drawn from options.look_seed, without the JPEG step when options.raw.
std::optional<RealisticLook> SimRealisticLook(const SimCameraOptions& options,
                                              const CameraIntrinsics& k);

// Reads a trajectory file: one pose a line, "x,y,z,pan,tilt,swing" (metres, radians, the
// corner frame of `monocle corner locate`); blank lines and lines starting with # skipped.
Result<std::vector<CornerPose>> ReadTrajectoryFile(const std::string& path);

// The rendered frames and ground truth of a simulated camera, and the fill pattern that
// hands them to an Aravis fake camera.
class SimScenes {
 public:
  static Result<std::shared_ptr<SimScenes>> Render(const SimCameraOptions& options);

  const SimCameraOptions& options() const { return options_; }
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  // Ground truth, keyed by the frame id the camera sends.
  const cv::Mat& FrameFor(uint64_t frame_id) const { return frames_[frame_id % frames_.size()]; }
  const CornerPose& CornerPoseFor(uint64_t frame_id) const {
    return corner_poses_[frame_id % corner_poses_.size()];
  }
  const FloorPose& floor_pose() const { return floor_pose_; }
  // Room scene: the robot base's pose in the map for each frame (k mod N).
  const std::vector<BasePose2d>& base_trajectory() const { return options_.base_trajectory; }
  const std::vector<CornerPose>& trajectory() const { return corner_poses_; }

  // Sets `fake`'s size and frame rate and makes it send these frames.
  void Attach(ArvFakeCamera* fake);
  static void Detach(ArvFakeCamera* fake);

 private:
  SimScenes() = default;
  static void Fill(ArvBuffer* buffer, void* self, guint32, guint32, ArvPixelFormat);

  SimCameraOptions options_;
  CameraIntrinsics intrinsics_;
  std::vector<cv::Mat> frames_;
  std::vector<CornerPose> corner_poses_;
  FloorPose floor_pose_;
};

// Served on the network: GigE Vision on a local address.
class SimGvCamera {
 public:
  static Result<std::unique_ptr<SimGvCamera>> Start(const SimCameraOptions& options);
  ~SimGvCamera();

  const SimCameraOptions& options() const { return scenes_->options(); }
  const CameraIntrinsics& intrinsics() const { return scenes_->intrinsics(); }
  const cv::Mat& FrameFor(uint64_t frame_id) const { return scenes_->FrameFor(frame_id); }
  const CornerPose& CornerPoseFor(uint64_t frame_id) const {
    return scenes_->CornerPoseFor(frame_id);
  }
  const FloorPose& floor_pose() const { return scenes_->floor_pose(); }
  const std::vector<CornerPose>& trajectory() const { return scenes_->trajectory(); }

 private:
  SimGvCamera() = default;
  std::shared_ptr<SimScenes> scenes_;
  GObjectPtr<ArvGvFakeCamera> camera_;
};

// The intrinsics of the simulated cameras: the paper's camera scaled to width x height.
CameraIntrinsics SimIntrinsics(int width, int height);
// The simulated floor camera's pose above the floor.
FloorPose SimFloorPose();

// Camera to ceiling of the simulated corner trajectory, metres.
inline constexpr double kSimCeilingDistanceM = 1.6;

}  // namespace monocle
