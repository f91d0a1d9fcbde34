// The corner detector's third stage: Y junctions, three segments whose lines meet near one
// point, each running away from it, at angles a ceiling corner can make.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "service/vision/hough_segments.h"

namespace monocle::corner_detection {

// The angle between two unit vectors, radians.
double AngleBetween(const Eigen::Vector2d& a, const Eigen::Vector2d& b);

struct YTriple {
  std::array<int, 3> segment{};
  Eigen::Vector2d corner;
  std::array<Eigen::Vector2d, 3> direction;
  double score = -1;
};

// The paper's identification of the corner lines: the three lines passing close to one
// point (the paper asks the pairwise intersections to be close together), each segment ending near
// them and running away from them, and every angle between the three rays above 90 degrees (we
// allow 80 for lens distortion and the half-resolution Hough). Among the triples that pass, the
// most supported comes first; edges that run to the image border (the paper's check 3) count extra.
std::vector<YTriple> FindYCandidates(const std::vector<Segment>& segments, int w, int h,
                                     double junction_radius);

}  // namespace monocle::corner_detection
