#include "service/vision/corner_rays.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <numbers>
#include <vector>

#include "service/vision/ring_samples.h"

namespace monocle {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kAngleBins = 360;  // a degree each
constexpr int kMaxRings = 64;

// One ring around the corner: the step across every ~1 px of it, counter-clockwise in image
// angle (the mean just counter-clockwise of a place minus the mean just clockwise), and
// whether both windows lay in the image.
struct Ring {
  double radius_px = 0;
  int samples = 0;
  std::unique_ptr<float[]> step;
  std::unique_ptr<uint8_t[]> step_valid;  // null: every step valid (a ring inside the image)

  // The step at image angle `angle`; false where a window left the image.
  bool StepAt(double angle, double* out) const { return StepAtSample(SampleAt(angle), out); }
  bool StepAtSample(int i, double* out) const {
    if (step_valid && !step_valid[i]) return false;
    *out = step[i];
    return true;
  }
  int SampleAt(double angle) const { return SampleOfAngle(angle, samples); }

  // Rounded half away from zero, as std::lround, without its library call, and wrapped by
  // subtraction, not a division: the angle is within a turn or two of [-pi, pi).
  static int SampleOfAngle(double angle, int samples) {
    const double at = angle / (2 * kPi) * samples;
    int i = at >= 0 ? static_cast<int>(at + 0.5) : -static_cast<int>(0.5 - at);
    while (i < 0) i += samples;
    while (i >= samples) i -= samples;
    return i;
  }
};

// The angle of direction bin `bin` (a degree each, from -pi).
double AngleOfBin(int bin) { return -kPi + 2 * kPi * bin / kAngleBins; }

// Which sample of a ring of `samples` each direction bin reads. A ring's sample count depends
// on its radius only, so each table is built once per thread rather than 360 directions times
// every ring each frame; a map, so that a table stays where it is as others are added.
const std::array<int, kAngleBins>& SamplesOfBins(int samples) {
  thread_local std::map<int, std::array<int, kAngleBins>> tables;
  auto [at, added] = tables.try_emplace(samples);
  if (added) {
    for (int bin = 0; bin < kAngleBins; ++bin)
      at->second[bin] = Ring::SampleOfAngle(AngleOfBin(bin), samples);
  }
  return at->second;
}

// The steps of a ring wholly in the image (see Ring): the mean of samples [i + gap, i + gap +
// width) less that of [i - gap - width + 1, i - gap], wrapping round, for each sample i. Summed
// window by window in loops over i that vectorize: prefix sums, one long chain of dependent
// additions, cost more than the ring's sampling.
void StepsOfRingInside(const float* value, int n, int gap, int width, float* step) {
  // The ring laid out with `lead` samples of wrap before it and after it: sample j (from -lead
  // to n - 1 + lead) at extended[j + lead].
  const int lead = gap + width - 1;
  thread_local std::vector<float> extended;  // (grown, never shrunk)
  if (extended.size() < static_cast<size_t>(n + 2 * lead)) extended.resize(n + 2 * lead);
  float* e = extended.data();
  std::copy(value + n - lead, value + n, e);  // (lead < n: MeasureRing asks no more)
  std::copy(value, value + n, e + lead);
  std::copy(value, value + lead, e + lead + n);
  std::fill(step, step + n, 0.0f);
  for (int k = 0; k < width; ++k) {
    const float* ccw = e + gap + lead + k;  // sample i + gap + k
    const float* cw = e + k;                // sample i - lead + k
    for (int i = 0; i < n; ++i) step[i] += ccw[i] - cw[i];
  }
  const float per_width = 1.0f / static_cast<float>(width);
  for (int i = 0; i < n; ++i) step[i] *= per_width;
}

Ring MeasureRing(const cv::Mat& grey, const Eigen::Vector2d& centre, double radius_px,
                 const RayProfileOptions& o) {
  Ring ring;
  ring.radius_px = radius_px;
  const int n = static_cast<int>(std::ceil(2 * kPi * radius_px));
  ring.samples = n;
  // Most rings lie wholly in the image: no sample or step window needs its own check.
  const bool inside = RingInsideImage(grey, centre, radius_px);
  // Grey levels along the ring, in scratch grown, never shrunk (zeroing it anew for each ring
  // was a tenth of the check's time).
  thread_local std::vector<float> value_scratch;
  thread_local std::vector<double> sum_scratch;
  if (value_scratch.size() < static_cast<size_t>(n)) {
    value_scratch.resize(n);
    sum_scratch.resize(2 * n + 1);
  }
  float* value = value_scratch.data();
  std::vector<uint8_t> ok(inside ? 0 : n, 0);  // (read only where the ring leaves the image)
  SampleRing(grey, centre, radius_px, n, value, inside ? nullptr : ok.data());
  const double per_sample = 2 * kPi * radius_px / n;  // px along the ring
  const int gap = static_cast<int>(std::ceil(o.step_gap_px / per_sample));
  const int width = std::max(1, static_cast<int>(std::lround(o.step_width_px / per_sample)));
  if (gap + width > n) {  // a ring too small for its windows: no step is read from it
    ring.step = std::make_unique<float[]>(n);
    ring.step_valid = std::make_unique<uint8_t[]>(n);
    return ring;
  }
  ring.step = std::make_unique_for_overwrite<float[]>(n);
  if (inside) {
    StepsOfRingInside(value, n, gap, width, ring.step.get());
    return ring;
  }
  // Prefix sums over two turns, so that windows wrap round.
  double* sum = sum_scratch.data();
  sum[0] = 0;
  std::vector<int> valid(2 * n + 1, 0);
  // (Two loops, not one with i % n: that division was a good part of the check's time.)
  for (int turn = 0; turn < 2; ++turn) {
    for (int j = 0; j < n; ++j) {
      const int i = turn * n + j;
      sum[i + 1] = sum[i] + value[j];
      valid[i + 1] = valid[i] + ok[j];
    }
  }
  ring.step_valid = std::make_unique<uint8_t[]>(n);  // zeros
  for (int i = 0; i < n; ++i) {
    // Counter-clockwise window [i + gap, i + gap + width), clockwise [i - gap - width + 1,
    // i - gap] shifted one turn on: both within the prefix sums' two turns, [0, 2n].
    const int ccw = i + gap, cw = i + n - gap - width + 1;
    if (valid[ccw + width] - valid[ccw] != width || valid[cw + width] - valid[cw] != width) {
      ring.step[i] = 0;
      continue;
    }
    ring.step[i] =
        static_cast<float>((sum[ccw + width] - sum[ccw] - sum[cw + width] + sum[cw]) / width);
    ring.step_valid[i] = 1;
  }
  return ring;
}

// |remainder(a - b, 2 pi)| for angles in [-pi, pi], without the library call (a thousand a
// frame): |a - b| <= 2 pi, so the remainder is a - b or 2 pi less it, and 2 pi - |a - b| is
// exact for |a - b| >= pi (Sterbenz). The same value bit for bit.
double AngleBetween(double a, double b) {
  constexpr double kTurn = 2 * kPi;
  const double apart = std::abs(a - b);
  return apart <= 0.5 * kTurn ? apart : kTurn - apart;
}

// The median step of a ray at `angle` over the rings that read it, or false when fewer than
// RayProfileOptions::min_ring_fraction of them do.
bool MedianRayStep(const std::vector<Ring>& rings, double angle, const RayProfileOptions& o,
                   double* step) {
  std::array<double, kMaxRings> steps;
  size_t count = 0;
  for (const Ring& ring : rings) {
    double s;
    if (ring.StepAt(angle, &s)) steps[count++] = s;
  }
  if (count < std::max<size_t>(3, std::ceil(o.min_ring_fraction * rings.size()))) return false;
  // Of an even count's two middle steps, the one nearer 0 (0 if they differ in sign).
  std::sort(steps.begin(), steps.begin() + count);
  const double low = steps[(count - 1) / 2], high = steps[count / 2];
  *step = low > 0 ? low : high < 0 ? high : 0;
  return true;
}

}  // namespace

Eigen::Vector2d OtherEdgeTowardsPx(const Eigen::Vector2d& corner_px, double angle_rad,
                                   double distance_px) {
  return corner_px + distance_px * Eigen::Vector2d(std::cos(angle_rad), std::sin(angle_rad));
}

OtherRay StrongestOtherRay(const cv::Mat& grey, const Eigen::Vector2d& corner_px,
                           const std::array<Eigen::Vector2d, 3>& edge_direction_px,
                           const RayProfileOptions& o) {
  OtherRay out;
  // No ring of a corner this far outside the image (or not a number) reads a pixel, and
  // casting its coordinates to int would overflow.
  const double margin_px = o.max_radius_px + 2;
  if (!corner_px.allFinite() || corner_px.x() < -margin_px || corner_px.y() < -margin_px ||
      corner_px.x() > grey.cols + margin_px || corner_px.y() > grey.rows + margin_px)
    return out;
  std::vector<Ring> rings;
  for (double r = o.min_radius_px; r <= o.max_radius_px + 1e-9 && rings.size() < kMaxRings;
       r += o.radius_step_px)
    rings.push_back(MeasureRing(grey, corner_px, r, o));
  std::array<double, 3> edge_angle;
  for (int k = 0; k < 3; ++k)
    edge_angle[k] = std::atan2(edge_direction_px[k].y(), edge_direction_px[k].x());

  // Each edge's own step: the strongest within a degree of where the pose puts it.
  for (int k = 0; k < 3; ++k) {
    for (double d = -1; d <= 1; d += 0.25) {
      double s;
      if (MedianRayStep(rings, edge_angle[k] + d * kPi / 180, o, &s))
        out.edge_step_grey[k] = std::max(out.edge_step_grey[k], std::abs(s));
    }
  }
  const double exclude_rad = o.exclude_deg * kPi / 180;
  // Where a step's windows reach one of the Y's edges (plus 2 px of its blur), that ring
  // does not count: at angle distance d from the nearest edge, rings from reach / d on.
  const double reach_px = o.step_gap_px + o.step_width_px + 2;
  const size_t min_rings = std::max<size_t>(3, std::ceil(o.min_ring_fraction * rings.size()));
  std::array<double, kMaxRings> steps;
  std::vector<const std::array<int, kAngleBins>*> sample_of_bin;
  for (const Ring& ring : rings) sample_of_bin.push_back(&SamplesOfBins(ring.samples));
  for (int bin = 0; bin < kAngleBins; ++bin) {
    const double angle = AngleOfBin(bin);
    double nearest = kPi;
    for (double e : edge_angle) nearest = std::min(nearest, AngleBetween(angle, e));
    if (nearest < exclude_rad) continue;
    size_t count = 0;
    for (size_t j = 0; j < rings.size(); ++j) {
      double s;
      if (rings[j].radius_px * nearest >= reach_px &&
          rings[j].StepAtSample((*sample_of_bin[j])[bin], &s))
        steps[count++] = s;
    }
    if (count < min_rings) continue;
    // The step all but other_ray_quantile of the rings show, with one sign (0 if they
    // disagree on it). It can beat the strongest so far only if few enough rings show less:
    // counted first, so that most directions are passed over without sorting.
    const size_t low_at = static_cast<size_t>(std::floor(o.other_ray_quantile * (count - 1)));
    const size_t high_at = static_cast<size_t>(std::ceil((1 - o.other_ray_quantile) * (count - 1)));
    size_t not_above = 0, not_below = 0;
    for (size_t i = 0; i < count; ++i) {
      not_above += steps[i] <= out.step_grey;
      not_below += steps[i] >= -out.step_grey;
    }
    if (not_above > low_at && not_below > count - 1 - high_at) continue;
    std::sort(steps.begin(), steps.begin() + count);
    const double low = steps[low_at], high = steps[high_at];
    const double s = low > 0 ? low : high < 0 ? high : 0;
    if (std::abs(s) > out.step_grey) {
      out.step_grey = std::abs(s);
      out.angle_rad = angle;
    }
  }
  return out;
}

}  // namespace monocle
