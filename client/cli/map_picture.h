// `monocle map draw`: the map from above (map frame, x right, y up), its rooms and ceiling
// corners, a true trajectory and the poses `corner locate --map` found, each joined to the
// corner it was measured from. Pure drawing: the caller reads the files.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "idl/cli_output.pb.h"
#include "service/geometry/map_pose.h"
#include "service/geometry/room_map.h"

namespace monocle::cli {

struct MapPicture {
  const RoomMap* map = nullptr;
  std::vector<BasePose2d> trajectory;           // ground truth, drawn as a black path
  std::vector<proto::MapLocationOutput> poses;  // `corner locate --map --json`'s "map" objects
  std::string title;                            // e.g. the map file's name
};

struct MapPictureScale {
  double px_per_m = 0;
  cv::Point2d origin_px;  // where map (0, 0) falls
  cv::Point ToPx(const Eigen::Vector2d& map_m) const;
};

// The colour the picture gives a corner: the same for its poses and their lines to it.
cv::Scalar CornerColour(const RoomMap& map, const std::string& corner_id);

// About 1400 x 1000 pixels for the map's extent (at least 40 px per metre); `scale` says where
// map points fall (for tests, and for users who want to mark the picture further).
cv::Mat DrawMapPicture(const MapPicture& picture, MapPictureScale* scale = nullptr);

}  // namespace monocle::cli
