// Intrinsic calibration from several chessboard views, with the uncertainty a measurement
// needs: OpenCV's calibrateCamera does the fit; monocle adds the full covariance of the
// intrinsics, the choice of distortion model, per-view residuals with outliers named, and
// warnings when the views do not constrain the model.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "service/common/result.h"
#include "service/geometry/camera_model.h"
#include "service/geometry/floor_calibration.h"

namespace monocle {

enum class DistortionModel {
  kAuto,        // the smallest of the three below that predicts views left out as well
                // as the best (within one standard error); by BIC below 5 views
  kK1K2,        // radial k1 k2
  kK1K2P1P2,    // plus tangential p1 p2
  kK1K2P1P2K3,  // plus radial k3 (wide-angle lenses)
};

const char* ToString(DistortionModel model);  // "auto", "k1k2", "k1k2p1p2", "k1k2p1p2k3"
Result<DistortionModel> ParseDistortionModel(const std::string& text);

struct IntrinsicView {
  std::string name;  // shown in reports, e.g. the image file
  BoardObservation board;
};

struct IntrinsicCalibrationOptions {
  DistortionModel model = DistortionModel::kAuto;
  // A view whose RMS exceeds this many times the median view's is an outlier.
  double outlier_factor = 3.0;
  bool drop_outliers = false;  // refit without the outliers
  // Refit every leave-one-view-out fit in full instead of one Gauss-Newton step from the
  // full fit: far slower, the same figures to a few percent; for checking.
  bool exact_leave_outs = false;
};

struct ViewFit {
  std::string name;
  double rms_px = 0;    // RMS distance between detected and reprojected corners
  double tilt_deg = 0;  // angle between the board's normal and the optical axis
  bool outlier = false;
  bool dropped = false;            // left out of the final fit (drop_outliers)
  Eigen::Matrix3d r_camera_board;  // board frame -> camera frame (metres)
  Eigen::Vector3d t_camera_board_m;
  std::vector<Eigen::Vector2d> residuals_px;  // reprojected - detected, per corner used
  int rejected_corners = 0;           // corners left out as blunders (residual > 5 robust sigma)
  std::vector<int> rejected_indices;  // their indices in the view's board.pixels
};

struct ModelTrial {
  DistortionModel model;
  double rms_px = 0;
  double bic = 0;  // Bayesian information criterion of the fit (lower is better)
  // RMS distance of each view's corners from where the fit without that view (its pose
  // refitted) puts them: how well the model predicts views it did not see. 0 below 5 views.
  double held_out_rms_px = 0;
};

struct IntrinsicCalibration {
  CameraIntrinsics intrinsics;
  // What measurements use (camera_model.h's order): the analytic covariance, each parameter's
  // variance widened to the views' own spread where that is larger (covariance_method says
  // which and why). Both figures are kept.
  IntrinsicsCovariance covariance = IntrinsicsCovariance::Zero();
  // Gauss-Newton: assumes every corner's error independent and the lens model exact.
  IntrinsicsCovariance analytic_covariance = IntrinsicsCovariance::Zero();
  // Leave-one-view-out jackknife: the spread of the parameters when each view is left out in
  // turn, which counts errors shared by a view's corners (a bent board, a lens the model does
  // not fit there). Zero with fewer than kMinJackknifeViews views. Each leave-out fit is one
  // Gauss-Newton step from the full fit (exact_leave_outs: refitted).
  IntrinsicsCovariance jackknife_covariance = IntrinsicsCovariance::Zero();
  std::string covariance_method;
  DistortionModel model = DistortionModel::kK1K2P1P2;
  std::string model_reason;        // which model and why, for people
  std::vector<ModelTrial> trials;  // every model fitted (one unless kAuto), smallest first
  double rms_px = 0;               // over all corners of the views used
  double corner_sigma_px = 0;      // noise of one corner coordinate, from the residuals
  int rejected_corners = 0;        // over all views
  std::vector<ViewFit> views;
  double coverage = 0;                         // fraction of the image inside some view's board
  std::vector<std::string> uncovered_corners;  // image corners no board reached
  double max_tilt_deg = 0;
  std::vector<std::string> warnings;  // the views do not constrain the model well

  Eigen::Matrix<double, kNumIntrinsicParams, 1> Sigma() const {
    return covariance.diagonal().cwiseMax(0).cwiseSqrt();
  }
};

// The jackknife needs this many views to say anything about their spread.
inline constexpr size_t kMinJackknifeViews = 5;

// Needs at least 3 views, all of `image_size`.
// OpenCV's camera matrix and distortion coefficients (k1 k2 p1 p2 [k3 ...]) as monocle's
// intrinsics for an image of `size`.
CameraIntrinsics IntrinsicsFromOpenCv(const cv::Mat& camera_matrix, const cv::Mat& dist,
                                      const cv::Size& size);

Result<IntrinsicCalibration> CalibrateIntrinsics(const std::vector<IntrinsicView>& views,
                                                 const cv::Size& image_size,
                                                 const IntrinsicCalibrationOptions& options = {});

}  // namespace monocle
