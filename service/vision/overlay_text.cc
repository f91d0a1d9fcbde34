#include "service/vision/overlay_text.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace monocle {

void PutOutlinedText(cv::Mat& image, const std::string& text, cv::Point at, double scale,
                     const cv::Scalar& colour, int thickness) {
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), thickness + 3,
              cv::LINE_AA);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, thickness, cv::LINE_AA);
}

int PutWrappedText(cv::Mat& image, const std::string& text, cv::Point at, double scale,
                   const cv::Scalar& colour, int thickness) {
  const int max_width = std::max(image.cols - 2 * at.x, 40);
  int baseline = 0;
  auto width = [&](const std::string& s) {
    return cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, scale, thickness + 3, &baseline).width;
  };
  const int line_height = static_cast<int>(
      1.5 *
      cv::getTextSize("Ag", cv::FONT_HERSHEY_SIMPLEX, scale, thickness + 3, &baseline).height);
  std::string line;
  for (size_t start = 0; start <= text.size();) {
    size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    const std::string longer = line.empty() ? word : line + " " + word;
    if (!line.empty() && width(longer) > max_width) {
      PutOutlinedText(image, line, at, scale, colour, thickness);
      at.y += line_height;
      line = word;
    } else {
      line = longer;
    }
    start = end + 1;
  }
  if (!line.empty()) {
    PutOutlinedText(image, line, at, scale, colour, thickness);
    at.y += line_height;
  }
  return at.y;
}

}  // namespace monocle
