#include "service/vision/floor_overlay.h"

#include "service/vision/overlay_text.h"

#include <cmath>
#include <functional>
#include <iomanip>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <utility>
#include <vector>

namespace monocle {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;
const cv::Scalar kCornerColour(0, 200, 0);
const cv::Scalar kBoardColour(255, 140, 0);
const cv::Scalar kHorizonColour(0, 140, 255);
const cv::Scalar kXAxisColour(0, 0, 255);
const cv::Scalar kYAxisColour(255, 0, 255);
const cv::Scalar kDistanceColour(0, 230, 230);

cv::Point2d P(const Eigen::Vector2d& v) { return {v.x(), v.y()}; }

void Label(cv::Mat& image, const std::string& text, cv::Point at, const cv::Scalar& colour,
           double scale = 0.55) {
  PutOutlinedText(image, text, at, scale, colour, 1);
}

// Projects a camera-frame point, or nothing where the lens model would fold it back into the
// image: the distortion polynomial is only trusted a little beyond the image's own field.
std::optional<Eigen::Vector2d> ProjectTrusted(const CameraIntrinsics& k,
                                              const Eigen::Vector3d& p_camera) {
  if (p_camera.z() <= 1e-9) return std::nullopt;
  const Eigen::Vector2d n = p_camera.head<2>() / p_camera.z();
  const double reach_x = 1.3 * std::max(k.cx, k.width_px - k.cx) / k.fx;
  const double reach_y = 1.3 * std::max(k.cy, k.height_px - k.cy) / k.fy;
  if (std::abs(n.x()) > reach_x || std::abs(n.y()) > reach_y) return std::nullopt;
  return ProjectToPixel(k, p_camera);
}

// A curve on the floor (or at infinity), sampled finely so that lens distortion bends it as
// it bends the image; drawn where it can be projected. Returns the last point drawn.
std::optional<Eigen::Vector2d> DrawCurve(
    cv::Mat& image, const CameraIntrinsics& k,
    const std::function<std::optional<Eigen::Vector3d>(double)>& camera_point_at, double t0,
    double t1, const cv::Scalar& colour, int thickness = 1) {
  constexpr int kSamples = 400;
  std::optional<Eigen::Vector2d> previous, last;
  for (int s = 0; s <= kSamples; ++s) {
    const double t = t0 + (t1 - t0) * s / kSamples;
    const auto p = camera_point_at(t);
    const auto px = p ? ProjectTrusted(k, *p) : std::nullopt;
    if (px && previous) {
      cv::line(image, P(*previous), P(*px), colour, thickness, cv::LINE_AA);
      last = px;
    }
    previous = px;
  }
  return last;
}

bool Inside(const cv::Mat& image, const Eigen::Vector2d& px, double margin = 0) {
  return px.x() >= margin && px.y() >= margin && px.x() < image.cols - margin &&
         px.y() < image.rows - margin;
}

}  // namespace

bool DrawFloorFrame(cv::Mat& image, const CameraIntrinsics& k, const FloorPose& pose) {
  auto on_floor = [&](double x, double y) -> std::optional<Eigen::Vector3d> {
    return RobotToCamera(pose, Eigen::Vector3d(x, y, 0));
  };
  // Lines of constant distance ahead, labelled where they leave the image on the right.
  for (double y : {0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 7.0, 10.0, 15.0, 20.0}) {
    const auto mid = ProjectRobotPoint(k, pose, Eigen::Vector3d(0, y, 0));
    if (!mid || !Inside(image, *mid)) continue;
    DrawCurve(
        image, k, [&](double x) { return on_floor(x, y); }, -3 * y, 3 * y, kDistanceColour);
    std::ostringstream text;
    text << y << " m";
    Label(image, text.str(),
          cv::Point(static_cast<int>(mid->x()) + 6, static_cast<int>(mid->y()) - 4),
          kDistanceColour);
  }

  // The horizon: where the floor's directions vanish.
  const Eigen::Matrix3d rotation = RotationCameraFromRobot(pose);
  const auto horizon_end = DrawCurve(
      image, k,
      [&](double phi) -> std::optional<Eigen::Vector3d> {
        return rotation * Eigen::Vector3d(std::cos(phi), std::sin(phi), 0);
      },
      0.02, std::numbers::pi - 0.02, kHorizonColour, 2);
  if (horizon_end)
    Label(image, "horizon", {10, static_cast<int>(horizon_end->y()) - 6}, kHorizonColour);
  const bool horizon_in_view = horizon_end && Inside(image, *horizon_end, -1e6) &&
                               horizon_end->y() >= 0 && horizon_end->y() < image.rows;

  // The robot frame's axes: origin on the floor under the optical centre. Usually below the
  // image; then the axes are drawn from the nearest point of Y_w that is in view.
  double y0 = 0;
  while (y0 < 50) {
    const auto px = ProjectRobotPoint(k, pose, Eigen::Vector3d(0, y0, 0));
    if (px && Inside(image, *px, 20)) break;
    y0 += 0.05;
  }
  if (y0 < 50) {
    DrawCurve(
        image, k, [&](double y) { return on_floor(0, y); }, y0, 100, kYAxisColour, 1);
    const double arrow_m = std::max(0.25, 0.15 * y0);
    const auto from = ProjectRobotPoint(k, pose, Eigen::Vector3d(0, y0, 0));
    const auto to_x = ProjectRobotPoint(k, pose, Eigen::Vector3d(arrow_m, y0, 0));
    const auto to_y = ProjectRobotPoint(k, pose, Eigen::Vector3d(0, y0 + arrow_m, 0));
    if (from && to_x && to_y) {
      cv::arrowedLine(image, P(*from), P(*to_x), kXAxisColour, 2, cv::LINE_AA, 0, 0.15);
      cv::arrowedLine(image, P(*from), P(*to_y), kYAxisColour, 2, cv::LINE_AA, 0, 0.15);
      Label(image, "X_w", P(*to_x) + cv::Point2d(6, 14), kXAxisColour);
      Label(image, "Y_w", P(*to_y) + cv::Point2d(6, 0), kYAxisColour);
      if (y0 > 0) {
        std::ostringstream text;
        text << std::fixed << std::setprecision(2) << "axes drawn " << y0
             << " m ahead of the origin (under the camera, out of view)";
        Label(image, text.str(), {10, image.rows - 12}, cv::Scalar(255, 255, 255), 0.45);
      }
    }
  }

  return horizon_in_view;
}

cv::Mat DrawFloorOverlay(const cv::Mat& grey, const CameraIntrinsics& k,
                         const FloorCalibration& floor, const BoardObservation& board,
                         const FloorGuidance& guidance) {
  cv::Mat image;
  cv::cvtColor(grey, image, cv::COLOR_GRAY2BGR);
  const FloorPose& pose = floor.pose;

  // The board's squares where the result puts them, one square beyond the inner corners.
  auto board_point = [&](double i, double j) -> std::optional<Eigen::Vector3d> {
    return RobotToCamera(pose, BoardToRobot(pose.yaw_rad, floor.board_origin_robot_m,
                                            {i * board.square_m, j * board.square_m}));
  };
  for (int i = -1; i <= board.cols; ++i)
    DrawCurve(
        image, k, [&](double j) { return board_point(i, j); }, -1, board.rows, kBoardColour);
  for (int j = -1; j <= board.rows; ++j)
    DrawCurve(
        image, k, [&](double i) { return board_point(i, j); }, -1, board.cols, kBoardColour);
  for (const auto& px : board.pixels) cv::circle(image, P(px), 4, kCornerColour, 1, cv::LINE_AA);

  const bool horizon_in_view = DrawFloorFrame(image, k, pose);

  // Caption on a dark band: the result, a legend in the drawing's colours and, in red, why
  // the result cannot be used.
  cv::Mat band = image(cv::Rect(0, 0, image.cols, std::min(image.rows, 84)));
  band *= 0.45;
  const auto sigma = floor.Sigma();
  std::ostringstream caption;
  caption << std::fixed << std::setprecision(4) << ToString(floor.method) << ": h " << pose.height_m
          << " m +-" << sigma[0] << "  pitch " << std::setprecision(2) << pose.pitch_rad * kDeg
          << " +-" << sigma[1] * kDeg << " deg  roll " << pose.roll_rad * kDeg << " deg  rms "
          << floor.rms_px << " px";
  Label(image, caption.str(), {10, 24}, cv::Scalar(255, 255, 255));
  int x = 10;
  for (const auto& [text, colour] : std::vector<std::pair<std::string, cv::Scalar>>{
           {"o corners found", kCornerColour},
           {"# board reprojected", kBoardColour},
           {"distance ahead", kDistanceColour},
           {horizon_in_view ? "horizon" : "horizon (not in view)", kHorizonColour},
           {"X_w", kXAxisColour},
           {"Y_w", kYAxisColour}}) {
    Label(image, text, {x, 48}, colour, 0.45);
    int baseline = 0;
    x += cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &baseline).width + 18;
  }
  if (guidance.ill_conditioned) {
    Label(image, "ILL-CONDITIONED: the result carries no information (see the output)", {10, 72},
          cv::Scalar(0, 0, 255));
  } else if (!guidance.target_met) {
    Label(image, "target accuracy not met (see the output's advice)", {10, 72},
          cv::Scalar(0, 0, 255));
  }
  return image;
}

}  // namespace monocle
