#include "client/cli/uncertainty_picture.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>

namespace monocle::cli {
namespace {

void Label(cv::Mat& image, const std::string& text, cv::Point at, double scale = 0.5) {
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), 3,
              cv::LINE_AA);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
}

std::string Px(double value) {
  std::ostringstream os;
  os << std::setprecision(value < 0.1 ? 1 : 2) << value;
  return os.str();
}

uint8_t Level(double sigma_px, const UncertaintyScale& scale) {
  if (!std::isfinite(sigma_px)) return 255;
  const double fraction = std::log(std::max(sigma_px, scale.bottom_px) / scale.bottom_px) /
                          std::log(scale.top_px / scale.bottom_px);
  return static_cast<uint8_t>(std::lround(255 * std::clamp(fraction, 0.0, 1.0)));
}

cv::Vec3b Viridis(uint8_t level) {
  cv::Mat grey(1, 1, CV_8U, cv::Scalar(level));
  cv::Mat colour;
  cv::applyColorMap(grey, colour, cv::COLORMAP_VIRIDIS);
  return colour.at<cv::Vec3b>(0, 0);
}

// A vertical bar at the right edge: the colours from the bottom of the scale to its top, with
// ticks at 1, 2 and 5 times powers of ten.
void DrawScale(cv::Mat& image, const UncertaintyScale& scale) {
  const int x = image.cols - 34, y0 = 60, y1 = image.rows - 40;
  if (y1 - y0 < 60) return;
  for (int y = y0; y <= y1; ++y) {
    const cv::Vec3b c = Viridis(static_cast<uint8_t>(std::lround(255.0 * (y1 - y) / (y1 - y0))));
    cv::line(image, {x, y}, {x + 14, y}, cv::Scalar(c[0], c[1], c[2]));
  }
  cv::rectangle(image, {x, y0}, {x + 14, y1}, cv::Scalar(255, 255, 255));
  for (double decade = scale.bottom_px; decade <= scale.top_px * 1.0001; decade *= 10) {
    for (const double step : {1.0, 2.0, 5.0}) {
      const double tick = decade * step;
      if (tick > scale.top_px * 1.0001) break;
      const int y = y1 - static_cast<int>(std::lround(Level(tick, scale) / 255.0 * (y1 - y0)));
      cv::line(image, {x - 4, y}, {x, y}, cv::Scalar(255, 255, 255));
      if (step != 2.0) Label(image, Px(tick), {x - 44, y + 5}, 0.4);
    }
  }
  Label(image, "px", {x - 2, y1 + 18}, 0.45);
}

}  // namespace

UncertaintyScale UncertaintyScaleOf(const ProjectionUncertaintyMap& map) {
  const double worst = std::max(map.relative.worst_px, 1e-6);
  const double decade = std::pow(10.0, std::floor(std::log10(worst)));
  double top = 10 * decade;
  for (const double step : {1.0, 2.0, 5.0}) {
    if (worst <= step * decade) {
      top = step * decade;
      break;
    }
  }
  // Two decades below the top, starting at a power of ten so that the ticks fall on 1-2-5.
  const double bottom = std::pow(10.0, std::floor(std::log10(top / 100)));
  return {bottom, top};
}

cv::Vec3b UncertaintyColour(double sigma_px, const UncertaintyScale& scale) {
  return Viridis(Level(sigma_px, scale));
}

cv::Mat ProjectionUncertaintyPicture(const ProjectionUncertaintyMap& map, const cv::Size& size,
                                     const std::vector<IntrinsicView>& views) {
  const UncertaintyScale scale = UncertaintyScaleOf(map);
  cv::Mat levels(map.rows, map.cols, CV_8U);
  for (int r = 0; r < map.rows; ++r)
    for (int c = 0; c < map.cols; ++c)
      levels.at<uint8_t>(r, c) = Level(map.RelativeAt(c, r), scale);
  // Cells are centred at (c + 0.5) step: scaled by the step, the grid covers the image.
  cv::Mat smooth;
  cv::resize(levels, smooth,
             cv::Size(static_cast<int>(std::lround(map.cols * map.step_px)),
                      static_cast<int>(std::lround(map.rows * map.step_px))),
             0, 0, cv::INTER_LINEAR);
  cv::Mat picture;
  cv::applyColorMap(smooth(cv::Rect({0, 0}, size)), picture, cv::COLORMAP_VIRIDIS);
  for (const auto& view : views) {
    for (const auto& px : view.board.pixels) {
      cv::circle(picture,
                 {static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y()))}, 1,
                 cv::Scalar(255, 255, 255), cv::FILLED);
    }
  }
  const cv::Point worst(static_cast<int>(map.relative.worst_at_px.x()),
                        static_cast<int>(map.relative.worst_at_px.y()));
  cv::circle(picture, worst, 12, cv::Scalar(0, 0, 255), 2, cv::LINE_AA);
  DrawScale(picture, scale);
  Label(picture,
        "1 sigma where a ray lands: median " + Px(map.relative.median_px) + " px, worst " +
            Px(map.relative.worst_px) + " px (red circle)",
        {10, 22});
  Label(picture,
        "(best camera rotation taken out; fixed in the camera: median " +
            Px(map.absolute.median_px) + " px)",
        {10, 42}, 0.4);
  Label(picture, "white dots: corners the views covered; hold the board where it is yellow",
        {10, size.height - 12}, 0.45);
  return picture;
}

}  // namespace monocle::cli
