#include "service/pipeline/point_queries.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <thread>

namespace monocle {
namespace {

bool InsideImage(const CameraIntrinsics& k, double u, double v) {
  return std::isfinite(u) && std::isfinite(v) && u >= -0.5 && v >= -0.5 && u <= k.width_px - 0.5 &&
         v <= k.height_px - 0.5;
}

}  // namespace

MeasuredPoint ToMeasuredPoint(const FloorMeasurement& measurement) {
  MeasuredPoint point;
  point.p_robot_m = {measurement.p_robot_m.x(), measurement.p_robot_m.y(),
                     measurement.p_robot_m.z()};
  // Symmetric to the last bit: the wire carries one off-diagonal of each pair, and the
  // service's answer and the command line's own must print the same.
  std::array<double, 9> covariance;
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(covariance.data()) =
      0.5 * (measurement.covariance + measurement.covariance.transpose());
  point.SetCovariance(covariance);
  return point;
}

RequestAnswer AnswerPointRequest(const std::map<std::string, CameraCalibration>& cameras,
                                 const std::string& camera_id,
                                 const std::vector<PixelQuery>& points, double pixel_sigma_px) {
  RequestAnswer out;
  const auto it = cameras.find(camera_id);
  if (it == cameras.end()) {
    out.status = RequestStatus::kInvalidRequest;
    out.error = "unknown floor camera '" + camera_id + "'";
    return out;
  }
  if (!it->second.floor) {
    out.status = RequestStatus::kInvalidRequest;
    out.error = "camera '" + camera_id + "' has no floor calibration";
    return out;
  }
  if (points.empty()) {
    out.status = RequestStatus::kInvalidRequest;
    out.error = "the request has no points";
    return out;
  }
  if (points.size() > kMaxPointsPerRequest) {
    out.status = RequestStatus::kInvalidRequest;
    out.error = "too many points in one request (" + std::to_string(points.size()) + " > " +
                std::to_string(kMaxPointsPerRequest) + "): split it";
    return out;
  }
  if (!std::isfinite(pixel_sigma_px) || pixel_sigma_px < 0) {
    out.status = RequestStatus::kInvalidRequest;
    out.error = "pixel sigma must be a finite number >= 0";
    return out;
  }
  const auto& k = it->second.intrinsics;
  const FloorCalibration& floor = *it->second.floor;
  const MeasurementNoise noise =
      MeasurementNoiseOf(floor, it->second.intrinsics_covariance,
                         pixel_sigma_px > 0 ? pixel_sigma_px : kDefaultPixelSigmaPx);
  // Large requests are measured on every core: the geometry of 100 000 points takes tens of
  // milliseconds on one (bench/floor_bench), as long as carrying them over DDS.
  out.points.resize(points.size());
  auto measure_range = [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const auto& p = points[i];
      MeasuredPoint& a = out.points[i];
      if (!InsideImage(k, p.u, p.v) ||
          (p.foot_px && !InsideImage(k, (*p.foot_px)[0], (*p.foot_px)[1]))) {
        std::ostringstream os;
        os << "pixel outside the " << k.width_px << "x" << k.height_px << " image or not a number";
        a.status = PointStatus::kInvalidPixel;
        a.error = os.str();
        continue;
      }
      const auto m = p.foot_px
                         ? MeasureVerticalPoint(k, floor.pose, noise,
                                                {(*p.foot_px)[0], (*p.foot_px)[1]}, {p.u, p.v})
                         : MeasureFloorPoint(k, floor.pose, noise, {p.u, p.v});
      if (m) {
        a = ToMeasuredPoint(*m);
      } else {
        a.status = PointStatus::kNotMeasurable;
        a.error = m.error().message;
      }
    }
  };
  constexpr size_t kPointsPerThread = 20000;
  // Read once: hardware_concurrency() reads /sys on every call, which measured 13 us, more
  // than the geometry of a one-point request.
  static const size_t kCores = std::max(1u, std::thread::hardware_concurrency());
  const size_t threads = std::clamp<size_t>(points.size() / kPointsPerThread, 1, kCores);
  std::vector<std::thread> helpers;
  const size_t chunk = (points.size() + threads - 1) / threads;
  for (size_t t = 1; t < threads; ++t)
    helpers.emplace_back(measure_range, t * chunk, std::min(points.size(), (t + 1) * chunk));
  measure_range(0, std::min(points.size(), chunk));
  for (auto& h : helpers) h.join();
  return out;
}

}  // namespace monocle
