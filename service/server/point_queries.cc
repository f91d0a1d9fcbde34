#include "service/server/point_queries.h"

#include <cmath>
#include <sstream>

namespace monocle {
namespace {

bool InsideImage(const CameraIntrinsics& k, double u, double v) {
  return std::isfinite(u) && std::isfinite(v) && u >= -0.5 && v >= -0.5 && u <= k.width_px - 0.5 &&
         v <= k.height_px - 0.5;
}

}  // namespace

RequestAnswer AnswerPointRequest(const std::map<std::string, CameraCalibration>& cameras,
                                 const std::string& camera_id, const std::vector<PixelPair>& points,
                                 double pixel_sigma_px) {
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
  out.points.reserve(points.size());
  for (const auto& p : points) {
    PointAnswer a;
    if (!InsideImage(k, p.u, p.v) || (p.paired && !InsideImage(k, p.floor_u, p.floor_v))) {
      std::ostringstream os;
      os << "pixel outside the " << k.width_px << "x" << k.height_px << " image or not a number";
      a.status = PointStatus::kInvalidPixel;
      a.error = os.str();
    } else {
      const auto m =
          p.paired ? MeasureVerticalPoint(k, floor.pose, noise, {p.floor_u, p.floor_v}, {p.u, p.v})
                   : MeasureFloorPoint(k, floor.pose, noise, {p.u, p.v});
      if (m) {
        a.measurement = *m;
      } else {
        a.status = PointStatus::kNotMeasurable;
        a.error = m.error().message;
      }
    }
    out.points.push_back(std::move(a));
  }
  return out;
}

}  // namespace monocle
