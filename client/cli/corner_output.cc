#include "client/cli/corner_output.h"

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace monocle::cli {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

}  // namespace

const char* kAxisName[3] = {"X", "Y", "Z"};

void WriteCornerOverlay(const std::string& dir, const std::string& image_path, const cv::Mat& grey,
                        const Result<CornerLocation>& result) {
  cv::Mat color;
  cv::cvtColor(grey, color, cv::COLOR_GRAY2BGR);
  auto pt = [](const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
  };
  std::string text;
  if (result) {
    for (const auto& s : result->edges.hough_segments)
      cv::line(color, pt(s.a_px), pt(s.b_px), cv::Scalar(0, 200, 255), 1, cv::LINE_AA);
    const cv::Scalar colors[3] = {cv::Scalar(0, 0, 255), cv::Scalar(0, 200, 0),
                                  cv::Scalar(255, 0, 0)};
    for (int a = 0; a < 3; ++a) {
      cv::line(color, pt(result->corner_px), pt(result->line_end_px[a]), colors[a], 2, cv::LINE_AA);
      cv::putText(color, kAxisName[a],
                  pt(result->line_end_px[a] + 0.1 * (result->corner_px - result->line_end_px[a])),
                  cv::FONT_HERSHEY_SIMPLEX, 1.0, colors[a], 2);
    }
    cv::circle(color, pt(result->corner_px), 8, cv::Scalar(0, 255, 255), 2, cv::LINE_AA);
    std::ostringstream os;
    os << std::fixed << std::setprecision(3) << "x " << result->pose.x_m << " y "
       << result->pose.y_m << " z " << result->pose.z_m << " m  pan " << std::setprecision(2)
       << result->pose.pan_rad * kDeg << " tilt " << result->pose.tilt_rad * kDeg << " swing "
       << result->pose.swing_rad * kDeg << " deg";
    text = os.str();
  } else {
    text = result.error().message;
  }
  cv::putText(color, text, cv::Point(12, 32), cv::FONT_HERSHEY_SIMPLEX, 0.8, cv::Scalar(0, 0, 0),
              4);
  cv::putText(color, text, cv::Point(12, 32), cv::FONT_HERSHEY_SIMPLEX, 0.8,
              cv::Scalar(0, 255, 255), 2);
  if (result) {
    // Second line: where the pose came from and how well each edge supports it.
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << ToString(result->source) << "  noise "
       << result->noise_sigma_grey << " grey";
    for (int a = 0; a < 3; ++a) {
      const auto& s = result->support[a];
      os << "  " << kAxisName[a] << ": " << std::setprecision(0) << s.length_px << " px, "
         << std::setprecision(1) << s.contrast_to_noise << "x noise";
    }
    cv::putText(color, os.str(), cv::Point(12, 64), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(0, 0, 0), 4);
    cv::putText(color, os.str(), cv::Point(12, 64), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(0, 255, 255), 1);
    if (result->suspect) {
      const std::string warning = "SUSPECT: " + result->suspect_reason;
      cv::putText(color, warning, cv::Point(12, 92), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                  cv::Scalar(0, 0, 0), 4);
      cv::putText(color, warning, cv::Point(12, 92), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                  cv::Scalar(0, 0, 255), 2);
    }
  }
  const std::string out = (std::filesystem::path(dir) /
                           (std::filesystem::path(image_path).stem().string() + ".overlay.png"))
                              .string();
  if (!cv::imwrite(out, color))
    std::cerr << "monocle: warning: cannot write overlay " << out << "\n";
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
  }
  out.set_source(ToString(r->source));
  out.set_suspect(r->suspect);
  if (r->suspect) out.set_suspect_reason(r->suspect_reason);
  out.set_noise_grey(r->noise_sigma_grey);
  return out;
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
  if (result.suspect) os << "  SUSPECT: " << result.suspect_reason;
  return os.str();
}

}  // namespace monocle::cli
