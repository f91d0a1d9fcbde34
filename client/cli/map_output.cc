#include "client/cli/map_output.h"

#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>

namespace monocle::cli {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

proto::MapPoseOutput ToMapPoseOutput(const MapPoseCandidate& c) {
  proto::MapPoseOutput out;
  out.set_corner(c.corner_id);
  out.set_room(c.room_id);
  out.set_x(c.base.x_m);
  out.set_y(c.base.y_m);
  out.set_heading_deg(c.base.heading_rad * kDegPerRad);
  out.mutable_sigma()->set_x(std::sqrt(c.base_covariance(0, 0)));
  out.mutable_sigma()->set_y(std::sqrt(c.base_covariance(1, 1)));
  out.mutable_sigma()->set_heading_deg(std::sqrt(c.base_covariance(2, 2)) * kDegPerRad);
  for (int i = 0; i < 3; ++i) out.add_camera_position(c.map_camera.translation[i]);
  const Eigen::Quaterniond& q = c.map_camera.rotation;
  for (double v : {q.w(), q.x(), q.y(), q.z()}) out.add_camera_quaternion(v);
  return out;
}

std::string Reason(const MapLocation& where) {
  if (where.consistent.empty()) return where.why_none;
  std::ostringstream os;
  os << where.consistent.size() << (where.consistent.size() == 1 ? " corner fits" : " corners fit")
     << (where.prior_contradicted ? ", none within the prior's reach" : "")
     << ": give the robot's pose with --prior X,Y,HEADING_DEG (or --track from a known start)";
  return os.str();
}

}  // namespace

std::string MapStatus(const MapLocation& where) {
  if (where.decided()) return "located";
  if (where.consistent.empty()) return "no corner fits";
  if (where.prior_contradicted) return "contradicts prior";
  return "ambiguous";
}

proto::MapLocationOutput ToMapLocationOutput(const MapLocation& where) {
  proto::MapLocationOutput out;
  out.set_status(MapStatus(where));
  out.set_level_error_deg(where.level_error_rad * kDegPerRad);
  out.set_suspect(where.suspect);
  if (where.suspect) out.set_suspect_reason(where.suspect_reason);
  if (where.decided()) {
    *out.mutable_pose() = ToMapPoseOutput(where.consistent.front());
    return out;
  }
  for (const auto& c : where.consistent) *out.add_candidates() = ToMapPoseOutput(c);
  out.set_reason(Reason(where));
  return out;
}

std::string MapLocationLine(const MapLocation& where) {
  std::ostringstream os;
  os << std::fixed;
  if (where.decided()) {
    const MapPoseCandidate& c = where.consistent.front();
    os << "map: " << c.corner_id << " (room " << c.room_id << ")  base x=" << std::setprecision(4)
       << c.base.x_m << " y=" << c.base.y_m << " m heading=" << std::setprecision(2)
       << c.base.heading_rad * kDegPerRad << " deg  (1σ " << std::setprecision(4)
       << std::sqrt(c.base_covariance(0, 0)) << " " << std::sqrt(c.base_covariance(1, 1)) << " m, "
       << std::setprecision(2) << std::sqrt(c.base_covariance(2, 2)) * kDegPerRad << " deg)";
    if (where.suspect) os << "  SUSPECT: " << where.suspect_reason;
    return os.str();
  }
  os << "map: " << MapStatus(where).c_str() << ": " << Reason(where);
  for (size_t i = 0; i < where.consistent.size(); ++i) {
    const MapPoseCandidate& c = where.consistent[i];
    os << (i == 0 ? "; candidates " : ", ") << c.corner_id << " (" << std::setprecision(2)
       << c.base.x_m << ", " << c.base.y_m << " m, " << std::setprecision(0)
       << c.base.heading_rad * kDegPerRad << " deg)";
  }
  return os.str();
}

}  // namespace monocle::cli
