#include "service/vision/corner_detector.h"

#include "service/geometry/undistortion_grid.h"
#include "service/vision/edge_tracing.h"
#include "service/vision/halve_image.h"
#include "service/vision/order_statistics.h"
#include "service/vision/y_junctions.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <tuple>

namespace monocle {
namespace {

using namespace corner_detection;  // the stages: thinning, Hough, Y junctions, tracing

constexpr double kPi = std::numbers::pi;

std::string FormatGrey(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", v);
  return buffer;
}

}  // namespace

double MinStepGrey(const CornerDetectorOptions& options, double noise_sigma_grey) {
  return std::max(options.min_step_grey, options.min_step_snr * noise_sigma_grey);
}

namespace {

struct SegmentStage {
  double scale = 1;
  cv::Mat small;
  std::vector<Segment> segments;
};

Eigen::Vector2d ToFull(const Eigen::Vector2d& p, double scale) {
  return ((p.array() + 0.5) / scale - 0.5).matrix();
}
Eigen::Vector2d ToSmall(const Eigen::Vector2d& p, double scale) {
  return ((p.array() + 0.5) * scale - 0.5).matrix();
}

// Undistorted pixel (the same camera without lens distortion) -> pixel.
Eigen::Vector2d RedistortPixel(const CameraIntrinsics& k, const Eigen::Vector2d& undistorted_px) {
  return NormalizedToPixel(
      k, Eigen::Vector2d((undistorted_px.x() - k.cx) / k.fx, (undistorted_px.y() - k.cy) / k.fy));
}

// The frame at the detection scales, halved once per frame and shared by the searches at
// both scales. Halving twice (2x2 means, as INTER_AREA gives them; HalveImage) is ten times
// faster than one resize to a quarter (OpenCV's general area path).
class ScaledFrames {
 public:
  explicit ScaledFrames(const cv::Mat& grey) : full_(grey) {}
  const cv::Mat& At(double scale) {
    if (scale > 0.75) return full_;
    if (half_.empty()) HalveImage(full_, &half_);
    if (scale > 0.375) return half_;
    if (quarter_.empty()) HalveImage(half_, &quarter_);
    return quarter_;
  }

 private:
  cv::Mat full_, half_, quarter_;
};

SegmentStage FindSegments(ScaledFrames& frames, const CornerDetectorOptions& options,
                          const CameraIntrinsics* k, double scale) {
  SegmentStage out;
  out.scale = scale;
  out.small = frames.At(scale);
  // A Gaussian before the gradient: edges between alike-painted surfaces are a few grey
  // levels high, and smoothing over ~2 px raises a long edge's gradient above the noise
  // (the paper's Sobel alone is not enough at a contrast-to-noise of 2).
  cv::Mat smooth;
  cv::GaussianBlur(out.small, smooth, cv::Size(7, 7), 1.0, 1.0, cv::BORDER_REPLICATE);
  auto edges = ThinEdges(smooth, options);
  if (k != nullptr && k->HasDistortion()) {
    // Move every edge pixel (and its gradient) to where an undistorted camera sees it,
    // interpolated from a grid built once per camera (and thread).
    const UndistortionGrid& grid = UndistortionGridFor(*k);
    for (auto& e : edges) {
      Eigen::Matrix2d j;
      const Eigen::Vector2d u = grid.Undistort(ToFull(Eigen::Vector2d(e.x, e.y), out.scale), &j);
      const Eigen::Vector2d p = ToSmall(u, out.scale);
      const Eigen::Vector2d tangent = (j * Eigen::Vector2d(-e.ny, e.nx)).normalized();
      e.x = static_cast<float>(p.x());
      e.y = static_cast<float>(p.y());
      e.nx = static_cast<float>(tangent.y());
      e.ny = static_cast<float>(-tangent.x());
    }
  }
  for (auto& e : edges) e.angle = std::atan2(e.ny, e.nx);  // used by the Hough and the buckets
  const double min_length = options.min_edge_length_px * out.scale;
  // Undistorted points may leave the frame a little: size the accumulator for 1.25x. A peak
  // needs 70 % of the shortest edge's pixels (the ends and the junction blur away); the
  // segment itself must still be that long.
  const auto peaks = HoughPeaks(edges, out.small.cols * 5 / 4, out.small.rows * 5 / 4,
                                static_cast<int>(0.7 * min_length), options.max_lines);
  // Edges bucketed by gradient direction (1 degree, modulo 180): a line only looks at the
  // edges within the 20 degrees its support test accepts.
  std::array<std::vector<const EdgePixel*>, 180> buckets;
  for (const auto& e : edges) {
    double deg = e.angle * 180 / kPi;
    if (deg < 0) deg += 180;
    buckets[static_cast<int>(deg) % 180].push_back(&e);
  }
  std::vector<const EdgePixel*> nearby;
  for (size_t i = 0; i < peaks.size(); ++i) {
    const double alpha = peaks[i].angle_bin * kPi / kAngleBins;
    const int center = static_cast<int>(alpha * 180 / kPi);
    nearby.clear();
    for (int b = center - 21; b <= center + 21; ++b) {
      const auto& bucket = buckets[((b % 180) + 180) % 180];
      nearby.insert(nearby.end(), bucket.begin(), bucket.end());
    }
    SegmentsOfLine(nearby, static_cast<int>(i), alpha, peaks[i].rho_bin, min_length, &out.segments);
  }
  // Several peaks of one wide Hough ridge refit to the same segment: keep one.
  std::vector<Segment> distinct;
  for (const auto& seg : out.segments) {
    bool seen = false;
    for (const auto& d : distinct) {
      seen |= (((seg.End(0) - d.End(0)).norm() < 2 && (seg.End(1) - d.End(1)).norm() < 2) ||
               ((seg.End(0) - d.End(1)).norm() < 2 && (seg.End(1) - d.End(0)).norm() < 2));
    }
    if (!seen) distinct.push_back(seg);
  }
  out.segments = std::move(distinct);
  return out;
}

// Full-resolution pixel of the image from a half-resolution (possibly undistorted) point.
Eigen::Vector2d ToImage(const Eigen::Vector2d& p, double scale, const CameraIntrinsics* k) {
  const Eigen::Vector2d full = ToFull(p, scale);
  return k != nullptr && k->HasDistortion() ? RedistortPixel(*k, full) : full;
}

// Subpixel edge points at full resolution along each edge of one Y, from just off the corner
// (where the three edges blur into each other) to the image border.
template <typename ToFull>
Result<CornerEdges> MeasureY(const cv::Mat& grey, const YTriple& y, int spacing_px, CornerEdges out,
                             const ToFull& to_full, double min_step) {
  out.corner_px = to_full(y.corner);
  out.sample_spacing_px = spacing_px;
  for (int m = 0; m < 3; ++m) {
    // The ray's direction in the image, where it leaves the corner.
    const Eigen::Vector2d d =
        (to_full(y.corner + 10 * y.direction[m]) - out.corner_px).normalized();
    out.direction[m] = d;
    out.points_px[m].clear();
    out.step_grey[m].clear();
    const auto samples = TraceEdge(grey, out.corner_px, d, min_step, spacing_px);
    for (const auto& sample : samples) {
      out.points_px[m].push_back(sample.point_px);
      out.step_grey[m].push_back(sample.step_grey);
    }
    out.blur_sigma_px[m] = EdgeBlurSigmaPx(samples);
    // Polarity: the sign most points near the corner have.
    int votes = 0;
    for (size_t i = 0;
         i < out.points_px[m].size() && static_cast<int>(i) < 80 / std::max(spacing_px, 1); ++i)
      votes += out.step_grey[m][i] > 0 ? 1 : -1;
    out.polarity[m] = votes >= 0 ? 1 : -1;
    // Fewer points than 20 px of edge hold.
    if (static_cast<int>(out.points_px[m].size()) * spacing_px < 20) {
      if (SaturatedAround(grey, out.corner_px)) {
        return MakeError(ErrorCode::kNotFound,
                         "a corner edge cannot be measured: the surfaces around the corner are "
                         "saturated (white or black clipped); lower the exposure or gain");
      }
      // Glare along the edge rather than around the corner: no point is measured beside a
      // clipped side, however clear the edge looks.
      if (ClippedAlong(grey, out.corner_px + 8 * d, out.corner_px + 200 * d)) {
        return MakeError(ErrorCode::kNotFound,
                         "a corner edge cannot be measured: a surface beside it is saturated "
                         "(white or black clipped) over most of its first 200 px; lower the "
                         "exposure or gain");
      }
      return MakeError(ErrorCode::kNotFound, "a corner edge has too little contrast to measure (" +
                                                 std::to_string(out.points_px[m].size()) +
                                                 " points with a step of at least " +
                                                 FormatGrey(min_step) + " grey levels at noise " +
                                                 FormatGrey(out.measurement_noise_grey) + ")");
    }
  }
  return out;
}

// Why no Y was found, in the user's terms: how many edges, whether two of them meet, and
// how strong the strongest third edge leaving their junction is against the noise.
std::string DiagnoseMissingY(const cv::Mat& grey, const std::vector<Segment>& segments,
                             double scale, const CameraIntrinsics* k, double noise_sigma,
                             double junction_radius) {
  // Distinct lines (segments of one Hough line count once).
  std::vector<const Segment*> distinct;
  for (const auto& s : segments) {
    bool seen = false;
    for (const auto* d : distinct)
      seen |= std::abs(d->direction.dot(s.direction)) > std::cos(kPi / 60) &&
              std::abs(d->rho - s.normal.dot(d->normal) * s.rho) < 3;
    if (!seen) distinct.push_back(&s);
  }
  const std::string edges = std::to_string(distinct.size()) + " straight edge" +
                            (distinct.size() == 1 ? "" : "s") + " found";
  if (distinct.size() < 2) return edges + "; a corner needs three meeting in a Y";
  // The best supported pair whose segments end near their lines' intersection.
  double best_support = -1;
  Eigen::Vector2d junction = Eigen::Vector2d::Zero();
  std::array<Eigen::Vector2d, 2> rays{Eigen::Vector2d::UnitX(), Eigen::Vector2d::UnitY()};
  for (size_t i = 0; i < distinct.size(); ++i) {
    for (size_t j = i + 1; j < distinct.size(); ++j) {
      const Segment& a = *distinct[i];
      const Segment& b = *distinct[j];
      Eigen::Matrix2d m;
      m << a.normal.transpose(), b.normal.transpose();
      if (std::abs(m.determinant()) < 0.2) continue;  // nearly parallel
      const Eigen::Vector2d c = m.inverse() * Eigen::Vector2d(a.rho, b.rho);
      auto end_near = [&](const Segment& s, Eigen::Vector2d* ray) {
        const double tc = s.direction.dot(c);
        const double d0 = std::abs(s.t0 - tc), d1 = std::abs(s.t1 - tc);
        *ray = d0 < d1 ? s.direction : Eigen::Vector2d(-s.direction);
        return std::min(d0, d1) < 4 * junction_radius;
      };
      std::array<Eigen::Vector2d, 2> r{Eigen::Vector2d::UnitX(), Eigen::Vector2d::UnitY()};
      if (!end_near(a, &r[0]) || !end_near(b, &r[1])) continue;
      if (a.support + b.support > best_support) {
        best_support = a.support + b.support;
        junction = c;
        rays = r;
      }
    }
  }
  if (best_support < 0) return edges + ", but no two of them meet at a corner";
  // Around the junction, the strongest straight step in any other direction.
  const Eigen::Vector2d corner = ToImage(junction, scale, k);
  double strongest = 0;
  for (int deg = 0; deg < 360; deg += 3) {
    const Eigen::Vector2d d(std::cos(deg * kPi / 180), std::sin(deg * kPi / 180));
    if (d.dot(rays[0]) > std::cos(kPi / 9) || d.dot(rays[1]) > std::cos(kPi / 9)) continue;
    std::vector<Eigen::Vector2d> positions, normals;
    for (double t = 10; t < 130; t += 2) {
      positions.push_back(corner + t * d);
      normals.emplace_back(-d.y(), d.x());
    }
    for (int sign : {+1, -1}) {
      const auto found = MeasureEdgePoints(grey, positions, normals, 3, sign, 0.5);
      if (found.size() < positions.size() / 2) continue;
      std::vector<double> steps;
      for (const auto& f : found) steps.push_back(std::abs(f.step_grey));
      std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
      strongest = std::max(strongest, steps[steps.size() / 2]);
    }
  }
  char where[64];
  std::snprintf(where, sizeof where, " at (%.0f, %.0f) px", corner.x(), corner.y());
  const std::string measured =
      "contrast " + FormatGrey(strongest) + " grey levels at noise " + FormatGrey(noise_sigma);
  // A step well above the noise that still is no edge of a Y: clutter or a curved shade.
  if (strongest > 4 * std::max(noise_sigma, 0.5))
    return edges + "; 2 meet" + where + " but no straight third edge leaves it (strongest step " +
           measured + ")";
  // No third edge where the walls around the junction are clipped white: the glare hides it.
  if (SaturatedAround(grey, corner))
    return edges + "; 2 meet" + where +
           " but the surfaces around them are saturated (white or black clipped), which hides "
           "the third; lower the exposure or gain";
  return edges + "; 2 meet" + where + " but the third is too weak (" + measured + ")";
}

// One detection at `scale` of the image: the Hough stage there, then every Y it finds
// measured at full resolution and offered to `accept`. Nothing, or why none was accepted;
// with `diagnose`, a view without a Y says what was seen (measured at full resolution: a
// twentieth of a detection, spent only where the reason is reported).
std::optional<Error> TryScale(const cv::Mat& grey, ScaledFrames& frames,
                              const CornerDetectorOptions& options, const CameraIntrinsics* k,
                              double scale, double noise_sigma_grey, double measurement_noise_grey,
                              bool diagnose, const std::function<bool(CornerEdges)>& accept) {
  const auto stage = FindSegments(frames, options, k, scale);
  const auto& segments = stage.segments;
  auto to_full = [&](const Eigen::Vector2d& p) { return ToImage(p, scale, k); };
  CornerEdges out;
  out.direction.fill(Eigen::Vector2d::Zero());  // set per Y by MeasureY
  out.detection_scale = scale;
  for (const auto& s : segments)
    out.hough_segments.push_back({to_full(s.End(0)), to_full(s.End(1)), s.support});
  const auto candidates = FindYCandidates(segments, stage.small.cols, stage.small.rows,
                                          options.junction_radius_px * scale);
  out.noise_sigma_grey = noise_sigma_grey;
  out.measurement_noise_grey = measurement_noise_grey;
  const double min_step = MinStepGrey(options, out.noise_sigma_grey);
  if (candidates.empty() && !diagnose)
    return MakeError(ErrorCode::kNotFound, "no ceiling corner found at this resolution");
  if (candidates.empty()) {
    return MakeError(ErrorCode::kNotFound,
                     "no ceiling corner found: " +
                         DiagnoseMissingY(grey, segments, scale, k, out.measurement_noise_grey,
                                          options.junction_radius_px * scale));
  }
  // The best supported Y first; a Y whose edges cannot be measured at full resolution
  // (clutter or shading that looked like an edge at low resolution) is passed over.
  std::optional<Error> why;
  for (const auto& y : candidates) {
    auto edges = MeasureY(grey, y, options.trace_spacing_px, out, to_full, min_step);
    if (!edges) {
      if (!why) why = edges.error();
      continue;
    }
    if (accept(std::move(*edges))) return std::nullopt;
    if (!why) why = MakeError(ErrorCode::kNotFound, "no Y found is a ceiling corner");
  }
  return why;
}

// Detection's resolution: half for a camera image (a quarter of the pixels, and the Hough
// cells grow with it); with `first`, a quarter for images at least 800 px on each side,
// tried before half: its 4x4 averages quarter the noise, so long edges stand out as well,
// and a view whose short edge it misses is tried again at half.
double DetectionScale(const cv::Mat& grey, bool first) {
  const int side = std::min(grey.cols, grey.rows);
  if (first && side >= 800) return 0.25;
  return side >= 400 ? 0.5 : 1.0;
}

}  // namespace

std::vector<HoughSegment> DetectStraightEdges(const cv::Mat& grey,
                                              const CornerDetectorOptions& options,
                                              const CameraIntrinsics* k) {
  std::vector<HoughSegment> out;
  if (grey.empty() || grey.type() != CV_8UC1 || grey.cols < 64 || grey.rows < 64) return out;
  ScaledFrames frames(grey);
  const auto stage = FindSegments(frames, options, k, DetectionScale(grey, false));
  for (const auto& s : stage.segments) {
    out.push_back(
        {ToImage(s.End(0), stage.scale, k), ToImage(s.End(1), stage.scale, k), s.support});
  }
  return out;
}

Result<CornerEdges> DetectCornerEdges(const cv::Mat& grey, const CornerDetectorOptions& options,
                                      const CameraIntrinsics* k) {
  std::optional<CornerEdges> found;
  const auto error = ForEachCornerCandidate(grey, options, k, [&](CornerEdges edges) {
    found = std::move(edges);
    return true;
  });
  if (error) return *error;
  return std::move(*found);
}

std::optional<Error> ForEachCornerCandidate(const cv::Mat& grey,
                                            const CornerDetectorOptions& options,
                                            const CameraIntrinsics* k,
                                            const std::function<bool(CornerEdges)>& accept) {
  if (grey.empty() || grey.type() != CV_8UC1) {
    return MakeError(ErrorCode::kInvalidArgument, "corner detection needs an 8-bit grey image");
  }
  if (grey.cols < 64 || grey.rows < 64) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "the image is " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                         ": too small to find a corner in (at least 64x64)");
  }
  const double coarse = DetectionScale(grey, options.quarter_resolution_first),
               fine = DetectionScale(grey, false);
  // Halved first: that reads the whole frame (from memory, for a camera's new frame), and
  // the noise estimate's rows are then read from the cache (a sixth less time for it).
  ScaledFrames frames(grey);
  frames.At(coarse);
  const double noise_sigma_grey = EstimateNoiseSigma(grey);
  const double measurement_noise_grey = EstimateMeasurementNoiseSigma(grey);
  const auto why = TryScale(grey, frames, options, k, coarse, noise_sigma_grey,
                            measurement_noise_grey, /*diagnose=*/coarse == fine, accept);
  if (!why || coarse == fine) return why;
  // Again at the finer resolution, whose reason is the one to report.
  return TryScale(grey, frames, options, k, fine, noise_sigma_grey, measurement_noise_grey,
                  /*diagnose=*/true, accept);
}

}  // namespace monocle
