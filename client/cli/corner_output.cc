#include "client/cli/corner_output.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "service/io/image_codec.h"
#include "service/vision/corner_detector.h"
#include "service/vision/corner_rays.h"
#include "service/vision/corner_tracker.h"
#include "service/vision/overlay_text.h"

namespace monocle::cli {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

}  // namespace

const char* kAxisName[3] = {"X", "Y", "Z"};

namespace {

cv::Point Pt(const Eigen::Vector2d& p) {
  return cv::Point(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
}

}  // namespace

cv::Mat DrawCornerOverlay(const cv::Mat& grey, const CameraIntrinsics& intrinsics,
                          const Result<CornerLocation>& result) {
  cv::Mat color;
  cv::cvtColor(grey, color, cv::COLOR_GRAY2BGR);
  std::string text;
  const cv::Scalar colors[3] = {cv::Scalar(0, 0, 255), cv::Scalar(0, 200, 0),
                                cv::Scalar(255, 0, 0)};
  // Lighter versions for text on its black outline.
  const cv::Scalar label_colors[3] = {cv::Scalar(110, 110, 255), cv::Scalar(110, 255, 110),
                                      cv::Scalar(255, 190, 110)};
  if (result) {
    // What the detector saw: its straight segments.
    for (const auto& s : result->edges.hough_segments)
      cv::line(color, Pt(s.a_px), Pt(s.b_px), cv::Scalar(0, 200, 255), 1, cv::LINE_AA);
    // What was measured: each edge as far as it was found, with its support beside it.
    for (int a = 0; a < 3; ++a) {
      cv::line(color, Pt(result->corner_px), Pt(result->line_end_px[a]), colors[a], 2, cv::LINE_AA);
      const EdgeSupport& s = result->support[a];
      std::ostringstream label;
      label << std::fixed << kAxisName[a] << " " << std::setprecision(0) << s.length_px << " px "
            << std::setprecision(0) << s.coverage * 100 << "%, " << std::setprecision(1)
            << s.contrast_to_noise << "x noise, misfit " << std::setprecision(2) << s.misfit_px
            << " px";
      // Below it, how much of the position's uncertainty this edge gives.
      std::ostringstream share;
      share << std::fixed << std::setprecision(0) << s.position_variance_share * 100
            << "% of the position's variance";
      // At 60 % along the measured edge, pulled inside the picture.
      Eigen::Vector2d at = result->corner_px + 0.6 * (result->line_end_px[a] - result->corner_px);
      at.x() = std::clamp(at.x() + 10, 4.0, std::max(4.0, color.cols - 420.0));
      at.y() = std::clamp(at.y(), 110.0, std::max(110.0, color.rows - 60.0));
      PutOutlinedText(color, label.str(), Pt(at), 0.55, label_colors[a], 1);
      PutOutlinedText(color, share.str(), Pt(at + Eigen::Vector2d(0, 20)), 0.55, label_colors[a],
                      1);
    }
    // What the pose predicts: each axis through the lens, to the border, drawn over the
    // measured edges (thin white): where the two part, the edges do not agree with the pose.
    for (int a = 0; a < 3; ++a) {
      std::vector<cv::Point> curve{Pt(result->corner_px)};
      for (const auto& p : PredictEdgePx(intrinsics, result->pose, a, 4)) curve.push_back(Pt(p));
      cv::polylines(color, curve, false, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    }
    // The strongest other edge leaving the corner, as far as the rings read it: where it is
    // what flagged the pose, a person sees the edge that was lost.
    if (result->other_edge_flagged) {
      const Eigen::Vector2d end =
          OtherEdgeTowardsPx(result->corner_px, result->other_edge_angle_rad, 96);
      cv::line(color, Pt(result->corner_px), Pt(end), cv::Scalar(255, 0, 255), 3, cv::LINE_AA);
      std::ostringstream label;
      label << std::fixed << std::setprecision(0) << "another edge, "
            << result->other_edge_step_grey << " grey";
      PutOutlinedText(color, label.str(), Pt(end + Eigen::Vector2d(6, 0)), 0.55,
                      cv::Scalar(255, 120, 255), 1);
    }
    cv::circle(color, Pt(result->corner_px), 8, cv::Scalar(0, 255, 255), 2, cv::LINE_AA);
    std::ostringstream os;
    os << std::fixed << std::setprecision(3) << "x " << result->pose.x_m << " y "
       << result->pose.y_m << " z " << result->pose.z_m << " m  pan " << std::setprecision(2)
       << result->pose.pan_rad * kDeg << " tilt " << result->pose.tilt_rad * kDeg << " swing "
       << result->pose.swing_rad * kDeg << " deg";
    text = os.str();
  } else {
    // No pose: the straight edges the detector saw, to look at beside its reason (which
    // counts them: "3 straight edges found; 2 meet at ...").
    for (const auto& s : DetectStraightEdges(grey, {}, &intrinsics))
      cv::line(color, Pt(s.a_px), Pt(s.b_px), cv::Scalar(0, 200, 255), 2, cv::LINE_AA);
    PutOutlinedText(color, "orange: straight segments seen", cv::Point(12, color.rows - 14), 0.5,
                    cv::Scalar(255, 255, 255), 1);
    text = result.error().message;
  }
  int y = PutWrappedText(color, text, cv::Point(12, 32), 0.8, cv::Scalar(0, 255, 255), 2);
  if (result) {
    // Second line: where the pose came from and the image's noise.
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << ToString(result->source) << "  noise "
       << result->noise_sigma_grey << " grey  rms " << std::setprecision(2) << result->rms_px
       << " px";
    y = PutWrappedText(color, os.str(), cv::Point(12, y), 0.6, cv::Scalar(0, 255, 255), 1);
    if (result->suspect) {
      PutWrappedText(color, "SUSPECT: " + result->suspect_reason, cv::Point(12, y), 0.6,
                     cv::Scalar(0, 0, 255), 2);
    }
    PutOutlinedText(color,
                    std::string("thick: edges measured (as far as found)   thin white: edges the "
                                "pose predicts   orange: straight segments seen") +
                        (result->other_edge_flagged ? "   magenta: another edge" : ""),
                    cv::Point(12, color.rows - 14), 0.5, cv::Scalar(255, 255, 255), 1);
  }
  return color;
}

void WriteCornerOverlay(const std::string& dir, const std::string& image_path, const cv::Mat& grey,
                        const CameraIntrinsics& intrinsics, const Result<CornerLocation>& result) {
  const std::string out = (std::filesystem::path(dir) /
                           (std::filesystem::path(image_path).stem().string() + ".overlay.png"))
                              .string();
  if (const auto written = WriteImageFile(out, DrawCornerOverlay(grey, intrinsics, result));
      !written)
    std::cerr << "monocle: warning: cannot write overlay: " << written.error().message << "\n";
}

proto::CornerOutput ToCornerOutput(const std::string& image, const Result<CornerLocation>& r) {
  proto::CornerOutput out;
  out.set_image(image);
  if (!r) {
    out.set_error(r.error().message);
    return out;
  }
  const auto& p = r->pose;
  out.set_x(p.x_m);
  out.set_y(p.y_m);
  out.set_z(p.z_m);
  out.set_pan(p.pan_rad);
  out.set_tilt(p.tilt_rad);
  out.set_swing(p.swing_rad);
  for (double v : {r->q_corner_camera.w(), r->q_corner_camera.x(), r->q_corner_camera.y(),
                   r->q_corner_camera.z()})
    out.add_quaternion(v);
  out.add_corner_px(r->corner_px.x());
  out.add_corner_px(r->corner_px.y());
  out.set_rms_px(r->rms_px);
  const auto s = r->Sigma();
  out.mutable_sigma()->set_x(s[0]);
  out.mutable_sigma()->set_y(s[1]);
  out.mutable_sigma()->set_pan(s[2]);
  out.mutable_sigma()->set_tilt(s[3]);
  out.mutable_sigma()->set_swing(s[4]);
  out.set_sigma_excludes_intrinsics(!r->sigma_includes_intrinsics);
  for (int a = 0; a < 3; ++a) {
    auto* line = out.add_lines();
    line->set_axis(kAxisName[a]);
    line->add_from_px(r->corner_px.x());
    line->add_from_px(r->corner_px.y());
    line->add_to_px(r->line_end_px[a].x());
    line->add_to_px(r->line_end_px[a].y());
    line->set_points(r->points_per_line[a]);
    const EdgeSupport& s = r->support[a];
    line->set_length_px(s.length_px);
    line->set_visible_length_px(s.visible_length_px);
    line->set_coverage(s.coverage);
    line->set_contrast_grey(s.contrast_grey);
    line->set_contrast_to_noise(s.contrast_to_noise);
    line->set_edge_rms_px(s.rms_px);
    line->set_sigma_px(s.sigma_px);
    line->set_misfit_px(s.misfit_px);
    line->set_position_variance_share(s.position_variance_share);
  }
  out.set_source(ToString(r->source));
  out.set_suspect(r->suspect);
  if (r->suspect) out.set_suspect_reason(r->suspect_reason);
  out.set_noise_grey(r->noise_sigma_grey);
  if (r->edges.detection_scale > 0) out.set_detection_scale(r->edges.detection_scale);
  if (r->other_edge_step_grey > 0) {
    out.set_other_edge_step_grey(r->other_edge_step_grey);
    const Eigen::Vector2d towards = OtherEdgeTowardsPx(r->corner_px, r->other_edge_angle_rad);
    out.add_other_edge_towards_px(towards.x());
    out.add_other_edge_towards_px(towards.y());
  }
  if (r->edges_measured_again) out.set_measured_again(true);
  if (r->shading_shift.squaredNorm() > 0) {
    out.add_shading_shift_m(r->shading_shift[0]);
    out.add_shading_shift_m(r->shading_shift[1]);
  }
  if (r->level_error_rad) {
    out.set_level_error_deg(*r->level_error_rad * 180 / std::numbers::pi);
    out.set_level_sigma_deg(r->level_sigma_rad * 180 / std::numbers::pi);
  }
  if (r->base) {
    const RigidTransform& b = r->base->corner_base;
    std::array<double, 9> covariance;
    for (int i = 0; i < 9; ++i)
      covariance[static_cast<size_t>(i)] = r->base->covariance(i / 3, i % 3);
    *out.mutable_base() =
        ToBaseOutput({b.translation.x(), b.translation.y(), b.translation.z()},
                     {b.rotation.w(), b.rotation.x(), b.rotation.y(), b.rotation.z()},
                     r->base->heading_rad, covariance);
  }
  return out;
}

proto::BasePoseOutput ToBaseOutput(const std::array<double, 3>& position_m,
                                   const std::array<double, 4>& quaternion_wxyz, double heading_rad,
                                   const std::array<double, 9>& covariance) {
  proto::BasePoseOutput out;
  out.set_x(position_m[0]);
  out.set_y(position_m[1]);
  out.set_z(position_m[2]);
  out.set_heading_deg(heading_rad * kDeg);
  out.mutable_sigma()->set_x(std::sqrt(covariance[0]));
  out.mutable_sigma()->set_y(std::sqrt(covariance[4]));
  out.mutable_sigma()->set_heading_deg(std::sqrt(covariance[8]) * kDeg);
  for (double c : covariance) out.add_covariance(c);
  for (double q : quaternion_wxyz) out.add_quaternion(q);
  return out;
}

std::string BaseText(const proto::BasePoseOutput& base) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(4) << "  base x=" << base.x() << " y=" << base.y()
     << " m heading=" << std::setprecision(2) << base.heading_deg() << " deg  (1σ "
     << std::setprecision(4) << base.sigma().x() << " " << base.sigma().y() << " m, "
     << std::setprecision(2) << base.sigma().heading_deg() << " deg)";
  return os.str();
}

std::string CornerResultLine(const std::string& label, const CornerLocation& result) {
  const auto& p = result.pose;
  const auto s = result.Sigma();
  std::ostringstream os;
  os << std::fixed << std::setprecision(4) << label << "  x=" << p.x_m << " y=" << p.y_m
     << " z=" << p.z_m << " m  pan=" << p.pan_rad << " tilt=" << p.tilt_rad
     << " swing=" << p.swing_rad << " rad  (1σ " << s[0] << " " << s[1] << " m, " << s[2] << " "
     << s[3] << " " << s[4] << " rad)  corner " << std::setprecision(1) << result.corner_px.x()
     << "," << result.corner_px.y() << " px  rms " << std::setprecision(3) << result.rms_px
     << " px  " << ToString(result.source);
  if (result.level_error_rad) {
    os << std::setprecision(2) << "  level " << *result.level_error_rad * 180 / std::numbers::pi
       << " deg off as solved (1σ " << result.level_sigma_rad * 180 / std::numbers::pi << " deg)";
  }
  if (result.base) os << BaseText(ToCornerOutput("", result).base());
  if (result.suspect) os << "  SUSPECT: " << result.suspect_reason;
  return os.str();
}

}  // namespace monocle::cli
