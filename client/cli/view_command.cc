// monocle view: the service's live frame of one camera, with what the service concluded from
// it drawn on it (the corner pose's edges, or the floor calibration's distances and horizon).
#include <algorithm>
#include <csignal>
#include <deque>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <thread>

#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/live.h"
#include "client/cli/shared_options.h"
#include "idl/protocol/dds.h"
#include "idl/protocol/wire.h"
#include "idl/ros2_messages.h"
#include "service/io/calibration_file.h"
#include "service/io/image_codec.h"
#include "service/vision/corner_tracker.h"
#include "service/vision/floor_overlay.h"
#include "service/vision/overlay_text.h"

namespace monocle::cli {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

constexpr const char* kViewAbout =
    R"(Saves the service's live frame of a camera with what the service measured in it drawn on it:
for a corner camera the three edges its pose predicts (through the lens; X red, Y green,
Z blue), the corner, the pose (metres, degrees in the corner frame), detected or tracked,
SUSPECT with its reason; for a floor camera the distances ahead on the floor (metres), the
horizon and the robot frame's axes from the camera's floor calibration. The frame comes from
the camera's ROS 2 image_raw topic (published while someone subscribes, at most
image_max_rate_hz). A corner camera's picture waits for a frame whose pose this view can
hear; with no pose heard within --timeout it shows the last frame and says so.)";

volatile std::sig_atomic_t g_stop = 0;
void OnStopSignal(int) { g_stop = 1; }

struct LiveFrame {
  cv::Mat grey;
  int64_t stamp_ns = 0;
};

void PutText(cv::Mat& image, const std::string& text, cv::Point at, double scale,
             const cv::Scalar& colour) {
  PutOutlinedText(image, text, at, scale, colour, 1);
}

// The corner camera's picture: the pose of this very frame (or why there is none,
// `no_pose_reason`).
void DrawCornerView(cv::Mat& image, const CameraIntrinsics& k, const std::optional<Pose>& pose,
                    const std::string& no_pose_reason) {
  if (!pose) {
    PutText(image, "no pose for this frame (" + no_pose_reason + ")", {12, 32}, 0.7,
            cv::Scalar(0, 200, 255));
    return;
  }
  if (!pose->valid) {
    PutWrappedText(image, "no corner: " + pose->error, {12, 32}, 0.6, cv::Scalar(0, 0, 255), 1);
    return;
  }
  const CornerPose p{pose->x_m,     pose->y_m,      pose->z_m,
                     pose->pan_rad, pose->tilt_rad, pose->swing_rad};
  const cv::Point corner(static_cast<int>(std::lround(pose->corner_px[0])),
                         static_cast<int>(std::lround(pose->corner_px[1])));
  const cv::Scalar colours[3] = {cv::Scalar(110, 110, 255), cv::Scalar(110, 255, 110),
                                 cv::Scalar(255, 190, 110)};
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<cv::Point> curve{corner};
    for (const auto& px : PredictEdgePx(k, p, axis, 4))
      curve.emplace_back(static_cast<int>(std::lround(px.x())),
                         static_cast<int>(std::lround(px.y())));
    cv::polylines(image, curve, false, cv::Scalar(0, 0, 0), 4, cv::LINE_AA);
    cv::polylines(image, curve, false, colours[axis], 2, cv::LINE_AA);
    if (curve.size() > 30) {
      PutText(image,
              axis == 0   ? "X"
              : axis == 1 ? "Y"
                          : "Z",
              curve[curve.size() * 3 / 4], 0.9, colours[axis]);
    }
  }
  cv::circle(image, corner, 8, cv::Scalar(0, 255, 255), 2, cv::LINE_AA);
  std::ostringstream line;
  line << std::fixed << std::setprecision(3) << "x " << p.x_m << " y " << p.y_m << " z " << p.z_m
       << " m  pan " << std::setprecision(2) << p.pan_rad * kDeg << " tilt " << p.tilt_rad * kDeg
       << " swing " << p.swing_rad * kDeg << " deg";
  PutText(image, line.str(), {12, 32}, 0.8, cv::Scalar(0, 255, 255));
  std::ostringstream second;
  second << std::fixed << std::setprecision(1) << "1 sigma x "
         << std::sqrt(pose->covariance[0]) * 1000 << " mm, y "
         << std::sqrt(pose->covariance[6]) * 1000 << " mm  rms " << std::setprecision(2)
         << pose->rms_px << " px  " << (pose->tracked ? "tracked" : "detected");
  PutText(image, second.str(), {12, 62}, 0.6, cv::Scalar(0, 255, 255));
  if (pose->suspect) {
    PutWrappedText(image, "SUSPECT: " + pose->suspect_reason, {12, 90}, 0.6, cv::Scalar(0, 0, 255),
                   1);
  }
}

// What the command line asks of `monocle view`, checked once.
struct ViewOptions {
  std::string camera, out;
  double every_s = 0, count = 1;
  LiveOptions live;
};

// kExitOk with `o` filled, -1 when the help was printed, or the exit status of the mistake
// (already reported).
int ParseViewOptions(const std::vector<std::string>& argv, ViewOptions* o) {
  std::optional<double> count;
  CommandLine line("view", kViewAbout);
  line.Text("--camera", &o->camera, "ID", "the camera (`monocle status` lists them)");
  line.Require("--camera");
  line.Custom("--out", "LIVE.png",
              "where to save the picture (replaced in one step: a viewer never reads half)",
              [o](const std::string& out) -> std::optional<std::string> {
                const auto ext = std::filesystem::path(out).extension().string();
                if (!CanWriteImageExtension(ext))
                  return out + ": give an image file name ending .png, .jpg or .pgm, e.g. live.png";
                o->out = out;
                return std::nullopt;
              });
  line.Require("--out");
  line.Number("--every", &o->every_s, "S",
              "save a new picture every S seconds until Ctrl-C (0: once)",
              In("seconds").Between(0, 86400));
  line.Number("--count", &count, "N", "stop after N pictures (with --every)",
              In("pictures").AtLeast(1).Integer());
  DeclareServiceOptions(line, &o->live, "give up after S seconds without a frame");
  if (const auto exit_now = line.Parse(argv)) return *exit_now == kExitOk ? -1 : *exit_now;
  o->count = count.value_or(o->every_s > 0 ? 1e18 : 1);
  return kExitOk;
}

// The camera as the service describes it: its status, its published calibration and that
// calibration file's own values.
struct ViewedCamera {
  CameraStatus status;
  Calibration calibration;
  CameraCalibration file;
  bool corner() const { return status.role != "floor"; }
};

int FindCamera(Client& client, int domain, const std::string& name, ViewedCamera* out) {
  auto cam = FindServiceCamera(client, name, domain);
  if (!cam) return Fail(cam.error(), kExitFailure);
  auto calibrations = client.calibrations();
  if (!calibrations) return Fail(calibrations.error());
  std::optional<Calibration> calibration;
  for (const auto& c : *calibrations)
    if (c.camera_id == cam->camera_id) calibration = c;
  if (!calibration)
    return Fail("the service published no calibration of '" + name + "'", kExitFailure);
  // The calibration file's own text, as the service published it: intrinsics and floor pose.
  auto file = ParseCalibration(calibration->text, "the service's calibration of '" + name + "'");
  if (!file) return Fail(file.error(), kExitFailure);
  *out = ViewedCamera{*cam, *calibration, *file};
  return kExitOk;
}

// Poses of the camera, kept for a moment to meet their frames. A frame's pose can be met
// only if it was published after this subscription began to hear the service: the service
// publishes poses in frame order, so that holds for every frame from the first pose heard
// on. An earlier frame (the image reader may match first) would wait for a pose it can
// never hear and be taken for one the service skipped.
class RecentPoses {
 public:
  void Add(const Pose& p) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!first_stamp_ns_) first_stamp_ns_ = p.capture_time_ns;
    poses_.push_back(p);
    if (poses_.size() > 200) poses_.pop_front();
  }
  bool CanArrive(int64_t frame_stamp_ns) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return first_stamp_ns_ && frame_stamp_ns >= *first_stamp_ns_;
  }
  // The frame's pose, published once the frame is processed: waited for until a pose of a
  // later frame shows that the service skipped this one (poses come in frame order), or 5 s
  // (a busy or slow service, e.g. a sanitizer build, takes more than a frame time).
  std::optional<Pose> WaitFor(int64_t frame_stamp_ns) const {
    for (int i = 0; i < 250; ++i) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        bool skipped = false;
        for (const auto& p : poses_) {
          if (p.capture_time_ns == frame_stamp_ns) return p;
          skipped |= p.capture_time_ns > frame_stamp_ns;
        }
        if (skipped) return std::nullopt;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return std::nullopt;
  }

 private:
  mutable std::mutex mutex_;
  std::deque<Pose> poses_;
  std::optional<int64_t> first_stamp_ns_;
};

using ImageReader = dds::Endpoint<sensor_msgs_msg_dds__Image_>;

// The first frame after `next_due` (for a corner camera, one whose pose can be heard), or the
// newest frame before that as `unpaired` if no pose comes; neither when the time is up.
Status TakeFrame(ImageReader& images, const ViewOptions& o, bool corner, const RecentPoses& poses,
                 std::chrono::steady_clock::time_point next_due, std::optional<LiveFrame>* frame,
                 std::optional<LiveFrame>* unpaired) {
  const auto give_up = std::max(std::chrono::steady_clock::now(), next_due) +
                       std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                           std::chrono::duration<double>(o.live.timeout_s));
  while (!*frame && !g_stop && std::chrono::steady_clock::now() < give_up) {
    auto taken = images.Take<LiveFrame>(std::chrono::milliseconds(200), [](const auto& s) {
      LiveFrame f;
      if (std::string(s.encoding ? s.encoding : "") == "mono8" && s.width > 0 &&
          static_cast<uint64_t>(s.step) * s.height == s.data._length && s.step >= s.width) {
        f.grey = cv::Mat(static_cast<int>(s.height), static_cast<int>(s.width), CV_8UC1,
                         s.data._buffer, s.step)
                     .clone();
      }
      f.stamp_ns = int64_t{s.header.stamp.sec} * 1000000000 + s.header.stamp.nanosec;
      return f;
    });
    if (!taken) return taken.error();
    if (std::chrono::steady_clock::now() < next_due) continue;
    for (auto& f : *taken) {
      if (f.grey.empty()) continue;
      const bool pose_can_arrive = !corner || poses.CanArrive(f.stamp_ns);
      (pose_can_arrive ? *frame : *unpaired) = std::move(f);
    }
  }
  return Ok{};
}

// The frame with what the service measured in it drawn on it.
cv::Mat DrawPicture(const ViewedCamera& cam, const LiveFrame& frame, const RecentPoses& poses,
                    bool no_pose_heard) {
  cv::Mat picture;
  cv::cvtColor(frame.grey, picture, cv::COLOR_GRAY2BGR);
  const CameraIntrinsics& k = cam.file.intrinsics;
  if (cam.corner()) {
    const std::optional<Pose> pose = no_pose_heard ? std::nullopt : poses.WaitFor(frame.stamp_ns);
    DrawCornerView(picture, k, pose,
                   no_pose_heard ? "no pose heard from the service within --timeout"
                                 : "the service skipped it while busy");
  } else if (cam.file.floor) {
    const FloorPose& floor = cam.file.floor->pose;
    DrawFloorFrame(picture, k, floor);
    std::ostringstream caption;
    caption << std::fixed << std::setprecision(3) << "floor: h " << floor.height_m << " m  pitch "
            << std::setprecision(2) << floor.pitch_rad * kDeg << " deg  (rev "
            << cam.calibration.revision << ")";
    PutText(picture, caption.str(), {12, 32}, 0.8, cv::Scalar(0, 255, 255));
  } else {
    PutText(picture, "floor camera without a floor calibration: `monocle floor calibrate`",
            {12, 32}, 0.7, cv::Scalar(0, 0, 255));
  }
  std::ostringstream stamp;
  stamp << cam.status.camera_id << "  frame at " << frame.stamp_ns << " ns";
  PutText(picture, stamp.str(), {12, picture.rows - 40}, 0.5, cv::Scalar(255, 255, 255));
  return picture;
}

// Replaced in one step (rename), so a viewer polling the file never reads half a picture.
Status SavePicture(const std::string& out, const cv::Mat& picture) {
  const std::string partial = out + ".partial" + std::filesystem::path(out).extension().string();
  if (Status s = WriteImage(partial, picture); !s) return s;
  std::error_code ec;
  std::filesystem::rename(partial, out, ec);
  if (ec) return MakeError(ErrorCode::kIo, "cannot write " + out + ": " + ec.message());
  return Ok{};
}

}  // namespace

int ViewCommand(const std::vector<std::string>& argv) {
  ViewOptions o;
  if (int status = ParseViewOptions(argv, &o); status != kExitOk)
    return status < 0 ? kExitOk : status;  // -1: the help was asked for and printed
  int status = kExitOk;
  auto client = OpenClient(o.live, &status);
  if (!client) return status;
  ViewedCamera cam;
  if (int found = FindCamera(*client, o.live.domain, o.camera, &cam); found != kExitOk)
    return found;
  RecentPoses poses;
  std::optional<Subscription> subscription;
  if (cam.corner()) {
    auto sub = client->subscribe_poses([&](const Pose& p) { poses.Add(p); }, o.camera);
    if (!sub) return Fail(sub.error());
    subscription.emplace(std::move(*sub));
  }
  std::string security = o.live.security_dir.value_or("");
  if (security.empty()) {
    if (const char* env = std::getenv("MONOCLE_SECURITY")) security = env;
  }
  auto participant = dds::CreateParticipant(static_cast<dds_domainid_t>(o.live.domain), security);
  if (!participant) return Fail(participant.error(), kExitFailure);
  const std::string topic = wire::RosTopic(cam.status.ros_namespace, "image_raw");
  auto images = ImageReader::Open(*participant, &sensor_msgs_msg_dds__Image__desc, topic.c_str(),
                                  false, true, wire::kRosDefaultQos);
  if (!images) return Fail(images.error(), kExitFailure);

  std::signal(SIGINT, OnStopSignal);
  std::signal(SIGTERM, OnStopSignal);
  int saved = 0;
  auto next_due = std::chrono::steady_clock::now();
  while (!g_stop && saved < o.count) {
    std::optional<LiveFrame> frame, unpaired;
    if (Status s = TakeFrame(*images, o, cam.corner(), poses, next_due, &frame, &unpaired); !s)
      return Fail(s.error(), kExitFailure);
    if (g_stop) break;
    const bool no_pose_heard = !frame && unpaired;
    if (no_pose_heard) frame = std::move(unpaired);
    if (!frame) {
      return Fail("no frame from camera '" + o.camera + "' on " + topic + " within " +
                      std::to_string(static_cast<int>(o.live.timeout_s)) +
                      " s (camera state: " + ToString(cam.status.state) +
                      (cam.status.last_error.empty() ? "" : ", " + cam.status.last_error) + ")",
                  kExitFailure);
    }
    const cv::Mat picture = DrawPicture(cam, *frame, poses, no_pose_heard);
    if (Status s = SavePicture(o.out, picture); !s) return Fail(s.error(), kExitFailure);
    ++saved;
    std::cout << "saved " << o.out << " (" << o.camera << ", frame at " << frame->stamp_ns << " ns)"
              << std::endl;
    next_due = std::chrono::steady_clock::now() +
               std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                   std::chrono::duration<double>(o.every_s));
  }
  return kExitOk;
}

}  // namespace monocle::cli
