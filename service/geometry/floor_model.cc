#include "service/geometry/floor_model.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace monocle {
namespace {

// Rays within this of the horizon (denominator of eq. 5) would meet the floor more than
// ~1000 camera heights away: treated as above the horizon.
constexpr double kMinDescent = 1e-3;

std::string PixelText(const Eigen::Vector2d& px) {
  std::ostringstream os;
  os << px.x() << "," << px.y();
  return os.str();
}

// Value and derivatives of the paper's floor solution (eq. 5) w.r.t. the paper's
// normalized coordinates (x1, y1), h and theta.
struct FloorSolution {
  double x_w, y_w;
  // d(x_w, y_w) / d(x1, y1, h, theta)
  Eigen::Matrix<double, 2, 4> jacobian;
};

std::optional<FloorSolution> SolveFloor(double x1, double y1, double h, double theta) {
  const double s = std::sin(theta), c = std::cos(theta);
  const double descent = y1 * s - c;  // -(ray direction z in the robot frame)
  const double ray_norm = std::sqrt(x1 * x1 + y1 * y1 + 1);
  if (descent / ray_norm < kMinDescent) return std::nullopt;
  const double forward = s + y1 * c;
  FloorSolution out;
  out.y_w = h * forward / descent;
  const double z_c = out.y_w * s - h * c;
  out.x_w = x1 * z_c;
  const double dy_dy1 = -h / (descent * descent);
  const double dy_dh = forward / descent;
  const double dy_dtheta = -h * (1 + y1 * y1) / (descent * descent);
  out.jacobian << z_c, x1 * s * dy_dy1, x1 * (s * dy_dh - c),
      x1 * (s * dy_dtheta + out.y_w * c + h * s), 0, dy_dy1, dy_dh, dy_dtheta;
  return out;
}

Error AboveHorizon(const Eigen::Vector2d& px) {
  return MakeError(
      ErrorCode::kOutOfRange,
      "pixel " + PixelText(px) + " is at or above the horizon: its ray never meets the floor");
}

Error NotInvertible(const Eigen::Vector2d& px) {
  return MakeError(
      ErrorCode::kOutOfRange,
      "pixel " + PixelText(px) + " lies where the lens distortion model cannot be inverted");
}

}  // namespace

std::ostream& operator<<(std::ostream& os, const FloorPose& p) {
  return os << "FloorPose{h=" << p.height_m << " m, pitch=" << p.pitch_rad
            << " rad, yaw=" << p.yaw_rad << " rad, roll=" << p.roll_rad << " rad}";
}

std::ostream& operator<<(std::ostream& os, const FloorMeasurement& m) {
  return os << "FloorMeasurement{p=(" << m.p_robot_m.transpose() << ") m, sigma=("
            << m.Sigma().transpose() << ") m}";
}

Eigen::Matrix3d RotationCameraFromRobot(const FloorPose& pose) {
  const double s = std::sin(pose.pitch_rad), c = std::cos(pose.pitch_rad);
  Eigen::Matrix3d pitch;
  pitch << 1, 0, 0, 0, c, -s, 0, s, c;
  const double sr = std::sin(pose.roll_rad), cr = std::cos(pose.roll_rad);
  Eigen::Matrix3d roll;
  roll << cr, -sr, 0, sr, cr, 0, 0, 0, 1;
  return roll * pitch;
}

Eigen::Vector3d TranslationCameraFromRobot(const FloorPose& pose) {
  const double s = std::sin(pose.pitch_rad), c = std::cos(pose.pitch_rad);
  const double sr = std::sin(pose.roll_rad), cr = std::cos(pose.roll_rad);
  Eigen::Matrix3d roll;
  roll << cr, -sr, 0, sr, cr, 0, 0, 0, 1;
  return roll * Eigen::Vector3d(0, pose.height_m * s, -pose.height_m * c);
}

Eigen::Vector3d RobotToCamera(const FloorPose& pose, const Eigen::Vector3d& p_robot_m) {
  return RotationCameraFromRobot(pose) * p_robot_m + TranslationCameraFromRobot(pose);
}

std::optional<Eigen::Vector2d> ProjectRobotPoint(const CameraIntrinsics& k, const FloorPose& pose,
                                                 const Eigen::Vector3d& p_robot_m) {
  const Eigen::Vector3d p_c = RobotToCamera(pose, p_robot_m);
  if (p_c.z() <= 0) return std::nullopt;
  return ProjectToPixel(k, p_c);
}

Eigen::Vector2d RemoveRoll(double roll_rad, const Eigen::Vector2d& n) {
  const double s = std::sin(roll_rad), c = std::cos(roll_rad);
  return {c * n.x() + s * n.y(), -s * n.x() + c * n.y()};
}

Result<Eigen::Vector3d> FloorPointFromPixel(const CameraIntrinsics& k, const FloorPose& pose,
                                            const Eigen::Vector2d& floor_px) {
  const auto n = PixelToNormalized(k, floor_px);
  if (!n) return NotInvertible(floor_px);
  const Eigen::Vector2d p = RemoveRoll(pose.roll_rad, *n);
  const auto sol = SolveFloor(p.x(), p.y(), pose.height_m, pose.pitch_rad);
  if (!sol) return AboveHorizon(floor_px);
  return Eigen::Vector3d(sol->x_w, sol->y_w, 0);
}

namespace {

using IntrinsicsJacobian2 = Eigen::Matrix<double, 2, kNumIntrinsicParams>;

// Paper coordinates of a pixel and their Jacobians w.r.t. (u, v, roll) and the intrinsics.
struct PaperCoordinates {
  Eigen::Vector2d xy;
  Eigen::Matrix<double, 2, 3> jacobian;                                   // d(x1, y1)/d(u, v, roll)
  IntrinsicsJacobian2 intrinsics_jacobian = IntrinsicsJacobian2::Zero();  // d(x1, y1)/d(k)
};

bool HasIntrinsicsUncertainty(const MeasurementNoise& noise) {
  return !noise.intrinsics_covariance.isZero();
}

std::optional<PaperCoordinates> ToPaperCoordinates(const CameraIntrinsics& k, double roll,
                                                   const Eigen::Vector2d& px,
                                                   bool with_intrinsics_jacobian) {
  Eigen::Matrix2d dn_dpx;
  const auto n = PixelToNormalized(k, px, &dn_dpx);
  if (!n) return std::nullopt;
  const double s = std::sin(roll), c = std::cos(roll);
  Eigen::Matrix2d r;
  r << c, s, -s, c;
  PaperCoordinates out;
  out.xy = r * *n;
  out.jacobian.leftCols<2>() = r * dn_dpx;
  out.jacobian.col(2) << out.xy.y(), -out.xy.x();
  if (with_intrinsics_jacobian)
    out.intrinsics_jacobian = r * NormalizedJacobianWrtIntrinsics(k, *n, dn_dpx);
  return out;
}

// Covariance of a measurement with Jacobians w.r.t. the pose, the intrinsics and the pixels.
template <int Rows, int Pixels>
Eigen::Matrix<double, Rows, Rows> Propagate(
    const MeasurementNoise& noise, const Eigen::Matrix<double, Rows, 4>& j_pose,
    const Eigen::Matrix<double, Rows, kNumIntrinsicParams>& j_intrinsics,
    const Eigen::Matrix<double, Rows, Pixels>& j_pixel) {
  // lazyProduct: Eigen sends fixed-size products this large (2x9 by 9x9) through its blocked
  // GEMM, whose packing cost more than the arithmetic (7 % of a 100 000-point request's CPU
  // in perf); coefficient-wise products of these small sizes are cheaper.
  const Eigen::Matrix<double, Rows, kNumIntrinsicParams> j_pose_c =
      j_pose.lazyProduct(noise.pose_intrinsics_covariance);
  const Eigen::Matrix<double, Rows, kNumIntrinsicParams> j_k_k =
      j_intrinsics.lazyProduct(noise.intrinsics_covariance);
  const Eigen::Matrix<double, Rows, 4> j_pose_p = j_pose.lazyProduct(noise.pose_covariance);
  const Eigen::Matrix<double, Rows, Rows> cross = j_pose_c.lazyProduct(j_intrinsics.transpose());
  return j_pose_p.lazyProduct(j_pose.transpose()) + cross + cross.transpose() +
         j_k_k.lazyProduct(j_intrinsics.transpose()) +
         noise.pixel_sigma_px * noise.pixel_sigma_px * j_pixel.lazyProduct(j_pixel.transpose());
}

}  // namespace

Result<FloorMeasurement> MeasureFloorPoint(const CameraIntrinsics& k, const FloorPose& pose,
                                           const MeasurementNoise& noise,
                                           const Eigen::Vector2d& floor_px) {
  const auto pc = ToPaperCoordinates(k, pose.roll_rad, floor_px, HasIntrinsicsUncertainty(noise));
  if (!pc) return NotInvertible(floor_px);
  const auto sol = SolveFloor(pc->xy.x(), pc->xy.y(), pose.height_m, pose.pitch_rad);
  if (!sol) return AboveHorizon(floor_px);
  // Jacobian of (x_w, y_w) w.r.t. the pose (h, theta, alpha, roll) and the pixel (u, v).
  const Eigen::Matrix2d d_dxy = sol->jacobian.leftCols<2>();
  Eigen::Matrix<double, 2, 4> j_pose;
  j_pose.col(0) = sol->jacobian.col(2);
  j_pose.col(1) = sol->jacobian.col(3);
  j_pose.col(2).setZero();
  j_pose.col(3) = d_dxy * pc->jacobian.col(2);
  const Eigen::Matrix2d j_pixel = d_dxy * pc->jacobian.leftCols<2>();
  const Eigen::Matrix<double, 2, kNumIntrinsicParams> j_intrinsics =
      d_dxy * pc->intrinsics_jacobian;
  FloorMeasurement m;
  m.p_robot_m << sol->x_w, sol->y_w, 0;
  m.covariance.topLeftCorner<2, 2>() = Propagate<2, 2>(noise, j_pose, j_intrinsics, j_pixel);
  return m;
}

Result<FloorMeasurement> MeasureVerticalPoint(const CameraIntrinsics& k, const FloorPose& pose,
                                              const MeasurementNoise& noise,
                                              const Eigen::Vector2d& foot_px,
                                              const Eigen::Vector2d& top_px) {
  const bool with_k = HasIntrinsicsUncertainty(noise);
  const auto pf = ToPaperCoordinates(k, pose.roll_rad, foot_px, with_k);
  if (!pf) return NotInvertible(foot_px);
  const auto pt = ToPaperCoordinates(k, pose.roll_rad, top_px, with_k);
  if (!pt) return NotInvertible(top_px);
  const double h = pose.height_m, theta = pose.pitch_rad;
  const auto sol = SolveFloor(pf->xy.x(), pf->xy.y(), h, theta);
  if (!sol) return AboveHorizon(foot_px);
  const double s = std::sin(theta), c = std::cos(theta);
  const double y1t = pt->xy.y();
  const double descent_t = y1t * s - c;
  const double forward_t = s + y1t * c;
  // Eq. (7) needs the top pixel's ray to move forward (towards Y_w) as well; a ray in the
  // X_w-Z_w plane cannot tell heights along the vertical line.
  if (std::abs(forward_t) / std::sqrt(1 + y1t * y1t) < 1e-6) {
    return MakeError(ErrorCode::kDegenerate,
                     "pixel " + PixelText(top_px) +
                         " looks straight down the vertical line: its height is undefined");
  }
  const double y_w = sol->y_w;
  // Eq. (7), rearranged: z_w = h - descent_t * y_w / forward_t.
  const double z_w = h - descent_t * y_w / forward_t;
  if (!std::isfinite(z_w)) return AboveHorizon(top_px);

  // Jacobian of z_w w.r.t. y_w, y1t, h (direct), theta (direct).
  const double dz_dyw = -descent_t / forward_t;
  const double dz_dy1t = -y_w / (forward_t * forward_t);
  const double dz_dtheta_direct = -y_w * (1 + y1t * y1t) / (forward_t * forward_t);
  // Full Jacobians w.r.t. pose (h, theta, alpha, roll) and pixels (uf, vf, ut, vt).
  const Eigen::Matrix2d d_dxy = sol->jacobian.leftCols<2>();
  Eigen::Matrix<double, 3, 4> j_pose = Eigen::Matrix<double, 3, 4>::Zero();
  Eigen::Matrix<double, 3, 4> j_pixel = Eigen::Matrix<double, 3, 4>::Zero();
  j_pose.block<2, 1>(0, 0) = sol->jacobian.col(2);
  j_pose.block<2, 1>(0, 1) = sol->jacobian.col(3);
  j_pose.block<2, 1>(0, 3) = d_dxy * pf->jacobian.col(2);
  j_pixel.block<2, 2>(0, 0) = d_dxy * pf->jacobian.leftCols<2>();
  j_pose(2, 0) = 1 + dz_dyw * sol->jacobian(1, 2);
  j_pose(2, 1) = dz_dtheta_direct + dz_dyw * sol->jacobian(1, 3);
  j_pose(2, 3) = dz_dyw * j_pose(1, 3) + dz_dy1t * pt->jacobian(1, 2);
  j_pixel.block<1, 2>(2, 0) = dz_dyw * j_pixel.block<1, 2>(1, 0);
  j_pixel.block<1, 2>(2, 2) = dz_dy1t * pt->jacobian.block<1, 2>(1, 0);

  Eigen::Matrix<double, 3, kNumIntrinsicParams> j_intrinsics;
  j_intrinsics.topRows<2>() = d_dxy * pf->intrinsics_jacobian;
  j_intrinsics.row(2) = dz_dyw * j_intrinsics.row(1) + dz_dy1t * pt->intrinsics_jacobian.row(1);

  FloorMeasurement m;
  m.p_robot_m << sol->x_w, y_w, z_w;
  m.covariance = Propagate<3, 4>(noise, j_pose, j_intrinsics, j_pixel);
  // A top below its foot is not a point above the floor: the two pixels are swapped, or the
  // foot is not under the top. Within the noise (3 sigma) a height just under zero is a
  // point on the floor and stands.
  const double sigma_z = std::sqrt(std::max(0.0, m.covariance(2, 2)));
  if (z_w < -kVerticalPointSigmas * sigma_z) {
    std::ostringstream os;
    os.precision(3);
    os << "pixel " << PixelText(top_px) << " is below its foot " << PixelText(foot_px)
       << " (height " << z_w << " m, 1 sigma " << sigma_z
       << " m): give the point above the floor first and its foot on the floor after @";
    return MakeError(ErrorCode::kOutOfRange, os.str());
  }
  return m;
}

}  // namespace monocle
