#include "service/geometry/floor_calibration.h"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <string>

#include "service/geometry/levenberg_marquardt.h"

namespace monocle {
namespace {

constexpr int kNumParams = 6;  // h, pitch, roll, yaw, t_x, t_y

FloorPose PoseFromParams(const Eigen::VectorXd& q) { return FloorPose{q[0], q[1], q[3], q[2]}; }

// Reprojection residuals (pixels) of every corner under parameters q.
bool BoardResiduals(const CameraIntrinsics& k, const BoardObservation& board,
                    const Eigen::VectorXd& q, Eigen::VectorXd* r) {
  const FloorPose pose = PoseFromParams(q);
  const Eigen::Matrix3d rot = RotationCameraFromRobot(pose);
  const Eigen::Vector3d trans = TranslationCameraFromRobot(pose);
  const Eigen::Vector2d origin(q[4], q[5]);
  for (int j = 0; j < board.rows; ++j) {
    for (int i = 0; i < board.cols; ++i) {
      const Eigen::Vector3d p_c =
          rot * BoardToRobot(pose.yaw_rad, origin, board.BoardPoint(i, j)) + trans;
      if (p_c.z() <= 1e-9) return false;
      const int idx = j * board.cols + i;
      r->segment<2>(2 * idx) = ProjectToPixel(k, p_c) - board.pixels[idx];
    }
  }
  return true;
}

double RmsPx(const Eigen::VectorXd& residuals) {
  return std::sqrt(residuals.squaredNorm() / (residuals.size() / 2));
}

// Normalized (undistorted) coordinates of every corner.
Result<std::vector<Eigen::Vector2d>> NormalizedCorners(const CameraIntrinsics& k,
                                                       const BoardObservation& board) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(board.pixels.size());
  for (const auto& px : board.pixels) {
    const auto n = PixelToNormalized(k, px);
    if (!n) {
      return MakeError(ErrorCode::kOutOfRange,
                       "a board corner lies where the lens distortion cannot be inverted");
    }
    out.push_back(*n);
  }
  return out;
}

// Plane-to-image homography by normalised DLT, then decomposed into the floor parameters.
Result<Eigen::VectorXd> InitialGuessFromHomography(const BoardObservation& board,
                                                   const std::vector<Eigen::Vector2d>& normalized) {
  const int n = static_cast<int>(normalized.size());
  // Hartley normalisation of both point sets.
  auto similarity = [](const std::vector<Eigen::Vector2d>& pts) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : pts) mean += p;
    mean /= pts.size();
    double spread = 0;
    for (const auto& p : pts) spread += (p - mean).norm();
    spread /= pts.size();
    const double s = std::sqrt(2.0) / std::max(spread, 1e-300);
    Eigen::Matrix3d t;
    t << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;
    return t;
  };
  std::vector<Eigen::Vector2d> board_pts;
  for (int j = 0; j < board.rows; ++j)
    for (int i = 0; i < board.cols; ++i) board_pts.push_back(board.BoardPoint(i, j));
  const Eigen::Matrix3d tb = similarity(board_pts), ti = similarity(normalized);
  Eigen::MatrixXd a(2 * n, 9);
  for (int idx = 0; idx < n; ++idx) {
    const Eigen::Vector3d p = tb * board_pts[idx].homogeneous();
    const Eigen::Vector3d q = ti * normalized[idx].homogeneous();
    a.row(2 * idx) << 0, 0, 0, -p.transpose(), q.y() * p.transpose();
    a.row(2 * idx + 1) << p.transpose(), 0, 0, 0, -q.x() * p.transpose();
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
  const Eigen::VectorXd hv = svd.matrixV().col(8);
  Eigen::Matrix3d h;
  h << hv[0], hv[1], hv[2], hv[3], hv[4], hv[5], hv[6], hv[7], hv[8];
  h = ti.inverse() * h * tb;
  // H ~ [r1 r2 t] with the board's points in front of the camera (t_z > 0).
  double scale = 1.0 / h.col(0).norm();
  if (h(2, 2) * scale < 0) scale = -scale;
  Eigen::Matrix3d r;
  r.col(0) = h.col(0) * scale;
  r.col(1) = h.col(1) * scale;
  r.col(2) = r.col(0).cross(r.col(1));
  const Eigen::Vector3d t = h.col(2) * scale;
  Eigen::JacobiSVD<Eigen::Matrix3d> rsvd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  r = rsvd.matrixU() * rsvd.matrixV().transpose();
  if (r.determinant() < 0) return MakeError(ErrorCode::kDegenerate, "the board pose is degenerate");

  // R_cb = R_roll * R_pitch * R_yaw, where the board's z axis is the floor normal.
  const Eigen::Vector3d normal = r.col(2);
  const double pitch = std::acos(std::clamp(normal.z(), -1.0, 1.0));
  const double roll = std::atan2(normal.x(), -normal.y());
  FloorPose pose{1.0, pitch, 0.0, roll};
  const Eigen::Matrix3d r_cw = RotationCameraFromRobot(pose);
  const Eigen::Matrix3d r_wb = r_cw.transpose() * r;
  // Eq. (10): board x axis in the robot frame is (cos a, -sin a).
  const double yaw = std::atan2(-r_wb(1, 0), r_wb(0, 0));
  const Eigen::Vector3d t_w = r_cw.transpose() * t;  // = (t_x, t_y, -h)
  if (!(t_w.z() < 0)) {
    return MakeError(ErrorCode::kDegenerate,
                     "the board is not below the camera: the image cannot show a floor board");
  }
  Eigen::VectorXd q(kNumParams);
  q << -t_w.z(), pitch, roll, yaw, t_w.x(), t_w.y();
  return q;
}

using IntrinsicsSensitivity = Eigen::Matrix<double, Eigen::Dynamic, kNumIntrinsicParams>;

// d(residuals)/d(intrinsics) at parameters q: each corner's pixel moves with the intrinsics
// while its ray stays put.
IntrinsicsSensitivity ResidualJacobianWrtIntrinsics(const CameraIntrinsics& k,
                                                    const BoardObservation& board,
                                                    const Eigen::VectorXd& q) {
  const FloorPose pose = PoseFromParams(q);
  const Eigen::Matrix3d rot = RotationCameraFromRobot(pose);
  const Eigen::Vector3d trans = TranslationCameraFromRobot(pose);
  const Eigen::Vector2d origin(q[4], q[5]);
  IntrinsicsSensitivity j(2 * board.pixels.size(), kNumIntrinsicParams);
  for (int jj = 0; jj < board.rows; ++jj) {
    for (int i = 0; i < board.cols; ++i) {
      const Eigen::Vector3d p_c =
          rot * BoardToRobot(pose.yaw_rad, origin, board.BoardPoint(i, jj)) + trans;
      j.middleRows<2>(2 * (jj * board.cols + i)) =
          PixelJacobianWrtIntrinsics(k, p_c.head<2>() / p_c.z());
    }
  }
  return j;
}

// Adds the intrinsics' share to the covariance of (h, pitch, yaw, roll) given the fit's
// sensitivity `d_pose_d_k` (4 x 9) to them, and sets the cross-covariance.
void AddIntrinsicsUncertainty(const Eigen::Matrix<double, 4, kNumIntrinsicParams>& d_pose_d_k,
                              const IntrinsicsCovariance& k_covariance, FloorCalibration* out) {
  out->corner_covariance = out->covariance;
  out->intrinsics_cross_covariance = d_pose_d_k * k_covariance;
  out->covariance += out->intrinsics_cross_covariance * d_pose_d_k.transpose();
}

// The full method's result at parameters q, from the fit's Jacobian `jq` (residuals x 6) and
// the corners' share of the covariance `cov6` (6 x 6, order of q).
void FillFullCalibration(const CameraIntrinsics& k, const BoardObservation& board,
                         const Eigen::VectorXd& q, const Eigen::MatrixXd& jq,
                         const Eigen::MatrixXd& cov6, const IntrinsicsCovariance& k_covariance,
                         FloorCalibration* out) {
  out->method = FloorCalibrationMethod::kFull;
  out->pose = PoseFromParams(q);
  out->board_origin_robot_m = q.tail<2>();
  // Parameter order in q: h, pitch, roll, yaw; output order: h, pitch, yaw, roll.
  const int order[4] = {0, 1, 3, 2};
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) out->covariance(a, b) = cov6(order[a], order[b]);
  // Sensitivity of the optimum to the intrinsics (6 x 9), then in output order.
  const Eigen::MatrixXd d_q_d_k =
      -(jq.transpose() * jq)
           .ldlt()
           .solve(jq.transpose() * ResidualJacobianWrtIntrinsics(k, board, q));
  Eigen::Matrix<double, 4, kNumIntrinsicParams> d_pose_d_k;
  for (int a = 0; a < 4; ++a) d_pose_d_k.row(a) = d_q_d_k.row(order[a]);
  AddIntrinsicsUncertainty(d_pose_d_k, k_covariance, out);
}

Result<FloorCalibration> CalibrateFull(const CameraIntrinsics& k, const BoardObservation& board,
                                       const std::vector<Eigen::Vector2d>& normalized,
                                       const IntrinsicsCovariance& k_covariance) {
  auto init = InitialGuessFromHomography(board, normalized);
  if (!init) return init.error();
  Eigen::VectorXd q = *init;
  const int m = 2 * static_cast<int>(board.pixels.size());
  const auto summary = MinimizeLevenbergMarquardt(
      [&](const Eigen::VectorXd& x, Eigen::VectorXd* r) { return BoardResiduals(k, board, x, r); },
      m, &q);
  if (summary.residuals.size() != m) {
    return MakeError(ErrorCode::kDegenerate, "the board pose could not be fitted");
  }
  // A robot's floor camera is mounted roughly upright; a board that needs the camera
  // turned past 45 degrees about its axis means an upside-down mount or a wrong image.
  if (std::abs(q[2]) > std::numbers::pi / 4) {
    return MakeError(
        ErrorCode::kDegenerate,
        "the board implies a camera roll of " + std::to_string(q[2] * 180 / std::numbers::pi) +
            " degrees (beyond +-45): is the camera mounted upside down? Rotate its images "
            "by 180 degrees first");
  }
  const Eigen::MatrixXd cov6 = CovarianceFromJacobian(summary.jacobian, summary.residuals);
  if (cov6.size() == 0) {
    return MakeError(ErrorCode::kDegenerate,
                     "the board pose is degenerate: the corners do not constrain height and pitch");
  }
  FloorCalibration out;
  out.rms_px = RmsPx(summary.residuals);
  FillFullCalibration(k, board, q, summary.jacobian, cov6, k_covariance, &out);
  return out;
}

struct PaperEstimate {
  double height, pitch, yaw;
  double condition;  // of eq. (13)'s least-squares system, columns scaled to unit length
};

// Xu et al. section 3: eq. (13) over every pair of corners in a column,
// solved by least squares for (sin 2theta, cos 2theta, h / cos alpha); then eq. (15)
// over every pair of corners in a row for tan alpha. The paper's printed
// (15) is garbled in our copy; this is (14) solved for tan alpha.
std::optional<PaperEstimate> EstimatePaper(const BoardObservation& board,
                                           const std::vector<Eigen::Vector2d>& normalized) {
  const double s = board.square_m;
  std::vector<Eigen::RowVector3d> rows;
  std::vector<double> rhs;
  // Every pair of corners in a column, not only neighbours: eq. (13) holds for any pair,
  // and the longer baselines condition the solve far better.
  for (int i = 0; i < board.cols; ++i) {
    for (int j = 1; j < board.rows; ++j) {
      for (int j_prev = 0; j_prev < j; ++j_prev) {
        const double dy_p = (j - j_prev) * s;
        const double y = normalized[j * board.cols + i].y();
        const double y_prev = normalized[j_prev * board.cols + i].y();
        rows.emplace_back(dy_p * (y + y_prev), -dy_p * (1 - y * y_prev), -2 * (y - y_prev));
        rhs.push_back(dy_p * (1 + y * y_prev));
      }
    }
  }
  if (rows.size() < 3) return std::nullopt;
  Eigen::MatrixXd a(rows.size(), 3);
  Eigen::VectorXd b(rows.size());
  for (size_t r = 0; r < rows.size(); ++r) {
    a.row(r) = rows[r];
    b[r] = rhs[r];
  }
  const Eigen::Vector3d sol = a.colPivHouseholderQr().solve(b);
  // Scaled so that the number reflects the geometry, not the units of the unknowns.
  const Eigen::MatrixXd a_scaled = a * a.colwise().norm().cwiseInverse().asDiagonal();
  const Eigen::Vector3d singular = Eigen::JacobiSVD<Eigen::MatrixXd>(a_scaled).singularValues();
  const double condition = singular[0] / std::max(singular[2], 1e-300);
  if (!sol.allFinite()) return std::nullopt;
  double pitch = 0.5 * std::atan2(sol[0], sol[1]);
  if (pitch < 0) pitch += std::numbers::pi;  // theta in [0, pi)
  const double h_over_cos_alpha = sol[2];
  const double s2 = std::sin(2 * pitch), c2 = std::cos(2 * pitch);
  // Eq. (14): tan(alpha) * dx_p * [-(y + y') sin2t + (1 - y y') cos2t + (1 + y y')]
  //           = 2 (y - y') h / cos(alpha)
  double num = 0, den = 0;
  for (int j = 0; j < board.rows; ++j) {
    for (int i = 1; i < board.cols; ++i) {
      for (int i_prev = 0; i_prev < i; ++i_prev) {
        const double dx_p = (i - i_prev) * s;
        const double y = normalized[j * board.cols + i].y();
        const double y_prev = normalized[j * board.cols + i_prev].y();
        const double coef = dx_p * (-(y + y_prev) * s2 + (1 - y * y_prev) * c2 + (1 + y * y_prev));
        const double target = 2 * (y - y_prev) * h_over_cos_alpha;
        num += coef * target;
        den += coef * coef;
      }
    }
  }
  if (!(den > 0)) return std::nullopt;
  const double yaw = std::atan(num / den);
  return PaperEstimate{h_over_cos_alpha * std::cos(yaw), pitch, yaw, condition};
}

Result<FloorCalibration> CalibratePaper(const CameraIntrinsics& k, const BoardObservation& board,
                                        const std::vector<Eigen::Vector2d>& normalized,
                                        const IntrinsicsCovariance& k_covariance) {
  const auto estimate = EstimatePaper(board, normalized);
  if (!estimate || !(estimate->height > 0)) {
    return MakeError(
        ErrorCode::kDegenerate,
        "the paper's linear calibration (eq. 13) has no valid solution for this board");
  }
  FloorCalibration out;
  out.method = FloorCalibrationMethod::kPaper;
  out.pose = FloorPose{estimate->height, estimate->pitch, estimate->yaw, 0.0};
  out.condition_number = estimate->condition;

  // The paper does not estimate the board's position; fit it (t_x, t_y only) so that a
  // reprojection error can be reported on the same footing as the full method.
  Eigen::VectorXd full(kNumParams);
  full << out.pose.height_m, out.pose.pitch_rad, 0.0, out.pose.yaw_rad, 0.0, 0.0;
  {
    const auto p0 = FloorPointFromPixel(k, out.pose, board.pixels[0]);
    if (p0) full.tail<2>() = p0->head<2>();
  }
  Eigen::VectorXd t = full.tail<2>();
  const int m = 2 * static_cast<int>(board.pixels.size());
  const auto summary = MinimizeLevenbergMarquardt(
      [&](const Eigen::VectorXd& x, Eigen::VectorXd* r) {
        Eigen::VectorXd q = full;
        q.tail<2>() = x;
        return BoardResiduals(k, board, q, r);
      },
      m, &t);
  out.board_origin_robot_m = t;
  out.rms_px = summary.residuals.size() == m ? RmsPx(summary.residuals) : 0.0;

  // First-order propagation of corner noise (estimated from the residual) through the
  // linear estimator, by central differences over every corner coordinate.
  const double sigma_px = out.rms_px / std::sqrt(2.0);
  Eigen::Matrix<double, 3, Eigen::Dynamic> jac(3, m);
  std::vector<Eigen::Vector2d> perturbed = normalized;
  const double step_px = 1e-3;
  for (int c = 0; c < m; ++c) {
    const int idx = c / 2, axis = c % 2;
    const double step_n = step_px / (axis == 0 ? k.fx : k.fy);
    perturbed[idx][axis] = normalized[idx][axis] + step_n;
    const auto plus = EstimatePaper(board, perturbed);
    perturbed[idx][axis] = normalized[idx][axis] - step_n;
    const auto minus = EstimatePaper(board, perturbed);
    perturbed[idx][axis] = normalized[idx][axis];
    if (!plus || !minus) {
      jac.col(c).setZero();
      continue;
    }
    jac.col(c) << plus->height - minus->height, plus->pitch - minus->pitch, plus->yaw - minus->yaw;
    jac.col(c) /= 2 * step_px;
  }
  const Eigen::Matrix3d cov3 = sigma_px * sigma_px * jac * jac.transpose();
  out.covariance.topLeftCorner<3, 3>() = cov3;  // roll is fixed at 0: no variance

  // Sensitivity to the intrinsics by central differences: the corners' rays move with them.
  Eigen::Matrix<double, 4, kNumIntrinsicParams> d_pose_d_k =
      Eigen::Matrix<double, 4, kNumIntrinsicParams>::Zero();
  if (!k_covariance.isZero()) {
    for (int p = 0; p < kNumIntrinsicParams; ++p) {
      const double step = std::sqrt(std::max(k_covariance(p, p), 0.0)) * 1e-3;
      if (!(step > 0)) continue;
      Eigen::Matrix<double, kNumIntrinsicParams, 1> delta =
          Eigen::Matrix<double, kNumIntrinsicParams, 1>::Zero();
      delta[p] = step;
      const auto n_plus = NormalizedCorners(PerturbIntrinsics(k, delta), board);
      const auto n_minus = NormalizedCorners(PerturbIntrinsics(k, -delta), board);
      if (!n_plus || !n_minus) continue;
      const auto plus = EstimatePaper(board, *n_plus);
      const auto minus = EstimatePaper(board, *n_minus);
      if (!plus || !minus) continue;
      d_pose_d_k.col(p).head<3>() << plus->height - minus->height, plus->pitch - minus->pitch,
          plus->yaw - minus->yaw;
      d_pose_d_k.col(p) /= 2 * step;
    }
  }
  AddIntrinsicsUncertainty(d_pose_d_k, k_covariance, &out);
  return out;
}

}  // namespace

const char* ToString(FloorCalibrationMethod method) {
  return method == FloorCalibrationMethod::kFull ? "full" : "paper";
}

std::ostream& operator<<(std::ostream& os, const FloorCalibration& c) {
  return os << "FloorCalibration{" << ToString(c.method) << " " << c.pose << " sigma=("
            << c.Sigma().transpose() << ") rms=" << c.rms_px << " px}";
}

Eigen::Vector3d BoardToRobot(double yaw_rad, const Eigen::Vector2d& origin,
                             const Eigen::Vector2d& p) {
  const double s = std::sin(yaw_rad), c = std::cos(yaw_rad);
  return {p.x() * c + p.y() * s + origin.x(), -p.x() * s + p.y() * c + origin.y(), 0.0};
}

Result<BoardObservation> ProjectBoard(const CameraIntrinsics& k, const FloorPose& pose,
                                      const Eigen::Vector2d& origin, int cols, int rows,
                                      double square_m) {
  BoardObservation board{cols, rows, square_m, {}};
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < cols; ++i) {
      const auto px =
          ProjectRobotPoint(k, pose, BoardToRobot(pose.yaw_rad, origin, board.BoardPoint(i, j)));
      if (!px) return MakeError(ErrorCode::kOutOfRange, "a board corner is behind the camera");
      board.pixels.push_back(*px);
    }
  }
  return board;
}

Result<FloorCalibration> CalibrateFloor(const CameraIntrinsics& k, const BoardObservation& board,
                                        FloorCalibrationMethod method,
                                        const IntrinsicsCovariance& k_covariance) {
  assert(board.pixels.size() == static_cast<size_t>(board.cols * board.rows));
  if (board.cols < 2 || board.rows < 2) {
    return MakeError(ErrorCode::kInvalidArgument, "the board needs at least 2x2 inner corners");
  }
  if (!(board.square_m > 0)) {
    return MakeError(ErrorCode::kInvalidArgument, "the board's square size must be positive");
  }
  auto normalized = NormalizedCorners(k, board);
  if (!normalized) return normalized.error();
  return method == FloorCalibrationMethod::kFull
             ? CalibrateFull(k, board, *normalized, k_covariance)
             : CalibratePaper(k, board, *normalized, k_covariance);
}

Result<FloorCalibration> PredictFloorCalibration(const CameraIntrinsics& k, const FloorPose& pose,
                                                 const Eigen::Vector2d& board_origin_robot_m,
                                                 int cols, int rows, double square_m,
                                                 double corner_sigma_px,
                                                 const IntrinsicsCovariance& k_covariance) {
  const auto board = ProjectBoard(k, pose, board_origin_robot_m, cols, rows, square_m);
  if (!board) return board.error();
  Eigen::VectorXd q(kNumParams);
  q << pose.height_m, pose.pitch_rad, pose.roll_rad, pose.yaw_rad, board_origin_robot_m.x(),
      board_origin_robot_m.y();
  const int m = 2 * static_cast<int>(board->pixels.size());
  // The fit's Jacobian at the truth, by the same central differences the solver uses.
  Eigen::MatrixXd jq;
  if (!NumericJacobian([&](const Eigen::VectorXd& x,
                           Eigen::VectorXd* r) { return BoardResiduals(k, *board, x, r); },
                       q, m, &jq))
    return MakeError(ErrorCode::kOutOfRange, "a board corner is behind the camera");
  const Eigen::MatrixXd info = jq.transpose() * jq;
  Eigen::LDLT<Eigen::MatrixXd> ldlt(info);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) {
    return MakeError(ErrorCode::kDegenerate, "this board placement does not constrain the pose");
  }
  const Eigen::MatrixXd cov6 = corner_sigma_px * corner_sigma_px *
                               ldlt.solve(Eigen::MatrixXd::Identity(kNumParams, kNumParams));
  FloorCalibration out;
  out.rms_px = std::sqrt(2.0) * corner_sigma_px;
  FillFullCalibration(k, *board, q, jq, cov6, k_covariance, &out);
  return out;
}

MeasurementNoise MeasurementNoiseOf(const FloorCalibration& floor,
                                    const IntrinsicsCovariance& k_covariance,
                                    double pixel_sigma_px) {
  MeasurementNoise noise;
  noise.pose_covariance = floor.covariance;
  noise.pixel_sigma_px = pixel_sigma_px;
  noise.intrinsics_covariance = k_covariance;
  noise.pose_intrinsics_covariance = floor.intrinsics_cross_covariance;
  return noise;
}

}  // namespace monocle
