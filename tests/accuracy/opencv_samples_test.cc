// Real photos: OpenCV's own calibration views (Debian package opencv-doc,
// examples/data/left01.jpg .. left14.jpg, 9x6 inner corners, 25 mm squares). monocle's
// intrinsics must agree with OpenCV's sample pipeline (findChessboardCorners, cornerSubPix
// 11x11, calibrateCamera with the same distortion model) within 2 sigma of their difference
// (both reported sigmas), and every view's board pose with solvePnP's.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "service/geometry/projection_uncertainty.h"
#include "service/vision/chessboard.h"
#include "service/vision/intrinsic_calibration.h"

namespace monocle {
namespace {

const std::filesystem::path kData = "/usr/share/doc/opencv-doc/examples/data";

int OpenCvFlags(DistortionModel model) {
  switch (model) {
    case DistortionModel::kK1K2:
      return cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST;
    case DistortionModel::kK1K2P1P2:
      return cv::CALIB_FIX_K3;
    default:
      return 0;
  }
}

TEST(OpenCvSamplesTest, IntrinsicsAgreeWithOpenCvWithinTwoSigma) {
  if (!std::filesystem::exists(kData / "left01.jpg")) {
    GTEST_SKIP() << "OpenCV's sample photos are not installed (" << kData
                 << "/left01.jpg): install the Debian package opencv-doc (scripts/setup does)";
  }
  const BoardSpec spec{9, 6, 0.025};
  std::vector<IntrinsicView> views;
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> opencv_corners;
  cv::Size size;
  for (int i = 1; i <= 14; ++i) {
    std::ostringstream name;
    name << "left" << std::setw(2) << std::setfill('0') << i << ".jpg";
    const cv::Mat grey = cv::imread((kData / name.str()).string(), cv::IMREAD_GRAYSCALE);
    if (grey.empty()) continue;  // left10.jpg is not shipped
    size = grey.size();
    auto board = DetectChessboard(grey, spec);
    // OpenCV's sample pipeline on the same image.
    std::vector<cv::Point2f> corners;
    if (!board || !cv::findChessboardCorners(grey, {9, 6}, corners)) continue;
    cv::cornerSubPix(grey, corners, {11, 11}, {-1, -1},
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.0001));
    std::vector<cv::Point3f> obj;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 9; ++c) obj.emplace_back(c * 0.025f, r * 0.025f, 0.f);
    object.push_back(obj);
    opencv_corners.push_back(corners);
    views.push_back({name.str(), std::move(*board)});
  }
  ASSERT_GE(views.size(), 12u);
  const auto cal = CalibrateIntrinsics(views, size);
  ASSERT_TRUE(cal.ok()) << cal.error();
  cv::Mat camera_matrix, dist, std_in, std_ex, per_view;
  std::vector<cv::Mat> rvecs, tvecs;
  double opencv_rms = cv::calibrateCamera(object, opencv_corners, size, camera_matrix, dist, rvecs,
                                          tvecs, std_in, std_ex, per_view, OpenCvFlags(cal->model));
  // OpenCV's pipeline has no defence against a mis-refined corner: left02.jpg comes out at
  // 1.2 px RMS, 6x the other views (OpenCV's own left_intrinsics.yml shows the same) and
  // pulls fx by ~3 px. Give it the same rule monocle applies (a view above 3x the median
  // RMS is an outlier) and refit without it, so that the comparison is of the methods.
  std::vector<double> errors(per_view.begin<double>(), per_view.end<double>());
  std::vector<double> sorted = errors;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  std::vector<std::vector<cv::Point3f>> kept_object;
  std::vector<std::vector<cv::Point2f>> kept_corners;
  for (size_t v = 0; v < errors.size(); ++v) {
    if (errors[v] > 3 * sorted[sorted.size() / 2]) {
      std::cout << "OpenCV's pipeline: " << views[v].name << " is an outlier (" << errors[v]
                << " px); refitting without it\n";
      continue;
    }
    kept_object.push_back(object[v]);
    kept_corners.push_back(opencv_corners[v]);
  }
  if (kept_object.size() < object.size()) {
    opencv_rms = cv::calibrateCamera(kept_object, kept_corners, size, camera_matrix, dist, rvecs,
                                     tvecs, std_in, std_ex, per_view, OpenCvFlags(cal->model));
  }
  // OpenCV's own 1 sigma, on our residual-variance convention (intrinsic_calibration_test):
  // both estimates carry noise, so they must agree within 2 sigma of their difference.
  const double points = 54.0 * kept_object.size();
  const double params = 4 + 6.0 * kept_object.size() +
                        (cal->model == DistortionModel::kK1K2       ? 2
                         : cal->model == DistortionModel::kK1K2P1P2 ? 4
                                                                    : 5);
  const double convention = std::sqrt((points - params) / (2 * points - params));
  const auto& k = cal->intrinsics;
  const auto sigma = cal->Sigma();
  const IntrinsicParams mine = IntrinsicParamsOf(k);
  const IntrinsicParams theirs = IntrinsicParamsOf(IntrinsicsFromOpenCv(camera_matrix, dist, size));
  for (const auto& v : cal->views)
    std::cout << v.name << " rms " << v.rms_px << " rejected " << v.rejected_corners
              << (v.outlier ? " OUTLIER" : "") << "\n";
  std::cout << views.size() << " views; monocle " << cal->model_reason << "; RMS " << cal->rms_px
            << " px (OpenCV's sample pipeline " << opencv_rms << " px)\n";
  for (int p = 0; p < kNumIntrinsicParams; ++p) {
    const double their_sigma = std_in.at<double>(p) * convention;
    std::cout << std::setw(3) << kIntrinsicParamNames[p] << "  monocle " << std::setw(12) << mine[p]
              << " +- " << std::setw(10) << sigma[p] << "   OpenCV " << std::setw(12) << theirs[p]
              << " +- " << their_sigma << "\n";
    if (sigma[p] == 0) continue;  // a term the chosen model holds at 0
    EXPECT_LE(std::abs(mine[p] - theirs[p]),
              2 * std::sqrt(sigma[p] * sigma[p] + their_sigma * their_sigma))
        << kIntrinsicParamNames[p];
  }
  EXPECT_LT(cal->rms_px, opencv_rms);

  // Each view's board pose against solvePnP with the same intrinsics and corners.
  const cv::Matx33d kk(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  cv::Mat d(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) d.at<double>(i) = k.distortion[i];
  for (size_t v = 0; v < views.size(); ++v) {
    // solvePnP sees every corner; compare views whose corners monocle used all of.
    if (cal->views[v].rejected_corners > 0) continue;
    const auto& b = views[v].board;
    std::vector<cv::Point3d> obj;
    std::vector<cv::Point2d> img;
    for (int j = 0; j < b.rows; ++j) {
      for (int i = 0; i < b.cols; ++i) {
        obj.emplace_back(b.BoardPoint(i, j).x(), b.BoardPoint(i, j).y(), 0);
        img.emplace_back(b.Pixel(i, j).x(), b.Pixel(i, j).y());
      }
    }
    cv::Mat rvec, tvec;
    ASSERT_TRUE(cv::solvePnP(obj, img, kk, d, rvec, tvec, false, cv::SOLVEPNP_ITERATIVE));
    cv::Matx33d r;
    cv::Rodrigues(rvec, r);
    Eigen::Matrix3d r_pnp;
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) r_pnp(a, c) = r(a, c);
    const auto& fit = cal->views[v];
    const double angle_deg =
        Eigen::AngleAxisd(r_pnp.transpose() * fit.r_camera_board).angle() * 180 / std::numbers::pi;
    const Eigen::Vector3d t_pnp(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
    EXPECT_LT(angle_deg, 0.05) << fit.name;
    EXPECT_LT((t_pnp - fit.t_camera_board_m).norm(), 1e-3 * t_pnp.norm()) << fit.name;
  }
}

// The views of one camera of OpenCV's stereo set ("left" or "right"), by file number.
std::vector<std::pair<int, IntrinsicView>> SampleViews(const std::string& camera, cv::Size* size) {
  std::vector<std::pair<int, IntrinsicView>> views;
  for (int i = 1; i <= 14; ++i) {
    std::ostringstream name;
    name << camera << std::setw(2) << std::setfill('0') << i << ".jpg";
    const cv::Mat grey = cv::imread((kData / name.str()).string(), cv::IMREAD_GRAYSCALE);
    if (grey.empty()) continue;  // left10.jpg is not shipped
    *size = grey.size();
    auto board = DetectChessboard(grey, {9, 6, 0.025});
    if (board) views.push_back({i, {name.str(), std::move(*board)}});
  }
  return views;
}

// Honest 1 sigma on real photos: each camera's views split into two disjoint halves two ways
// (odd and even file numbers; the first seven and the rest), each half calibrated on its own.
// Their difference in units of the 1 sigma each reports, z = (A - B) / sqrt(sA^2 + sB^2), is
// about N(0, 1) when the sigmas are honest: over fx fy cx cy of the 8 comparisons, RMS z at
// most 1.5 and no |z| above 3. The analytic z is printed beside each, for comparison, and
// where the halves put a ray against the projection 1 sigma they report.
TEST(OpenCvSamplesTest, HalvesAgreeWithinTheSigmaTheyReport) {
  if (!std::filesystem::exists(kData / "left01.jpg")) {
    GTEST_SKIP() << "OpenCV's sample photos are not installed (" << kData
                 << "/left01.jpg): install the Debian package opencv-doc (scripts/setup does)";
  }
  double sum_z2 = 0, max_z = 0, sum_analytic_z2 = 0;
  int count = 0;
  for (const std::string camera : {"left", "right"}) {
    cv::Size size;
    const auto views = SampleViews(camera, &size);
    ASSERT_GE(views.size(), 12u) << camera;
    using Split = std::function<bool(size_t order, int number)>;
    const std::vector<std::pair<std::string, Split>> splits = {
        {"odd/even", [](size_t, int number) { return number % 2 == 1; }},
        {"first 7/rest", [](size_t order, int) { return order < 7; }}};
    for (const auto& [split_name, in_first] : splits) {
      std::vector<IntrinsicView> a, b;
      for (size_t o = 0; o < views.size(); ++o)
        (in_first(o, views[o].first) ? a : b).push_back(views[o].second);
      const auto cal_a = CalibrateIntrinsics(a, size);
      const auto cal_b = CalibrateIntrinsics(b, size);
      ASSERT_TRUE(cal_a.ok() && cal_b.ok()) << camera << " " << split_name;
      const IntrinsicParams pa = IntrinsicParamsOf(cal_a->intrinsics);
      const IntrinsicParams pb = IntrinsicParamsOf(cal_b->intrinsics);
      std::cout << camera << ", " << split_name << " (" << a.size() << " + " << b.size()
                << " views; " << ToString(cal_a->model) << " / " << ToString(cal_b->model) << "):";
      for (int p = 0; p < 4; ++p) {
        const double sa = cal_a->Sigma()[p], sb = cal_b->Sigma()[p];
        const double z = (pa[p] - pb[p]) / std::hypot(sa, sb);
        const double analytic_z = (pa[p] - pb[p]) / std::sqrt(cal_a->analytic_covariance(p, p) +
                                                              cal_b->analytic_covariance(p, p));
        std::cout << "  " << kIntrinsicParamNames[p] << " " << std::fixed << std::setprecision(2)
                  << pa[p] - pb[p] << " px, z " << z << " (analytic " << analytic_z << ")";
        sum_z2 += z * z;
        sum_analytic_z2 += analytic_z * analytic_z;
        max_z = std::max(max_z, std::abs(z));
        ++count;
      }
      std::cout << "\n";
      // Where the halves put a ray, against the projection 1 sigma each reports.
      const auto projection = CompareProjections(cal_a->intrinsics, cal_a->covariance,
                                                 cal_b->intrinsics, cal_b->covariance);
      for (const auto& [how, f] : {std::pair{"absolute", projection.absolute},
                                   std::pair{"relative", projection.relative}}) {
        std::cout << "  projection, " << how << ": difference median " << f.median_difference_px
                  << " px, worst " << f.worst_difference_px << " px; z median " << f.median_z
                  << ", worst " << f.worst_z << "; " << std::setprecision(0)
                  << 100 * f.fraction_within_1_sigma << " % within 1 sigma\n"
                  << std::setprecision(2);
      }
      // A ray fixed in the camera: the halves' difference is mostly the principal point's,
      // which the widened 1 sigma covers (honest: median z 1.18).
      EXPECT_LE(projection.absolute.median_z, 3.0) << camera << " " << split_name;
    }
  }
  const double rms_z = std::sqrt(sum_z2 / count);
  std::cout << "RMS z " << rms_z << " (analytic alone " << std::sqrt(sum_analytic_z2 / count)
            << "), largest |z| " << max_z << "\n";
  EXPECT_LE(rms_z, 1.5);
  EXPECT_LE(max_z, 3.0);
}

// The leave-one-view-out fits behind the jackknife and the choice of lens model are one
// Gauss-Newton step from the full fit; on real photos, whose views disagree most, they must
// give what refitting each in full gives: the same model, the jackknife's 1 sigma of fx fy
// cx cy within 10 % and each model's held-out RMS within 3 %.
TEST(OpenCvSamplesTest, OneStepLeaveOutsAgreeWithRefitting) {
  if (!std::filesystem::exists(kData / "left01.jpg")) {
    GTEST_SKIP() << "OpenCV's sample photos are not installed (" << kData
                 << "/left01.jpg): install the Debian package opencv-doc (scripts/setup does)";
  }
  for (const std::string camera : {"left", "right"}) {
    cv::Size size;
    const auto numbered = SampleViews(camera, &size);
    std::vector<IntrinsicView> all, first;
    for (size_t o = 0; o < numbered.size(); ++o) {
      all.push_back(numbered[o].second);
      if (o < 7) first.push_back(numbered[o].second);
    }
    for (const auto* views : {&all, &first}) {
      IntrinsicCalibrationOptions exact;
      exact.exact_leave_outs = true;
      const auto one_step = CalibrateIntrinsics(*views, size);
      const auto refitted = CalibrateIntrinsics(*views, size, exact);
      ASSERT_TRUE(one_step.ok() && refitted.ok()) << camera;
      const std::string what = camera + ", " + std::to_string(views->size()) + " views";
      EXPECT_EQ(one_step->model, refitted->model)
          << what << ": " << one_step->model_reason << " / " << refitted->model_reason;
      std::cout << what << ": jackknife 1 sigma one step / refitted:";
      for (int p = 0; p < 4; ++p) {
        const double a = std::sqrt(one_step->jackknife_covariance(p, p));
        const double b = std::sqrt(refitted->jackknife_covariance(p, p));
        std::cout << "  " << kIntrinsicParamNames[p] << " " << a << " / " << b;
        EXPECT_NEAR(a, b, 0.10 * b) << what << " " << kIntrinsicParamNames[p];
      }
      std::cout << "\n";
      for (size_t m = 0; m < one_step->trials.size(); ++m) {
        EXPECT_NEAR(one_step->trials[m].held_out_rms_px, refitted->trials[m].held_out_rms_px,
                    0.03 * refitted->trials[m].held_out_rms_px)
            << what << " " << ToString(one_step->trials[m].model);
      }
    }
  }
}

}  // namespace
}  // namespace monocle
