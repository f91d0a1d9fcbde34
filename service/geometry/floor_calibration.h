// Extrinsic calibration of a floor camera from one chessboard lying on the floor.
// Pure geometry: Eigen only. Board detection lives in service/vision.
#pragma once

#include <Eigen/Core>
#include <ostream>
#include <string>
#include <vector>

#include "service/common/result.h"
#include "service/geometry/camera_model.h"
#include "service/geometry/floor_model.h"

namespace monocle {

// Inner corners of a chessboard seen in one image. Board frame P: x_p to the right in the
// image, y_p away from the camera, origin at the corner nearest the camera on the left.
// Corner (i, j) sits at (i * square_m, j * square_m) and its pixel at pixels[j * cols + i].
struct BoardObservation {
  int cols = 0;  // inner corners along x_p
  int rows = 0;  // inner corners along y_p
  double square_m = 0;
  std::vector<Eigen::Vector2d> pixels;

  Eigen::Vector2d BoardPoint(int i, int j) const { return {i * square_m, j * square_m}; }
  const Eigen::Vector2d& Pixel(int i, int j) const { return pixels[j * cols + i]; }
};

enum class FloorCalibrationMethod {
  kFull,   // all six degrees of freedom by minimising reprojection error (default)
  kPaper,  // Xu et al. eq. (13) by least squares, then eq. (15) for the yaw
};

const char* ToString(FloorCalibrationMethod method);

struct FloorCalibration {
  FloorPose pose;
  // Covariance of (h, pitch, yaw, roll): corner noise plus the intrinsics' uncertainty,
  // propagated to first order through the fit (see CalibrateFloor).
  FloorCovariance covariance = FloorCovariance::Zero();
  // The part of `covariance` due to corner noise alone, for reports; not stored in files.
  FloorCovariance corner_covariance = FloorCovariance::Zero();
  // cov((h, pitch, yaw, roll), intrinsics in camera_model.h's order).
  Eigen::Matrix<double, 4, kNumIntrinsicParams> intrinsics_cross_covariance =
      Eigen::Matrix<double, 4, kNumIntrinsicParams>::Zero();
  Eigen::Vector2d board_origin_robot_m = Eigen::Vector2d::Zero();  // (t_x, t_y) of eq. 10
  double rms_px = 0;  // RMS distance between observed and reprojected corners
  FloorCalibrationMethod method = FloorCalibrationMethod::kFull;
  // Paper method only: condition number of eq. (13)'s least-squares system with its columns
  // scaled to unit length (0 for the full method). Large when the board's columns show too
  // little perspective for the linear solve; see floor_guidance.h.
  double condition_number = 0;

  Eigen::Vector4d Sigma() const { return covariance.diagonal().cwiseSqrt(); }
};

std::ostream& operator<<(std::ostream& os, const FloorCalibration& c);

// Fits the floor pose to the board's corners with the intrinsics held fixed. Its
// covariance: corner noise (sigma from the residuals) through the fit, plus the intrinsics'
// covariance `k_covariance` through the fit's sensitivity to them, dq/dk = -(J_q^T J_q)^-1
// J_q^T J_k (implicit function theorem at the optimum), which also gives the
// cross-covariance the measurement needs.
Result<FloorCalibration> CalibrateFloor(
    const CameraIntrinsics& k, const BoardObservation& board, FloorCalibrationMethod method,
    const IntrinsicsCovariance& k_covariance = IntrinsicsCovariance::Zero());

// What the full method would report for a board (cols x rows, square) lying at
// `board_origin_robot_m` with the calibration's yaw, seen by a camera at `pose`, whose corners
// are found with `corner_sigma_px` of noise per coordinate: for planning where to lay a board.
Result<FloorCalibration> PredictFloorCalibration(
    const CameraIntrinsics& k, const FloorPose& pose, const Eigen::Vector2d& board_origin_robot_m,
    int cols, int rows, double square_m, double corner_sigma_px,
    const IntrinsicsCovariance& k_covariance = IntrinsicsCovariance::Zero());

// Everything a floor measurement's 1 sigma stands on: this calibration, the intrinsics'
// covariance it was made with, and the pixel noise of the query.
MeasurementNoise MeasurementNoiseOf(const FloorCalibration& floor,
                                    const IntrinsicsCovariance& k_covariance,
                                    double pixel_sigma_px);

// Pixels of every corner of `board` (cols x rows, square) placed on the floor per eq. (10)
// at `board_origin_robot_m`, for round-trip tests and the renderer's ground truth.
// Fails if a corner is behind the camera.
Result<BoardObservation> ProjectBoard(const CameraIntrinsics& k, const FloorPose& pose,
                                      const Eigen::Vector2d& board_origin_robot_m, int cols,
                                      int rows, double square_m);

// Board frame (x_p, y_p) -> robot frame floor point, eq. (10) plus translation.
Eigen::Vector3d BoardToRobot(double yaw_rad, const Eigen::Vector2d& board_origin_robot_m,
                             const Eigen::Vector2d& p_board_m);

}  // namespace monocle
