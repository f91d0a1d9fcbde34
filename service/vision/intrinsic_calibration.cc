#include "service/vision/intrinsic_calibration.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>

namespace monocle {
namespace {

// What the views must show before the intrinsics can be trusted.
constexpr size_t kRecommendedViews = 10;
constexpr double kMinCoverage = 0.3;        // fraction of the image inside some board
constexpr double kMinUsefulTiltDeg = 15.0;  // the largest tilt among the views
constexpr double kMaxRelativeFocalSigma = 0.003;
constexpr double kMaxPrincipalPointSigmaFraction = 0.003;  // of the image size

struct Correspondences {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  std::vector<size_t> view_index;  // into the caller's views
};

// `rejected[v]` lists the corner indices of view v left out (blunders), may be empty.
Correspondences Collect(const std::vector<IntrinsicView>& views, const std::vector<bool>& use,
                        const std::vector<std::vector<int>>& rejected) {
  Correspondences c;
  for (size_t v = 0; v < views.size(); ++v) {
    if (!use[v]) continue;
    const auto& b = views[v].board;
    std::vector<cv::Point3f> obj;
    std::vector<cv::Point2f> img;
    for (int j = 0; j < b.rows; ++j) {
      for (int i = 0; i < b.cols; ++i) {
        if (!rejected.empty() &&
            std::find(rejected[v].begin(), rejected[v].end(), j * b.cols + i) != rejected[v].end())
          continue;
        const Eigen::Vector2d p = b.BoardPoint(i, j);
        obj.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.f);
        const auto& px = b.Pixel(i, j);
        img.emplace_back(static_cast<float>(px.x()), static_cast<float>(px.y()));
      }
    }
    c.object.push_back(std::move(obj));
    c.image.push_back(std::move(img));
    c.view_index.push_back(v);
  }
  return c;
}

int CalibrationFlags(DistortionModel model) {
  // Each Levenberg-Marquardt step solves the normal equations (intrinsics plus 6 per view);
  // OpenCV's default SVD of them cost 3x the whole fit's time on 30 views. LU of the damped,
  // positive definite system reaches the same optimum (intrinsic_calibration_test checks it
  // against OpenCV's default to 1/1000 sigma): 1.0 s -> 0.14 s, bench/intrinsics_bench.
  const int solver = cv::CALIB_USE_LU;
  switch (model) {
    case DistortionModel::kK1K2:
      return solver | cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST;
    case DistortionModel::kK1K2P1P2:
      return solver | cv::CALIB_FIX_K3;
    default:
      return solver;
  }
}

// Indices (camera_model.h's order) of the parameters a model estimates.
std::vector<int> FreeParameters(DistortionModel model) {
  switch (model) {
    case DistortionModel::kK1K2:
      return {0, 1, 2, 3, 4, 5};
    case DistortionModel::kK1K2P1P2:
      return {0, 1, 2, 3, 4, 5, 6, 7};
    default:
      return {0, 1, 2, 3, 4, 5, 6, 7, 8};
  }
}

// One view's part of the normal equations at a fit's optimum, its pose marginalised out:
// what a leave-this-view-out fit needs, one Gauss-Newton step away.
struct ViewSystem {
  Eigen::MatrixXd jk;                           // d(residuals)/d(free intrinsics), 2N x nk
  Eigen::Matrix<double, Eigen::Dynamic, 6> je;  // d(residuals)/d(rvec, tvec)
  Eigen::VectorXd r;                            // residuals (reprojected - detected), px
  Eigen::MatrixXd schur;                        // jk'jk - B C^-1 B', nk x nk
  Eigen::VectorXd gradient;                     // jk'r - B C^-1 je'r, nk
};

struct Fit {
  DistortionModel model;
  CameraIntrinsics intrinsics;
  std::vector<cv::Mat> rvecs, tvecs;
  double rss = 0;  // sum of squared residual coordinates, px^2
  int residuals = 0;
  double bic = 0;
  IntrinsicsCovariance covariance = IntrinsicsCovariance::Zero();
  double corner_sigma_px = 0;
  std::vector<std::vector<Eigen::Vector2d>> residuals_px;  // per used view
  std::vector<ViewSystem> systems;                         // per used view
};

}  // namespace

CameraIntrinsics IntrinsicsFromOpenCv(const cv::Mat& camera_matrix, const cv::Mat& dist,
                                      const cv::Size& size) {
  CameraIntrinsics k;
  k.width_px = size.width;
  k.height_px = size.height;
  k.fx = camera_matrix.at<double>(0, 0);
  k.fy = camera_matrix.at<double>(1, 1);
  k.cx = camera_matrix.at<double>(0, 2);
  k.cy = camera_matrix.at<double>(1, 2);
  for (int i = 0; i < 5; ++i) k.distortion[i] = dist.at<double>(i);
  return k;
}

namespace {

// Residuals and the Gauss-Newton covariance of the intrinsics with every view's pose
// marginalised out (Schur complement of the normal equations' arrow structure), scaled by
// the residual variance sum r^2 / (m - n).
void Evaluate(const Correspondences& c, Fit* fit) {
  const std::vector<int> free = FreeParameters(fit->model);
  const int nk = static_cast<int>(free.size());
  const cv::Matx33d camera_matrix(fit->intrinsics.fx, 0, fit->intrinsics.cx, 0, fit->intrinsics.fy,
                                  fit->intrinsics.cy, 0, 0, 1);
  cv::Mat dist(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) dist.at<double>(i) = fit->intrinsics.distortion[i];
  Eigen::MatrixXd schur = Eigen::MatrixXd::Zero(nk, nk);
  fit->rss = 0;
  fit->residuals = 0;
  fit->residuals_px.clear();
  fit->systems.clear();
  for (size_t v = 0; v < c.object.size(); ++v) {
    std::vector<cv::Point2d> projected;
    cv::Mat jac;  // 2N x 15: rvec(3) tvec(3) fx fy cx cy k1 k2 p1 p2 k3
    const std::vector<cv::Point3d> object(c.object[v].begin(), c.object[v].end());
    cv::projectPoints(object, fit->rvecs[v], fit->tvecs[v], camera_matrix, dist, projected, jac);
    const int n = static_cast<int>(projected.size());
    Eigen::MatrixXd je(2 * n, 6), jk(2 * n, nk);
    std::vector<Eigen::Vector2d> res(n);
    for (int i = 0; i < n; ++i) {
      res[i] = Eigen::Vector2d(projected[i].x - c.image[v][i].x, projected[i].y - c.image[v][i].y);
      fit->rss += res[i].squaredNorm();
      for (int row = 0; row < 2; ++row) {
        const double* j = jac.ptr<double>(2 * i + row);
        for (int a = 0; a < 6; ++a) je(2 * i + row, a) = j[a];
        for (int a = 0; a < nk; ++a) jk(2 * i + row, a) = j[6 + free[a]];
      }
    }
    fit->residuals += 2 * n;
    ViewSystem system;
    system.r.resize(2 * n);
    for (int i = 0; i < n; ++i) system.r.segment<2>(2 * i) = res[i];
    fit->residuals_px.push_back(std::move(res));
    const Eigen::Matrix<double, 6, 6> cee = je.transpose() * je;
    const Eigen::MatrixXd bke = jk.transpose() * je;
    const auto cee_ldlt = cee.ldlt();
    system.schur = jk.transpose() * jk - bke * cee_ldlt.solve(bke.transpose());
    system.gradient = jk.transpose() * system.r - bke * cee_ldlt.solve(je.transpose() * system.r);
    schur += system.schur;
    system.jk = std::move(jk);
    system.je = std::move(je);
    fit->systems.push_back(std::move(system));
  }
  const int params = nk + 6 * static_cast<int>(c.object.size());
  const int dof = std::max(fit->residuals - params, 1);
  const double variance = fit->rss / dof;
  fit->corner_sigma_px = std::sqrt(variance);
  // BIC with the noise variance profiled out: m ln(RSS/m) + n ln m.
  fit->bic = fit->residuals * std::log(std::max(fit->rss, 1e-300) / fit->residuals) +
             params * std::log(static_cast<double>(fit->residuals));
  Eigen::FullPivLU<Eigen::MatrixXd> lu(schur);
  fit->covariance.setZero();
  if (!lu.isInvertible()) {
    // A direction the views do not constrain at all: report it as unknown, not as exact.
    for (int a = 0; a < nk; ++a)
      fit->covariance(free[a], free[a]) = std::numeric_limits<double>::infinity();
    return;
  }
  const Eigen::MatrixXd cov = variance * lu.inverse();
  for (int a = 0; a < nk; ++a)
    for (int b = 0; b < nk; ++b) fit->covariance(free[a], free[b]) = cov(a, b);
}

// `start`: a fit of the same model to start from (its intrinsics), or null.
Result<Fit> FitModel(const Correspondences& c, const cv::Size& size, DistortionModel model,
                     const Fit* start = nullptr) {
  Fit fit;
  fit.model = model;
  cv::Mat camera_matrix, dist;
  int flags = CalibrationFlags(model);
  if (start != nullptr) {
    const CameraIntrinsics& k = start->intrinsics;
    camera_matrix = (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    dist = cv::Mat(1, 5, CV_64F);
    for (int i = 0; i < 5; ++i) dist.at<double>(i) = k.distortion[i];
    flags |= cv::CALIB_USE_INTRINSIC_GUESS;
  }
  // From a fit's optimum (a jackknife refit) a few steps reach the new one: stop when the
  // parameters move by less than 1e-10 of themselves, not at machine precision.
  const cv::TermCriteria until =
      start == nullptr
          ? cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100,
                             std::numeric_limits<double>::epsilon())
          : cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, 1e-10);
  try {
    cv::calibrateCamera(c.object, c.image, size, camera_matrix, dist, fit.rvecs, fit.tvecs, flags,
                        until);
  } catch (const cv::Exception& e) {
    return MakeError(ErrorCode::kDegenerate,
                     std::string("the views do not determine the camera (OpenCV: ") + e.err + ")");
  }
  fit.intrinsics = IntrinsicsFromOpenCv(camera_matrix, dist, size);
  Evaluate(c, &fit);
  return fit;
}

// The fit again without each view in turn: its parameters, and how well they predict the
// view left out (its pose refitted to them, the intrinsics not).
struct LeaveOuts {
  std::vector<IntrinsicParams> params;  // per used view
  std::vector<double> held_out_sse;     // that view's squared residual coordinates, px^2
  int held_out_corners = 0;             // over all views
};

IntrinsicParams Scatter(const std::vector<int>& free, const Eigen::VectorXd& step) {
  IntrinsicParams full = IntrinsicParams::Zero();
  for (size_t a = 0; a < free.size(); ++a) full[free[a]] = step[a];
  return full;
}

// Each leave-one-view-out fit as one Gauss-Newton step from the full fit's optimum on the
// other views' normal equations (their poses marginalised out): the fit without a view
// moves little, so one step is close to refitting (intrinsic_calibration_test checks it
// against ExactLeaveOuts) at the cost of a 9x9 solve instead of a calibration.
Result<LeaveOuts> LinearisedLeaveOuts(const Fit& fit) {
  const std::vector<int> free = FreeParameters(fit.model);
  const int nk = static_cast<int>(free.size());
  Eigen::MatrixXd schur = Eigen::MatrixXd::Zero(nk, nk);
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(nk);
  for (const auto& s : fit.systems) {
    schur += s.schur;
    gradient += s.gradient;
  }
  const IntrinsicParams at = IntrinsicParamsOf(fit.intrinsics);
  LeaveOuts out;
  for (const auto& s : fit.systems) {
    const Eigen::FullPivLU<Eigen::MatrixXd> rest(schur - s.schur);
    if (rest.rank() < nk) {
      return MakeError(ErrorCode::kDegenerate, "without one view the rest do not determine it");
    }
    const Eigen::VectorXd step = -rest.solve(gradient - s.gradient);
    out.params.push_back(at + Scatter(free, step));
    // The left-out view under the new intrinsics, its own pose refitted (linearised too).
    const Eigen::VectorXd moved = s.r + s.jk * step;
    const Eigen::Matrix<double, 6, 1> pose_step =
        -(s.je.transpose() * s.je).ldlt().solve(s.je.transpose() * moved);
    out.held_out_sse.push_back((moved + s.je * pose_step).squaredNorm());
    out.held_out_corners += static_cast<int>(s.r.size() / 2);
  }
  return out;
}

// Each leave-one-view-out fit refitted in full from the full fit's optimum, and the left-out
// view's pose by solvePnP: the reference LinearisedLeaveOuts approximates.
Result<LeaveOuts> ExactLeaveOuts(const Correspondences& c, const cv::Size& size, const Fit& full) {
  const size_t n = c.object.size();
  LeaveOuts out;
  for (size_t left = 0; left < n; ++left) {
    Correspondences rest;
    for (size_t v = 0; v < n; ++v) {
      if (v == left) continue;
      rest.object.push_back(c.object[v]);
      rest.image.push_back(c.image[v]);
      rest.view_index.push_back(c.view_index[v]);
    }
    auto fit = FitModel(rest, size, full.model, &full);
    if (!fit) return fit.error();
    out.params.push_back(IntrinsicParamsOf(fit->intrinsics));
    const CameraIntrinsics& k = fit->intrinsics;
    const cv::Matx33d camera_matrix(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    const cv::Mat dist = (cv::Mat_<double>(1, 5) << k.distortion[0], k.distortion[1],
                          k.distortion[2], k.distortion[3], k.distortion[4]);
    cv::Mat rvec = full.rvecs[left].clone(), tvec = full.tvecs[left].clone();
    cv::solvePnP(c.object[left], c.image[left], camera_matrix, dist, rvec, tvec, true);
    std::vector<cv::Point2f> projected;
    cv::projectPoints(c.object[left], rvec, tvec, camera_matrix, dist, projected);
    double sse = 0;
    for (size_t i = 0; i < projected.size(); ++i) {
      const cv::Point2f d = projected[i] - c.image[left][i];
      sse += d.dot(d);
    }
    out.held_out_sse.push_back(sse);
    out.held_out_corners += static_cast<int>(projected.size());
  }
  return out;
}

// (n-1)/n times the spread of the leave-one-out parameters. Errors shared by one view's
// corners move its leave-out fit, so they count here, as they do not in the analytic
// covariance.
IntrinsicsCovariance JackknifeCovariance(const LeaveOuts& leave_outs) {
  const size_t n = leave_outs.params.size();
  IntrinsicParams mean = IntrinsicParams::Zero();
  for (const auto& p : leave_outs.params) mean += p;
  mean /= static_cast<double>(n);
  IntrinsicsCovariance cov = IntrinsicsCovariance::Zero();
  for (const auto& p : leave_outs.params) cov += (p - mean) * (p - mean).transpose();
  return cov * (static_cast<double>(n - 1) / static_cast<double>(n));
}

double HeldOutRmsPx(const LeaveOuts& leave_outs) {
  double sse = 0;
  for (const double e : leave_outs.held_out_sse) sse += e;
  return std::sqrt(sse / std::max(leave_outs.held_out_corners, 1));
}

// The smallest model (they are nested, smallest first) whose error on views left out is
// within one standard error of the best's, paired view by view: a richer model must predict
// views it did not see clearly better, not merely fit the ones it did.
size_t ChooseByHeldOutViews(const std::vector<LeaveOuts>& per_model) {
  auto total = [](const LeaveOuts& l) {
    double sum = 0;
    for (const double e : l.held_out_sse) sum += e;
    return sum;
  };
  size_t best = 0;
  for (size_t m = 1; m < per_model.size(); ++m)
    if (total(per_model[m]) < total(per_model[best])) best = m;
  const size_t n = per_model[best].held_out_sse.size();
  for (size_t m = 0; m < best; ++m) {
    std::vector<double> excess(n);
    double mean = 0;
    for (size_t v = 0; v < n; ++v) {
      excess[v] = per_model[m].held_out_sse[v] - per_model[best].held_out_sse[v];
      mean += excess[v] / n;
    }
    double variance = 0;
    for (const double e : excess) variance += (e - mean) * (e - mean) / std::max<size_t>(n - 1, 1);
    if (mean * n <= std::sqrt(variance * n)) return m;
  }
  return best;
}

// How large a jackknife-to-analytic variance ratio noise alone makes with `dof` degrees of
// freedom: chi-square's upper 0.13 % point over dof (Wilson-Hilferty), i.e. 1 % over the up
// to 8 parameters tested together, so an honest analytic 1 sigma is rarely widened.
double RatioNoiseLimit(double dof) {
  const double a = 2.0 / (9.0 * dof);
  return std::pow(1.0 - a + 3.0 * std::sqrt(a), 3);
}

// The analytic covariance with each free parameter's variance raised to the jackknife's where
// that is larger than the jackknife's own noise explains (D A D, D diagonal: still a
// covariance, the correlations kept). The jackknife is noisy with few views and errs large:
// a ratio within its noise is no evidence against the analytic figure.
IntrinsicsCovariance Widened(const IntrinsicsCovariance& analytic,
                             const IntrinsicsCovariance& jackknife, const std::vector<int>& free,
                             size_t views) {
  const double limit = RatioNoiseLimit(static_cast<double>(views - 1));
  Eigen::Matrix<double, kNumIntrinsicParams, 1> scale =
      Eigen::Matrix<double, kNumIntrinsicParams, 1>::Ones();
  for (const int i : free) {
    if (!(analytic(i, i) > 0) || !std::isfinite(analytic(i, i))) continue;
    const double ratio = jackknife(i, i) / analytic(i, i);
    if (ratio > limit) scale[i] = std::sqrt(ratio);
  }
  return scale.asDiagonal() * analytic * scale.asDiagonal();
}

std::string Fixed(double value, int digits) {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(digits);
  os << value;
  return os.str();
}

// `held_out_rms_px`: per model, when the choice was by views left out; empty when by BIC.
// `bic_why`: why the choice was by BIC instead of by views left out.
std::string ModelReason(const std::vector<Fit>& fits, const std::vector<double>& held_out_rms_px,
                        size_t chosen, bool automatic, const std::string& bic_why) {
  const Fit& f = fits[chosen];
  auto rms = [](const Fit& x) { return std::sqrt(x.rss / (x.residuals / 2)); };
  if (!automatic) return std::string(ToString(f.model)) + ", as asked";
  const bool by_held_out = !held_out_rms_px.empty();
  std::string reason =
      std::string(ToString(f.model)) +
      (by_held_out ? ", the smallest model within one standard error of the "
                     "best at predicting views left out of the fit (RMS on "
                     "the view left out"
                   : ", the smallest model the data support (BIC, " + bic_why + "; RMS");
  for (size_t i = 0; i < fits.size(); ++i) {
    reason += std::string(i ? "; " : ": ") + ToString(fits[i].model) + " " +
              Fixed(by_held_out ? held_out_rms_px[i] : rms(fits[i]), 4) + " px";
  }
  reason += ")";
  if (chosen + 1 < fits.size()) {
    reason += "; " + std::string(ToString(fits[chosen + 1].model)) +
              (by_held_out ? " does not predict them clearly better"
                           : " lowers the residual too little for its extra terms");
  }
  return reason;
}

double TiltDeg(const cv::Mat& rvec) {
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  return std::acos(std::min(1.0, std::abs(r(2, 2)))) * 180 / std::numbers::pi;
}

// Fraction of the image covered by the boards' outlines, on a coarse raster, and which
// image corners (the outer fifth in both directions) no detected corner reached.
void MeasureCoverage(const std::vector<IntrinsicView>& views, const std::vector<bool>& used,
                     const cv::Size& size, IntrinsicCalibration* out) {
  constexpr double kScale = 1.0 / 8;
  cv::Mat mask(cv::Size(std::max(1, static_cast<int>(size.width * kScale)),
                        std::max(1, static_cast<int>(size.height * kScale))),
               CV_8U, cv::Scalar(0));
  bool corner_seen[4] = {false, false, false, false};  // top-left, top-right, bottom-l, bottom-r
  for (size_t v = 0; v < views.size(); ++v) {
    if (!used[v]) continue;
    const auto& b = views[v].board;
    std::vector<cv::Point> hull;
    for (const auto& [i, j] :
         {std::pair{0, 0}, {b.cols - 1, 0}, {b.cols - 1, b.rows - 1}, {0, b.rows - 1}}) {
      const auto& p = b.Pixel(i, j);
      hull.emplace_back(static_cast<int>(p.x() * kScale), static_cast<int>(p.y() * kScale));
    }
    cv::fillConvexPoly(mask, hull, cv::Scalar(255));
    for (const auto& p : b.pixels) {
      const bool left = p.x()<size.width * 0.25, right = p.x()> size.width * 0.75;
      const bool top = p.y()<size.height * 0.25, bottom = p.y()> size.height * 0.75;
      corner_seen[0] |= top && left;
      corner_seen[1] |= top && right;
      corner_seen[2] |= bottom && left;
      corner_seen[3] |= bottom && right;
    }
  }
  out->coverage = static_cast<double>(cv::countNonZero(mask)) / mask.total();
  const char* names[4] = {"top-left", "top-right", "bottom-left", "bottom-right"};
  for (int i = 0; i < 4; ++i)
    if (!corner_seen[i]) out->uncovered_corners.emplace_back(names[i]);
}

void AddWarnings(size_t used_views, IntrinsicCalibration* out) {
  const auto sigma = out->Sigma();
  const auto& k = out->intrinsics;
  if (used_views < kRecommendedViews) {
    out->warnings.push_back("only " + std::to_string(used_views) +
                            " views: use 10 or more, the board tilted in different directions");
  }
  if (out->coverage < kMinCoverage || !out->uncovered_corners.empty()) {
    std::string corners;
    for (const auto& c : out->uncovered_corners) corners += (corners.empty() ? "" : ", ") + c;
    out->warnings.push_back(
        "the boards cover " + Fixed(100 * out->coverage, 0) + " % of the image" +
        (corners.empty() ? "" : " and never reach its " + corners + " corner(s)") +
        ": the lens distortion is extrapolated there; show the board near every edge and corner");
  }
  if (out->max_tilt_deg < kMinUsefulTiltDeg) {
    out->warnings.push_back(
        "the board never tilts more than " + Fixed(out->max_tilt_deg, 0) +
        " degrees from facing the camera: focal length and board distance cannot be told "
        "apart; tilt it 20-45 degrees, in different directions, in several views");
  }
  const double rel_f = std::max(sigma[0] / k.fx, sigma[1] / k.fy);
  const double rel_c = std::max(sigma[2] / k.width_px, sigma[3] / k.height_px);
  if (!(rel_f <= kMaxRelativeFocalSigma) || !(rel_c <= kMaxPrincipalPointSigmaFraction)) {
    out->warnings.push_back("the views constrain the camera poorly: 1 sigma of fx " +
                            Fixed(100 * sigma[0] / k.fx, 2) + " %, of cx " + Fixed(sigma[2], 1) +
                            " px, of cy " + Fixed(sigma[3], 1) +
                            " px; measurements made with it say so in their 1 sigma");
  }
}

// A corner refined onto the wrong spot (a blunder of pixels, not noise) would dominate the
// fit and the choice of model. The richest model's fit finds them, as residuals beyond 5
// robust sigmas (and 0.5 px): per view (indexed as the caller's), the corners to leave out.
std::vector<std::vector<int>> FindBlunders(const Correspondences& c, const Fit& richest,
                                           size_t view_count, int* count) {
  std::vector<std::vector<int>> rejected(view_count);
  std::vector<double> magnitudes;
  for (const auto& view : richest.residuals_px)
    for (const auto& r : view) magnitudes.push_back(r.norm());
  std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2,
                   magnitudes.end());
  // The median of |r| for 2-D Gaussian noise is 1.1774 sigma.
  const double robust_sigma = magnitudes[magnitudes.size() / 2] / 1.1774;
  const double limit = std::max(5 * robust_sigma, 0.5);
  *count = 0;
  for (size_t u = 0; u < c.view_index.size(); ++u) {
    auto& view_rejected = rejected[c.view_index[u]];
    for (size_t i = 0; i < richest.residuals_px[u].size(); ++i) {
      if (richest.residuals_px[u][i].norm() > limit) view_rejected.push_back(i);
    }
    // A view that loses more than a quarter of its corners is a bad view, not a few bad
    // corners: keep it whole and let the outlier test name it.
    if (view_rejected.size() * 4 > richest.residuals_px[u].size()) view_rejected.clear();
    *count += view_rejected.size();
  }
  return rejected;
}

Result<LeaveOuts> LeaveOutsOf(const Correspondences& c, const cv::Size& size, const Fit& fit,
                              bool exact) {
  return exact ? ExactLeaveOuts(c, size, fit) : LinearisedLeaveOuts(fit);
}

// Chooses among `fits` (one per candidate model) and sets the model, its reason, the trials
// and the covariance of `out`.
void ChooseModelAndCovariance(const Correspondences& c, const cv::Size& size,
                              const std::vector<Fit>& fits, bool automatic, bool exact,
                              IntrinsicCalibration* out) {
  const bool enough_views = c.object.size() >= kMinJackknifeViews;
  std::vector<std::optional<LeaveOuts>> leave_outs(fits.size());
  for (size_t m = 0; m < fits.size() && enough_views; ++m) {
    if (!fits[m].covariance.allFinite()) continue;
    if (auto l = LeaveOutsOf(c, size, fits[m], exact)) leave_outs[m] = std::move(*l);
  }
  std::vector<double> held_out_rms;
  size_t chosen = 0;
  if (automatic && std::all_of(leave_outs.begin(), leave_outs.end(),
                               [](const auto& l) { return l.has_value(); })) {
    std::vector<LeaveOuts> all;
    for (const auto& l : leave_outs) {
      all.push_back(*l);
      held_out_rms.push_back(HeldOutRmsPx(*l));
    }
    chosen = ChooseByHeldOutViews(all);
  } else {
    for (size_t i = 1; i < fits.size(); ++i)
      if (fits[i].bic < fits[chosen].bic) chosen = i;
  }
  const Fit& fit = fits[chosen];
  out->intrinsics = fit.intrinsics;
  out->model = fit.model;
  const std::string bic_why =
      enough_views ? "with a view left out the rest did not determine every model"
                   : "fewer than " + std::to_string(kMinJackknifeViews) + " views to leave out";
  out->model_reason = ModelReason(fits, held_out_rms, chosen, automatic, bic_why);
  for (size_t m = 0; m < fits.size(); ++m) {
    const Fit& f = fits[m];
    out->trials.push_back({f.model, std::sqrt(f.rss / (f.residuals / 2)), f.bic,
                           leave_outs[m] ? HeldOutRmsPx(*leave_outs[m]) : 0.0});
  }
  out->analytic_covariance = fit.covariance;
  out->covariance = fit.covariance;
  if (!enough_views) {
    out->covariance_method = "analytic (Gauss-Newton) only: the jackknife needs " +
                             std::to_string(kMinJackknifeViews) + " views or more";
  } else if (!fit.covariance.allFinite()) {
    out->covariance_method =
        "analytic (Gauss-Newton) only: the views leave a parameter "
        "undetermined (its 1 sigma is infinite)";
  } else if (!leave_outs[chosen]) {
    // The fit stands; only the check of its 1 sigma is missing, and the user is told.
    out->covariance_method =
        "analytic (Gauss-Newton) only: with one view left out the rest did not determine the "
        "camera, so the spread between views could not be measured; add views";
  } else {
    out->jackknife_covariance = JackknifeCovariance(*leave_outs[chosen]);
    out->covariance = Widened(fit.covariance, out->jackknife_covariance, FreeParameters(fit.model),
                              c.object.size());
    out->covariance_method =
        "analytic (Gauss-Newton), each variance raised to the leave-one-view-out jackknife's "
        "where that is larger than chance (1 % over all parameters): errors shared by a view's "
        "corners count";
  }
}

// Per-view residuals, poses and outliers of the chosen fit.
void DescribeViews(const std::vector<IntrinsicView>& views, const Correspondences& c,
                   const Fit& fit, const std::vector<std::vector<int>>& rejected,
                   double outlier_factor, IntrinsicCalibration* out) {
  std::vector<double> view_rms;
  for (size_t u = 0; u < c.view_index.size(); ++u) {
    ViewFit v;
    v.name = views[c.view_index[u]].name;
    double sum = 0;
    for (const auto& r : fit.residuals_px[u]) sum += r.squaredNorm();
    v.rms_px = std::sqrt(sum / fit.residuals_px[u].size());
    v.tilt_deg = TiltDeg(fit.rvecs[u]);
    cv::Matx33d r;
    cv::Rodrigues(fit.rvecs[u], r);
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) v.r_camera_board(a, b) = r(a, b);
      v.t_camera_board_m[a] = fit.tvecs[u].at<double>(a);
    }
    v.residuals_px = fit.residuals_px[u];
    v.rejected_corners = static_cast<int>(rejected[c.view_index[u]].size());
    v.rejected_indices = rejected[c.view_index[u]];
    out->max_tilt_deg = std::max(out->max_tilt_deg, v.tilt_deg);
    view_rms.push_back(v.rms_px);
    out->views.push_back(std::move(v));
  }
  std::nth_element(view_rms.begin(), view_rms.begin() + view_rms.size() / 2, view_rms.end());
  const double median = view_rms[view_rms.size() / 2];
  for (auto& v : out->views) v.outlier = v.rms_px > outlier_factor * median;
}

// One fit over the views marked in `use`: every candidate model, the chosen one's
// covariance, per-view residuals, coverage and warnings.
Result<IntrinsicCalibration> CalibrateSubset(const std::vector<IntrinsicView>& views,
                                             const std::vector<bool>& use,
                                             const cv::Size& image_size,
                                             const IntrinsicCalibrationOptions& options) {
  const bool automatic = options.model == DistortionModel::kAuto;
  const std::vector<DistortionModel> candidates =
      automatic ? std::vector<DistortionModel>{DistortionModel::kK1K2, DistortionModel::kK1K2P1P2,
                                               DistortionModel::kK1K2P1P2K3}
                : std::vector<DistortionModel>{options.model};
  auto fit_all = [&](const Correspondences& c) -> Result<std::vector<Fit>> {
    std::vector<Fit> fits;
    for (const auto model : candidates) {
      auto fit = FitModel(c, image_size, model);
      if (!fit) return fit.error();
      fits.push_back(std::move(*fit));
    }
    return fits;
  };
  Correspondences c = Collect(views, use, {});
  auto fitted = fit_all(c);
  if (!fitted) return fitted.error();
  int rejected_count = 0;
  const auto rejected = FindBlunders(c, fitted->back(), views.size(), &rejected_count);
  if (rejected_count > 0) {
    c = Collect(views, use, rejected);
    fitted = fit_all(c);
    if (!fitted) return fitted.error();
  }
  IntrinsicCalibration out;
  out.rejected_corners = rejected_count;
  ChooseModelAndCovariance(c, image_size, *fitted, automatic, options.exact_leave_outs, &out);
  const Fit& fit = *std::find_if(fitted->begin(), fitted->end(),
                                 [&](const Fit& f) { return f.model == out.model; });
  out.rms_px = std::sqrt(fit.rss / (fit.residuals / 2));
  out.corner_sigma_px = fit.corner_sigma_px;
  DescribeViews(views, c, fit, rejected, options.outlier_factor, &out);
  MeasureCoverage(views, use, image_size, &out);
  AddWarnings(c.view_index.size(), &out);
  return out;
}

}  // namespace

const char* ToString(DistortionModel model) {
  switch (model) {
    case DistortionModel::kAuto:
      return "auto";
    case DistortionModel::kK1K2:
      return "k1k2";
    case DistortionModel::kK1K2P1P2:
      return "k1k2p1p2";
    case DistortionModel::kK1K2P1P2K3:
      return "k1k2p1p2k3";
  }
  return "?";
}

Result<DistortionModel> ParseDistortionModel(const std::string& text) {
  for (const auto m : {DistortionModel::kAuto, DistortionModel::kK1K2, DistortionModel::kK1K2P1P2,
                       DistortionModel::kK1K2P1P2K3}) {
    if (text == ToString(m)) return m;
  }
  return MakeError(ErrorCode::kInvalidArgument,
                   "--model '" + text + "' is not one of auto, k1k2, k1k2p1p2, k1k2p1p2k3");
}

Result<IntrinsicCalibration> CalibrateIntrinsics(const std::vector<IntrinsicView>& views,
                                                 const cv::Size& image_size,
                                                 const IntrinsicCalibrationOptions& options) {
  if (views.size() < 3) {
    return MakeError(ErrorCode::kInvalidArgument, "at least 3 board views are needed, " +
                                                      std::to_string(views.size()) + " given");
  }
  std::vector<bool> use(views.size(), true);
  auto first = CalibrateSubset(views, use, image_size, options);
  if (!first || !options.drop_outliers) return first;
  size_t kept = 0;
  for (size_t v = 0; v < views.size(); ++v) {
    use[v] = !first->views[v].outlier;
    kept += use[v];
  }
  if (kept == views.size() || kept < 3) return first;
  auto second = CalibrateSubset(views, use, image_size, options);
  if (!second) return second;
  // Report the dropped views too, with their residuals from the first fit.
  for (const auto& v : first->views) {
    if (!v.outlier) continue;
    second->views.push_back(v);
    second->views.back().dropped = true;
  }
  return second;
}

}  // namespace monocle
