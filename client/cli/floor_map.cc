#include "client/cli/floor_map.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "service/pipeline/point_queries.h"

namespace monocle::cli {
namespace {

// Contour levels of the horizontal 1 sigma, metres.
constexpr double kLevels[] = {0.005, 0.01, 0.02, 0.05, 0.10, 0.20, 0.50};
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kBehindM = 0.6;  // shown behind the robot origin, for the camera marker

int LevelOf(double sigma_m) {
  if (!std::isfinite(sigma_m)) return -1;
  int level = 0;
  for (double l : kLevels) level += sigma_m >= l;
  return level;
}

// Colour of a 1 sigma: log scale from 1 mm (blue) to 1 m (red), OpenCV's Turbo map.
cv::Vec3b ColourOf(double sigma_m, const cv::Mat& lut) {
  const double t = std::clamp((std::log10(sigma_m) + 3.0) / 3.0, 0.0, 1.0);
  return lut.at<cv::Vec3b>(0, static_cast<int>(std::lround(t * 255)));
}

std::string Distance(double m) {
  char s[32];
  std::snprintf(s, sizeof s, m < 0.01 ? "%.0f mm" : "%.0f cm", m < 0.01 ? m * 1000 : m * 100);
  return s;
}

// The horizontal 1 sigma of the floor point at each cell centre of the `cols` x `rows` grid
// (X_w = -range..range, Y_w = range..-behind), as `floor measure` reports it; NaN where the
// camera does not see the cell.
Result<cv::Mat> SigmaGrid(const CameraCalibration& calibration, const FloorMapOptions& o, int cols,
                          int rows) {
  const CameraIntrinsics& k = calibration.intrinsics;
  const FloorPose& pose = calibration.floor->pose;
  auto cell_x = [&](int c) { return -o.range_m + (c + 0.5) * o.cell_m; };
  auto cell_y = [&](int r) { return o.range_m - (r + 0.5) * o.cell_m; };  // row 0: farthest
  std::vector<PixelQuery> pixels;
  std::vector<int> cell_of;  // index r * cols + c of each pixel asked
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const auto px = ProjectRobotPoint(k, pose, Eigen::Vector3d(cell_x(c), cell_y(r), 0));
      if (!px || (*px)(0) < 0 || (*px)(1) < 0 || (*px)(0) > k.width_px - 1 ||
          (*px)(1) > k.height_px - 1) {
        continue;  // behind the camera or outside the image: not seen
      }
      pixels.push_back(PixelQuery{(*px)(0), (*px)(1), std::nullopt});
      cell_of.push_back(r * cols + c);
    }
  }
  cv::Mat grid(rows, cols, CV_64F, cv::Scalar(kNan));
  const std::map<std::string, CameraCalibration> cameras{{"map", calibration}};
  for (size_t start = 0; start < pixels.size(); start += kMaxPointsPerRequest) {
    const size_t n = std::min(kMaxPointsPerRequest, pixels.size() - start);
    const std::vector<PixelQuery> batch(pixels.begin() + static_cast<std::ptrdiff_t>(start),
                                        pixels.begin() + static_cast<std::ptrdiff_t>(start + n));
    const RequestAnswer answer = AnswerPointRequest(cameras, "map", batch, o.pixel_sigma_px);
    if (answer.status != RequestStatus::kAnswered) {
      return MakeError(ErrorCode::kInvalidArgument, answer.error);
    }
    for (size_t i = 0; i < n; ++i) {
      const MeasuredPoint& p = answer.points[i];
      if (!p.ok()) continue;  // near the horizon: not measurable
      grid.at<double>(cell_of[start + i]) = std::hypot(p.sigma_m[0], p.sigma_m[1]);
    }
  }
  return grid;
}

// Distance rings every metre, the robot frame's axes, the caption and the colour bar.
void DrawRingsAxesAndLegend(const FloorMapOptions& o, const FloorPose& pose, const cv::Mat& lut,
                            FloorMap* map_out) {
  FloorMap& map = *map_out;
  const int width = map.picture.cols;
  // Distance rings every metre around the robot origin, labelled.
  const double ring_px = 1.0 / o.metres_per_px;
  for (int m = 1; m <= static_cast<int>(o.range_m); ++m) {
    cv::circle(map.picture, map.origin_px, static_cast<int>(std::lround(m * ring_px)),
               cv::Scalar(200, 200, 200), 1, cv::LINE_AA);
    cv::putText(map.picture, std::to_string(m) + " m",
                cv::Point(static_cast<int>(map.origin_px.x) + 4,
                          static_cast<int>(map.origin_px.y - m * ring_px) - 4),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(230, 230, 230), 1, cv::LINE_AA);
  }
  // The robot frame: origin (below the optical centre), X_w right, Y_w forward (up).
  cv::arrowedLine(map.picture, map.origin_px, map.origin_px + cv::Point2d(0.5 * ring_px, 0),
                  cv::Scalar(0, 0, 255), 2, cv::LINE_AA, 0, 0.2);
  cv::arrowedLine(map.picture, map.origin_px, map.origin_px - cv::Point2d(0, 0.5 * ring_px),
                  cv::Scalar(255, 0, 255), 2, cv::LINE_AA, 0, 0.2);
  cv::putText(map.picture, "X", map.origin_px + cv::Point2d(0.5 * ring_px + 4, 5),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
  cv::putText(map.picture, "Y", map.origin_px - cv::Point2d(4, 0.5 * ring_px + 6),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 0, 255), 1, cv::LINE_AA);
  // Caption and colour bar.
  char caption[160];
  std::snprintf(caption, sizeof caption,
                "horizontal 1-sigma of a floor point; camera h %.3f m, pitch %.1f deg, pixel "
                "noise %.2f px",
                pose.height_m, pose.pitch_rad * 180 / M_PI, o.pixel_sigma_px);
  cv::putText(map.picture, caption, cv::Point(10, 20), cv::FONT_HERSHEY_SIMPLEX, 0.45,
              cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  const int bar_x = 10, bar_y = 32, bar_w = std::min(width - 20, 400), bar_h = 12;
  for (int i = 0; i < bar_w; ++i) {
    const double s = std::pow(10.0, -3.0 + 3.0 * i / (bar_w - 1));
    cv::line(map.picture, cv::Point(bar_x + i, bar_y), cv::Point(bar_x + i, bar_y + bar_h),
             cv::Scalar(ColourOf(s, lut)), 1);
  }
  for (double l : kLevels) {
    const int i = static_cast<int>(std::lround((std::log10(l) + 3.0) / 3.0 * (bar_w - 1)));
    cv::line(map.picture, cv::Point(bar_x + i, bar_y), cv::Point(bar_x + i, bar_y + bar_h + 3),
             cv::Scalar(0, 0, 0), 1);
    cv::putText(map.picture, Distance(l), cv::Point(bar_x + i - 12, bar_y + bar_h + 15),
                cv::FONT_HERSHEY_SIMPLEX, 0.35, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  }
}

}  // namespace

Result<FloorMap> RenderFloorMap(const CameraCalibration& calibration, const FloorMapOptions& o) {
  if (!calibration.floor) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "the calibration has no floor: calibrate it first (monocle floor calibrate)");
  }
  if (!(o.range_m > 0.5 && o.range_m <= 100) || !(o.metres_per_px >= 0.001) ||
      !(o.cell_m >= o.metres_per_px) || o.range_m / o.metres_per_px > 4000 ||
      !(o.pixel_sigma_px >= 0 && o.pixel_sigma_px <= 100)) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "--range must be 0.5..100 m, --resolution 1 mm or more (at most 4000 "
                     "pixels across), cells no finer than the resolution, pixel sigma 0..100 px");
  }
  const FloorPose& pose = calibration.floor->pose;

  // The grid: cell centres at X_w = -range..range, Y_w = -behind..range.
  const int cols = static_cast<int>(std::ceil(2 * o.range_m / o.cell_m));
  const int rows = static_cast<int>(std::ceil((o.range_m + kBehindM) / o.cell_m));
  auto grid = SigmaGrid(calibration, o, cols, rows);
  if (!grid) return grid.error();
  FloorMap map;
  map.metres_per_px = o.metres_per_px;
  const int width = static_cast<int>(std::lround(2 * o.range_m / o.metres_per_px));
  const int height = static_cast<int>(std::lround((o.range_m + kBehindM) / o.metres_per_px));
  map.origin_px = cv::Point2d(width / 2.0, o.range_m / o.metres_per_px);
  map.sigma_m = cv::Mat(height, width, CV_64F);
  cv::Mat lut(1, 256, CV_8UC1);
  for (int i = 0; i < 256; ++i) lut.at<uint8_t>(0, i) = static_cast<uint8_t>(i);
  cv::applyColorMap(lut, lut, cv::COLORMAP_TURBO);
  map.picture = cv::Mat(height, width, CV_8UC3, cv::Scalar(40, 40, 40));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      // The map pixel's centre on the floor, and the grid cell holding it.
      const double fx = (x + 0.5 - map.origin_px.x) * o.metres_per_px;
      const double fy = (map.origin_px.y - y - 0.5) * o.metres_per_px;
      const int c = static_cast<int>(std::floor((fx + o.range_m) / o.cell_m));
      const int r = static_cast<int>(std::floor((o.range_m - fy) / o.cell_m));
      const double s = (c >= 0 && c < cols && r >= 0 && r < rows) ? grid->at<double>(r, c) : kNan;
      map.sigma_m.at<double>(y, x) = s;
      if (std::isfinite(s)) map.picture.at<cv::Vec3b>(y, x) = ColourOf(s, lut);
    }
  }
  // Contours: where the level changes between neighbours (and the footprint's edge).
  for (int y = 0; y + 1 < height; ++y) {
    for (int x = 0; x + 1 < width; ++x) {
      const int l = LevelOf(map.sigma_m.at<double>(y, x));
      if (l != LevelOf(map.sigma_m.at<double>(y, x + 1)) ||
          l != LevelOf(map.sigma_m.at<double>(y + 1, x))) {
        const bool edge = l < 0 || LevelOf(map.sigma_m.at<double>(y, x + 1)) < 0 ||
                          LevelOf(map.sigma_m.at<double>(y + 1, x)) < 0;
        map.picture.at<cv::Vec3b>(y, x) = edge ? cv::Vec3b(255, 255, 255) : cv::Vec3b(0, 0, 0);
      }
    }
  }
  DrawRingsAxesAndLegend(o, pose, lut, &map);
  return map;
}

}  // namespace monocle::cli
