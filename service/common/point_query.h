// A point query and its answer, one type each from the command line to the wire: a floor
// pixel, or a pixel standing vertically above its foot on the floor (Xu et al. 2017, eqs. 5
// and 7), measured as a robot-frame point with its full covariance. Plain values, no Eigen:
// the client library installs this header as monocle/point_query.h.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

namespace monocle {

// A pixel to measure: on the floor, or standing vertically above the floor pixel `foot_px`.
struct PixelQuery {
  double u = 0, v = 0;                           // pixels
  std::optional<std::array<double, 2>> foot_px;  // (u, v) of the point's foot on the floor
};

// Why a point was or was not measured; the wire's POINT_* constants carry the same values.
enum class PointStatus : uint8_t { kMeasured = 0, kInvalidPixel = 1, kNotMeasurable = 2 };

struct MeasuredPoint {
  using Status = PointStatus;  // the spelling MeasuredPoint::Status, kept for clients
  PointStatus status = PointStatus::kMeasured;
  std::array<double, 3> p_robot_m{};   // x, y, z in the robot frame, metres
  std::array<double, 9> covariance{};  // row-major 3x3 of (x, y, z), square metres
  std::array<double, 3> sigma_m{};     // 1-sigma of x, y, z: sqrt of the diagonal, metres
  std::string error;                   // why not measured
  bool ok() const { return status == PointStatus::kMeasured; }

  // Sets the covariance and the sigmas that follow from it.
  void SetCovariance(const std::array<double, 9>& row_major_m2) {
    covariance = row_major_m2;
    for (int i = 0; i < 3; ++i) sigma_m[i] = std::sqrt(std::max(0.0, covariance[4 * i]));
  }
};

}  // namespace monocle
