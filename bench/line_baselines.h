// The line finders a user might reach for instead of monocle's corner detector, run the way
// their documentation shows, single-threaded: OpenCV Canny + HoughLines, and OpenCV contrib's
// (ximgproc) FastLineDetector and EdgeDrawing lines. They find lines or segments, not a corner
// or a pose: they are a floor on what finding the edges costs. For corner_bench (in-process)
// and the line_baseline program (whole processes).
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_drawing.hpp>
#include <opencv2/ximgproc/fast_line_detector.hpp>
#include <optional>
#include <string>
#include <vector>

namespace monocle::bench {

enum class LineMethod { kCannyHough, kFastLineDetector, kEdgeDrawing };

inline std::optional<LineMethod> ParseLineMethod(const std::string& name) {
  if (name == "canny-hough") return LineMethod::kCannyHough;
  if (name == "fld") return LineMethod::kFastLineDetector;
  if (name == "edge-drawing") return LineMethod::kEdgeDrawing;
  return std::nullopt;
}

inline const char* LineMethodName(LineMethod method) {
  switch (method) {
    case LineMethod::kCannyHough:
      return "Canny + HoughLines";
    case LineMethod::kFastLineDetector:
      return "FastLineDetector";
    case LineMethod::kEdgeDrawing:
      return "EdgeDrawing lines";
  }
  return "?";
}

struct CannyHoughSettings {  // Canny's thresholds and HoughLines' votes
  double low = 50, high = 150;
  int votes = 150;
};

// One finder, made once and run on many images (as a program would).
class LineFinder {
 public:
  explicit LineFinder(LineMethod method, CannyHoughSettings canny_hough = {})
      : method_(method), canny_hough_(canny_hough) {
    if (method == LineMethod::kFastLineDetector) fld_ = cv::ximgproc::createFastLineDetector();
    if (method == LineMethod::kEdgeDrawing) edge_drawing_ = cv::ximgproc::createEdgeDrawing();
  }

  // How many lines (Hough) or segments the image gives.
  size_t Find(const cv::Mat& grey) {
    switch (method_) {
      case LineMethod::kCannyHough:
        cv::Canny(grey, edges_, canny_hough_.low, canny_hough_.high);
        cv::HoughLines(edges_, lines_, 1, CV_PI / 360, canny_hough_.votes);
        return lines_.size();
      case LineMethod::kFastLineDetector:
        fld_->detect(grey, segments_);
        return segments_.size();
      case LineMethod::kEdgeDrawing:
        edge_drawing_->detectEdges(grey);
        edge_drawing_->detectLines(segments_);
        return segments_.size();
    }
    return 0;
  }
  const std::vector<cv::Vec2f>& hough_lines() const { return lines_; }

 private:
  LineMethod method_;
  CannyHoughSettings canny_hough_;
  cv::Ptr<cv::ximgproc::FastLineDetector> fld_;
  cv::Ptr<cv::ximgproc::EdgeDrawing> edge_drawing_;
  cv::Mat edges_;
  std::vector<cv::Vec2f> lines_;
  std::vector<cv::Vec4f> segments_;
};

}  // namespace monocle::bench
