// The corner detector's second stage: a Hough transform in (angle, rho) over the thinned
// edges, each voting near its own gradient's direction, and the contiguous segments of each
// peak's line.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "service/vision/edge_thinning.h"

namespace monocle::corner_detection {

// A line x cos(a) + y sin(a) = rho at half resolution, with the supporting span.
struct Segment {
  int line = 0;  // Hough peak it came from
  Eigen::Vector2d normal, direction;
  double rho = 0;
  double t0 = 0, t1 = 0;  // span along `direction`
  int support = 0;
  Eigen::Vector2d End(int i) const { return rho * normal + (i ? t1 : t0) * direction; }
};

struct HoughPeak {
  int angle_bin, rho_bin, votes;
};

// Hough transform in (alpha, rho), each edge voting only near its gradient's direction;
// peaks of the smoothed counts H'(a, r) = H(a, r - 1) + H(a, r) + H(a, r + 1).
std::vector<HoughPeak> HoughPeaks(const std::vector<EdgePixel>& edges, int w, int h, int min_votes,
                                  int max_peaks);

// Splits the edge pixels supporting a Hough line into contiguous segments.
void SegmentsOfLine(const std::vector<const EdgePixel*>& edges, int line, double alpha, double rho,
                    double min_length, std::vector<Segment>* out);

}  // namespace monocle::corner_detection
