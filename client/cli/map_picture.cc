#include "client/cli/map_picture.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <sstream>

namespace monocle::cli {
namespace {

constexpr int kMarginPx = 60;
constexpr int kLegendPx = 70;

void Text(cv::Mat& image, const std::string& text, cv::Point at, double size,
          const cv::Scalar& colour, int thickness = 1) {
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, size, colour, thickness, cv::LINE_AA);
}

std::vector<std::string> CornerIds(const RoomMap& map) {
  std::vector<std::string> ids;
  for (const auto& room : map.rooms)
    for (const auto& c : room.corners) ids.push_back(c.id);
  return ids;
}

void DrawArrow(cv::Mat& image, const MapPictureScale& s, const Eigen::Vector2d& from,
               const Eigen::Vector2d& to, const cv::Scalar& colour, int thickness) {
  cv::arrowedLine(image, s.ToPx(from), s.ToPx(to), colour, thickness, cv::LINE_AA, 0, 0.3);
}

}  // namespace

cv::Point MapPictureScale::ToPx(const Eigen::Vector2d& m) const {
  return cv::Point(static_cast<int>(std::lround(origin_px.x + m.x() * px_per_m)),
                   static_cast<int>(std::lround(origin_px.y - m.y() * px_per_m)));
}

cv::Scalar CornerColour(const RoomMap& map, const std::string& corner_id) {
  // Well separated hues (BGR), in the order the corners are listed.
  static const cv::Scalar kPalette[] = {{180, 119, 31},  {14, 127, 255},  {44, 160, 44},
                                        {40, 39, 214},   {189, 103, 148}, {75, 86, 140},
                                        {194, 119, 227}, {34, 189, 188},  {207, 190, 23}};
  const auto ids = CornerIds(map);
  const auto it = std::find(ids.begin(), ids.end(), corner_id);
  if (it == ids.end()) return {128, 128, 128};
  return kPalette[(it - ids.begin()) % std::size(kPalette)];
}

namespace {

// A 1 m grid with its coordinates, under everything; the rooms over it.
void DrawGridAndRooms(const RoomMap& map, const MapPictureScale& s, const Eigen::Vector2d& lo,
                      const Eigen::Vector2d& hi, cv::Mat& image) {
  for (double x = std::ceil(lo.x()); x <= hi.x(); x += 1) {
    cv::line(image, s.ToPx({x, lo.y()}), s.ToPx({x, hi.y()}), {235, 235, 235}, 1);
    Text(image, std::to_string(static_cast<int>(x)), s.ToPx({x, lo.y()}) + cv::Point(-4, 18), 0.45,
         {120, 120, 120});
  }
  for (double y = std::ceil(lo.y()); y <= hi.y(); y += 1) {
    cv::line(image, s.ToPx({lo.x(), y}), s.ToPx({hi.x(), y}), {235, 235, 235}, 1);
    Text(image, std::to_string(static_cast<int>(y)), s.ToPx({lo.x(), y}) + cv::Point(-24, 5), 0.45,
         {120, 120, 120});
  }
  // Rooms: floor light grey, walls dark; the room's id and ceiling height inside.
  for (const auto& room : map.rooms) {
    std::vector<cv::Point> polygon;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const auto& p : room.outline_m) {
      polygon.push_back(s.ToPx(p));
      centre += p;
    }
    centre /= static_cast<double>(room.outline_m.size());
    cv::fillPoly(image, std::vector<std::vector<cv::Point>>{polygon}, {236, 236, 236}, cv::LINE_AA);
    cv::polylines(image, polygon, true, {60, 60, 60}, 3, cv::LINE_AA);
    std::ostringstream label;
    label << room.id << "  ceiling " << std::fixed << std::setprecision(2) << room.ceiling_height_m
          << " m";
    // At the outline's vertex mean, moved inside if the room bends round it.
    Eigen::Vector2d at = centre;
    if (!InsideOutline(room.outline_m, at)) at = room.outline_m.front() + Eigen::Vector2d(0.6, 0.9);
    Text(image, label.str(), s.ToPx(at) + cv::Point(-60, 0), 0.5, {90, 90, 90});
  }
}

}  // namespace

cv::Mat DrawMapPicture(const MapPicture& picture, MapPictureScale* scale_out) {
  const RoomMap& map = *picture.map;
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const auto& room : map.rooms) {
    for (const auto& p : room.outline_m) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  for (const auto& b : picture.trajectory) {
    lo = lo.cwiseMin(Eigen::Vector2d(b.x_m, b.y_m));
    hi = hi.cwiseMax(Eigen::Vector2d(b.x_m, b.y_m));
  }
  lo.array() -= 0.5;
  hi.array() += 0.5;
  const Eigen::Vector2d extent = hi - lo;
  MapPictureScale s;
  s.px_per_m = std::max(40.0, std::min(1400 / extent.x(), 1000 / extent.y()));
  const int width = static_cast<int>(std::ceil(extent.x() * s.px_per_m)) + 2 * kMarginPx;
  const int height =
      static_cast<int>(std::ceil(extent.y() * s.px_per_m)) + 2 * kMarginPx + kLegendPx;
  s.origin_px =
      cv::Point2d(kMarginPx - lo.x() * s.px_per_m, kLegendPx + kMarginPx + hi.y() * s.px_per_m);
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));

  DrawGridAndRooms(map, s, lo, hi, image);
  // Corners: a ring in the corner's colour, its two ceiling edges (X, Y) as short arrows.
  for (const auto& room : map.rooms) {
    for (const auto& c : room.corners) {
      const cv::Scalar colour = CornerColour(map, c.id);
      DrawArrow(image, s, c.position_m, c.position_m + 0.45 * c.x_edge, colour, 2);
      DrawArrow(image, s, c.position_m, c.position_m + 0.45 * c.y_edge, colour, 2);
      cv::circle(image, s.ToPx(c.position_m), 7, colour, 2, cv::LINE_AA);
      const Eigen::Vector2d inward = (c.x_edge + c.y_edge).normalized();
      Text(image, c.id, s.ToPx(c.position_m + 0.55 * inward) + cv::Point(-20, 5), 0.5, colour, 2);
    }
  }
  // The true trajectory: a black path, the heading every few poses.
  for (size_t i = 0; i + 1 < picture.trajectory.size(); ++i) {
    const auto& a = picture.trajectory[i];
    const auto& b = picture.trajectory[i + 1];
    cv::line(image, s.ToPx({a.x_m, a.y_m}), s.ToPx({b.x_m, b.y_m}), {0, 0, 0}, 2, cv::LINE_AA);
  }
  for (const auto& b : picture.trajectory) {
    const Eigen::Vector2d p(b.x_m, b.y_m);
    const Eigen::Vector2d ahead(std::cos(b.heading_rad), std::sin(b.heading_rad));
    cv::line(image, s.ToPx(p), s.ToPx(p + 0.15 * ahead), {0, 0, 0}, 1, cv::LINE_AA);
  }
  // Candidates of views the map could not decide: hollow grey rings.
  for (const auto& l : picture.poses) {
    for (const auto& c : l.candidates())
      cv::circle(image, s.ToPx({c.x(), c.y()}), 6, {150, 150, 150}, 1, cv::LINE_AA);
  }
  // Located poses: a dot in the colour of the corner it was measured from, a thin line to that
  // corner, and its heading.
  for (const auto& l : picture.poses) {
    if (!l.has_pose()) continue;
    const auto& p = l.pose();
    const cv::Scalar colour = CornerColour(map, p.corner());
    const Eigen::Vector2d at(p.x(), p.y());
    const double heading = p.heading_deg() * std::numbers::pi / 180;
    for (const auto& room : map.rooms)
      for (const auto& c : room.corners)
        if (c.id == p.corner()) cv::line(image, s.ToPx(at), s.ToPx(c.position_m), colour, 1);
    cv::line(image, s.ToPx(at),
             s.ToPx(at + 0.25 * Eigen::Vector2d(std::cos(heading), std::sin(heading))), colour, 2,
             cv::LINE_AA);
    cv::circle(image, s.ToPx(at), 5, colour, cv::FILLED, cv::LINE_AA);
  }
  // Legend.
  int located = 0, undecided = 0;
  for (const auto& l : picture.poses) (l.has_pose() ? located : undecided) += 1;
  std::ostringstream title;
  title << picture.title << "   (map frame: x right, y up, metres; grid 1 m)";
  Text(image, title.str(), {14, 26}, 0.6, {0, 0, 0}, 1);
  std::ostringstream legend;
  if (!picture.trajectory.empty())
    legend << "black: true path (" << picture.trajectory.size() << " poses)   ";
  if (!picture.poses.empty()) {
    legend << "dots: " << located << " located poses, coloured by the corner they were measured "
           << "from (thin line to it)";
    if (undecided > 0) legend << "; grey rings: candidates of " << undecided << " undecided views";
  }
  legend << (legend.tellp() > 0 ? "   " : "") << "arrows: each corner's X and Y ceiling edges";
  Text(image, legend.str(), {14, 52}, 0.45, {60, 60, 60}, 1);
  if (scale_out != nullptr) *scale_out = s;
  return image;
}

}  // namespace monocle::cli
