#include "service/vision/edge_profile.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "service/vision/pixel_pairs.h"

namespace monocle {
namespace {

float Bilinear(const cv::Mat& img, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const uint8_t* r0 = img.ptr<uint8_t>(y0);
  const uint8_t* r1 = img.ptr<uint8_t>(y0 + 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
         fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

// The same for x, y >= 0 (and inside the image): truncation is then the floor, which spares
// two calls of the library's floor per sample (x86-64's baseline has no rounding instruction).
// Bit for bit the same value. MeasureShadingAcrossStretch reads ~500 samples a stretch with it.
float BilinearNonNegative(const cv::Mat& img, double x, double y) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const uint8_t* r0 = img.data + static_cast<size_t>(y0) * img.step[0];
  const uint8_t* r1 = r0 + img.step[0];
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
         fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

}  // namespace

namespace {

constexpr int kAlong = 3;  // profiles averaged over +-3 px along the edge
constexpr int kStep = 3;   // the step is measured between +-3 px of the edge

// Whether a profile at p, reaching r px along the normal n and kAlong px along the edge d,
// is sampled from pixels inside the image (bilinear reads the next pixel too). Exact for the
// profile's rectangle, so an edge is measured up to a few pixels from the border it leaves
// by, not a fixed margin in every direction: on a short edge those last pixels are a good
// part of what fixes its direction.
bool ProfileInside(const cv::Mat& grey, const Eigen::Vector2d& p, const Eigen::Vector2d& n,
                   const Eigen::Vector2d& d, int r) {
  const double reach_x = r * std::abs(n.x()) + kAlong * std::abs(d.x()) + 0.01;
  const double reach_y = r * std::abs(n.y()) + kAlong * std::abs(d.y()) + 0.01;
  return p.x() - reach_x >= 0 && p.y() - reach_y >= 0 && p.x() + reach_x < grey.cols - 1 &&
         p.y() + reach_y < grey.rows - 1;
}
// A side averaging this close to 255 (or 0) is (partly) clipped: with noise, many of its
// pixels are saturated. (254 kept points beside partly clipped walls, still biased.)
constexpr float kClippedWhite = 250.0f, kClippedBlack = 5.0f;

// The derivative filter across the edge: the central difference smoothed by [1 2 1] / 4
// (sigma 0), or a derivative of a Gaussian (taps j exp(-j^2 / 2 sigma^2), scaled so a ramp of
// slope 1 gives 1). Odd-symmetric, so it does not move a symmetric edge.
struct DerivativeKernel {
  std::vector<float> taps;
  explicit DerivativeKernel(double sigma_px) {
    if (!(sigma_px > 0)) {
      taps = {-0.125f, -0.25f, 0.0f, 0.25f, 0.125f};
      return;
    }
    const int reach = static_cast<int>(std::ceil(2.5 * sigma_px));
    double ramp_response = 0;
    std::vector<double> w;
    for (int j = -reach; j <= reach; ++j) {
      w.push_back(j * std::exp(-0.5 * j * j / (sigma_px * sigma_px)));
      ramp_response += w.back() * j;
    }
    for (double v : w) taps.push_back(static_cast<float>(v / ramp_response));
  }
  int Reach() const { return static_cast<int>(taps.size() / 2); }
};

// The kernel for `sigma_px`, built once per thread for each of the last few sigmas asked (an
// edge's stretches share one; each exponential of a kernel built per stretch cost 1 % of a
// tracked frame).
const DerivativeKernel& KernelFor(double sigma_px) {
  struct Cached {
    double sigma_px = -1;
    DerivativeKernel kernel{0};
  };
  thread_local std::array<Cached, 4> cache;
  thread_local size_t next = 0;
  for (const Cached& c : cache)
    if (c.sigma_px == sigma_px) return c.kernel;
  Cached& slot = cache[next];
  next = (next + 1) % cache.size();
  slot.sigma_px = sigma_px;
  slot.kernel = DerivativeKernel(sigma_px);
  return slot.kernel;
}

// The edge in one profile across it: profile[o] is the image at offset o - r along the
// normal. Its steepest rise within +-search (of the polarity asked, or either with 0),
// refined by a parabola, if the step across it is at least min_step.
std::optional<EdgePointSample> PeakOfProfile(const DerivativeKernel& kernel, const float* profile,
                                             int r, int search, double half_width_px, int polarity,
                                             double min_step_grey, const Eigen::Vector2d& p,
                                             const Eigen::Vector2d& n) {
  std::array<float, 128> deriv;  // written before it is read, over [r - search - 1, r + search + 1]
  if (2 * r + 1 > static_cast<int>(deriv.size())) return std::nullopt;
  const int reach = kernel.Reach();
  // Four offsets at a time, their sums in registers (they vectorize); each offset's sum is
  // still taken in the taps' order, the same value bit for bit as one offset at a time. (Tap
  // by tap over all offsets, each tap waited on the last one's stores.)
  const int first = r - search - 1, last = r + search + 1;
  const float* taps = kernel.taps.data();
  const int tap_count = 2 * reach + 1;
  int o = first;
  for (; o + 3 <= last; o += 4) {
    const float* p = profile + o - reach;
    float a0 = 0, a1 = 0, a2 = 0, a3 = 0;
    for (int t = 0; t < tap_count; ++t) {
      a0 += taps[t] * p[t];
      a1 += taps[t] * p[t + 1];
      a2 += taps[t] * p[t + 2];
      a3 += taps[t] * p[t + 3];
    }
    deriv[o] = a0;
    deriv[o + 1] = a1;
    deriv[o + 2] = a2;
    deriv[o + 3] = a3;
  }
  for (; o <= last; ++o) {
    float a = 0;
    for (int t = 0; t < tap_count; ++t) a += taps[t] * profile[o - reach + t];
    deriv[o] = a;
  }
  // Polarity 0: whichever sign is steeper here.
  float sign = static_cast<float>(polarity);
  if (polarity == 0) {
    float lo = 0, hi = 0;
    for (int o = r - search; o <= r + search; ++o) {
      lo = std::min(lo, deriv[o]);
      hi = std::max(hi, deriv[o]);
    }
    sign = hi >= -lo ? 1.0f : -1.0f;
  }
  int best = -1;
  float best_value = 0;
  for (int o = r - search - 1; o <= r + search + 1; ++o) {
    deriv[o] *= sign;
    if (o >= r - search && o <= r + search && deriv[o] > best_value) {
      best_value = deriv[o];
      best = o;
    }
  }
  if (best <= r - search || best >= r + search) return std::nullopt;  // a clear maximum inside
  // A side clipped at white (or black): the camera's saturation cut the blurred step short,
  // and its steepest rise sits up to a pixel off the true edge, towards the unclipped side
  // (0.6-1.2 px on realistic renders of bright walls under a lamp). Not measured here.
  const float side_a = profile[best - kStep - 1], side_b = profile[best + kStep + 1];
  if (std::max(side_a, side_b) >= kClippedWhite || std::min(side_a, side_b) <= kClippedBlack)
    return std::nullopt;
  const double step = profile[best + kStep] - profile[best - kStep];
  if (sign * step < min_step_grey) return std::nullopt;
  // The subpixel peak: a parabola through the logarithms of the three derivatives around it,
  // which is exact for a Gaussian peak, as a blurred step's derivative is. A parabola through
  // the values themselves is off by up to a few hundredths of a pixel depending on where the
  // samples fall (the subpixel phase), and a line sampled slightly askew of the edge sweeps
  // that phase along it: the points then lean towards the line they were sampled along.
  // (Fisher & Naidu 1996 compare the estimators.) Where a neighbour is not positive, the
  // plain parabola.
  const float left = deriv[best - 1], mid = deriv[best], right = deriv[best + 1];
  double offset = 0;
  if (left > 0 && right > 0) {
    // ln(left) - ln(right) and the logarithms' second difference, with two logarithms.
    const float difference = std::log(left / right);
    const float curvature = std::log(left * right / (mid * mid));
    if (curvature < 0) offset = 0.5 * difference / curvature;
  } else {
    const double denom = left - 2.0 * mid + right;
    if (denom < 0) offset = 0.5 * (left - right) / denom;
  }
  if (std::abs(best - r + offset) > half_width_px) return std::nullopt;
  return EdgePointSample{p + (best - r + offset) * n, step, best_value};
}

}  // namespace

std::vector<EdgePointSample> MeasureEdgePoints(const cv::Mat& grey,
                                               const std::vector<Eigen::Vector2d>& positions,
                                               const std::vector<Eigen::Vector2d>& normals,
                                               double half_width_px, int polarity,
                                               double min_step_grey, double derivative_sigma_px) {
  std::vector<EdgePointSample> out;
  const int search = static_cast<int>(std::ceil(half_width_px));
  const DerivativeKernel& kernel = KernelFor(derivative_sigma_px);
  // The profile reaches past the search window as far as PeakOfProfile reads: the step's
  // sides (kStep + 1 from a peak inside the window) and the filter around its edge.
  const int r = search + std::max(kStep, kernel.Reach() + 1);
  std::vector<float> profile(2 * r + 1);
  for (size_t i = 0; i < positions.size(); ++i) {
    const Eigen::Vector2d& p = positions[i];
    const Eigen::Vector2d& n = normals[i];
    const Eigen::Vector2d t(-n.y(), n.x());
    if (!ProfileInside(grey, p, n, t, r)) continue;
    for (int o = -r; o <= r; ++o) {
      float sum = 0;
      for (int a = -kAlong; a <= kAlong; ++a) {
        const Eigen::Vector2d q = p + o * n + a * t;
        sum += Bilinear(grey, q.x(), q.y());
      }
      profile[o + r] = sum / (2 * kAlong + 1);
    }
    if (auto found = PeakOfProfile(kernel, profile.data(), r, search, half_width_px, polarity,
                                   min_step_grey, p, n)) {
      out.push_back(*found);
    }
  }
  return out;
}

namespace {

// The patch of `columns.size()` x `height` samples at origin + c d + o n (c from `columns`,
// along the edge; row o across it), read bilinearly, row by row, into `patch_out`. Only the
// columns profiles read: profiles spaced wider than they are leave gaps.
void SamplePatch(const cv::Mat& grey, const Eigen::Vector2d& origin, const Eigen::Vector2d& d,
                 const Eigen::Vector2d& n, const std::vector<int>& columns, int height,
                 std::vector<float>* patch_out) {
  // Sampled here, bilinearly, with the image's edge pixels repeated beyond it (positions
  // that close to the border are skipped below anyway). OpenCV's warpAffine did this before,
  // but on a float copy of the region, with its position rounded to 1/32 px, and at ~100
  // calls a frame its allocations cost more than the sampling.
  std::vector<float>& patch = *patch_out;
  const int width = static_cast<int>(columns.size());
  // (Scratch here and below grown, never shrunk: a vector resized down and up again fills
  // its tail with zeros anew.)
  if (patch.size() < static_cast<size_t>(width) * height)
    patch.resize(static_cast<size_t>(width) * height);
  const int max_x0 = grey.cols - 2, max_y0 = grey.rows - 2;
  const double last_column = columns.back();
  const Eigen::Vector2d far_corner = origin + last_column * d + (height - 1) * n;
  Eigen::Vector2d lo = origin.cwiseMin(far_corner), hi = origin.cwiseMax(far_corner);
  for (const Eigen::Vector2d& c :
       {Eigen::Vector2d(origin + last_column * d), Eigen::Vector2d(origin + (height - 1) * n)}) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  const bool inside = lo.x() >= 0 && lo.y() >= 0 && hi.x() < max_x0 + 1 && hi.y() < max_y0 + 1;
  const size_t stride = grey.step[0];
  const uint8_t* data = grey.data;
  const float dx = static_cast<float>(d.x()), dy = static_cast<float>(d.y());
  // Per row in three simple loops (positions, then pixel_pairs.h's gather and blend): the
  // first and last vectorize (tracking 4-5 % faster than one loop). Offsets fit 32 bits:
  // frames are far smaller than 2 GB.
  thread_local std::vector<float> fx, fy;
  thread_local std::vector<uint16_t> top_pair, bottom_pair;  // left | right << 8
  thread_local std::vector<int32_t> offset;
  if (offset.size() < static_cast<size_t>(width)) {
    for (auto* v : {&fx, &fy}) v->resize(width);
    top_pair.resize(width);
    bottom_pair.resize(width);
    offset.resize(width);
  }
  // A pixel's offset in float, exact below 2^24 bytes: SSE2 has no 32-bit integer multiply,
  // and the emulated one cost as much as the rest of the positions' loop.
  const bool float_offsets_exact = static_cast<double>(grey.rows) * stride < (1 << 24);
  const float stride_f = static_cast<float>(stride);
  for (int o = 0; o < height; ++o) {
    float* row = &patch[static_cast<size_t>(o) * width];
    const Eigen::Vector2d row_origin = origin + static_cast<double>(o) * n;
    const float x_start = static_cast<float>(row_origin.x());
    const float y_start = static_cast<float>(row_origin.y());
    if (inside) {  // the patch is in the image: no clamping (x, y >= 0, so casts floor)
      for (int c = 0; c < width; ++c) {
        const float x = x_start + static_cast<float>(columns[c]) * dx,
                    y = y_start + static_cast<float>(columns[c]) * dy;
        const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
        const float x0_f = static_cast<float>(x0), y0_f = static_cast<float>(y0);
        fx[c] = x - x0_f;
        fy[c] = y - y0_f;
        offset[c] = float_offsets_exact ? static_cast<int32_t>(y0_f * stride_f + x0_f)
                                        : y0 * static_cast<int32_t>(stride) + x0;
      }
    } else {
      // Clamped into [0, max + 1] first, a position truncates to its floor: the same pixel
      // and weight as clamping floor(x) and then the weight, without a floor call per sample
      // (x86-64's baseline has no rounding instruction).
      const float x_end = static_cast<float>(max_x0 + 1), y_end = static_cast<float>(max_y0 + 1);
      for (int c = 0; c < width; ++c) {
        const float x = std::clamp(x_start + static_cast<float>(columns[c]) * dx, 0.0f, x_end),
                    y = std::clamp(y_start + static_cast<float>(columns[c]) * dy, 0.0f, y_end);
        const int x0 = std::min(static_cast<int>(x), max_x0);
        const int y0 = std::min(static_cast<int>(y), max_y0);
        fx[c] = std::min(x - static_cast<float>(x0), 1.0f);
        fy[c] = std::min(y - static_cast<float>(y0), 1.0f);
        offset[c] = y0 * static_cast<int32_t>(stride) + x0;
      }
    }
    GatherPixelPairs(data, stride, offset.data(), width, top_pair.data(), bottom_pair.data());
    BlendPixelPairs(top_pair.data(), bottom_pair.data(), fx.data(), fy.data(), width, row);
  }
}

}  // namespace

std::vector<EdgePointSample> MeasureEdgeStretch(const cv::Mat& grey, const Eigen::Vector2d& start,
                                                const Eigen::Vector2d& direction, int count,
                                                int spacing_px, double half_width_px, int polarity,
                                                double min_step_grey, double derivative_sigma_px) {
  std::vector<EdgePointSample> out;
  if (count <= 0 || spacing_px <= 0 || grey.cols < 2 || grey.rows < 2) return out;
  const int search = static_cast<int>(std::ceil(half_width_px));
  const DerivativeKernel& kernel = KernelFor(derivative_sigma_px);
  // The profile reaches past the search window as far as PeakOfProfile reads: the step's
  // sides (kStep + 1 from a peak inside the window) and the filter around its edge.
  const int r = search + std::max(kStep, kernel.Reach() + 1);
  const Eigen::Vector2d d = direction.normalized();
  const Eigen::Vector2d n(-d.y(), d.x());
  // Patch coordinates: column c along the edge, row o across it; image point =
  // origin + c d + o n.
  // The columns the profiles read, each once: profile i reads the span from i * spacing_px,
  // which starts at first_column[i] of the patch.
  constexpr int kSpan = 2 * kAlong + 1;
  thread_local std::vector<int> columns, first_column;
  columns.clear();
  first_column.resize(count);
  for (int i = 0; i < count; ++i) {
    const int from = std::max(i * spacing_px, columns.empty() ? 0 : columns.back() + 1);
    first_column[i] = static_cast<int>(columns.size()) - (from - i * spacing_px);
    for (int c = from; c < i * spacing_px + kSpan; ++c) columns.push_back(c);
  }
  const int width = static_cast<int>(columns.size()), height = 2 * r + 1;
  const Eigen::Vector2d origin = start - kAlong * d - r * n;
  thread_local std::vector<float> patch;
  SamplePatch(grey, origin, d, n, columns, height, &patch);
  thread_local std::vector<float> profile;
  profile.resize(height);
  out.reserve(count);  // (growing it a point at a time reallocated it five times a stretch)
  constexpr float kScale = 1.0f / kSpan;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector2d p = start + static_cast<double>(i * spacing_px) * d;
    if (!ProfileInside(grey, p, n, d, r)) continue;
    const int c0 = first_column[i];
    for (int o = 0; o < height; ++o) {
      const float* row = &patch[static_cast<size_t>(o) * width + c0];
      float sum = 0;
      for (int a = 0; a < kSpan; ++a) sum += row[a];
      profile[o] = kScale * sum;
    }
    if (auto found = PeakOfProfile(kernel, profile.data(), r, search, half_width_px, polarity,
                                   min_step_grey, p, n)) {
      out.push_back(*found);
    }
  }
  return out;
}

double EdgeBlurSigmaPx(const std::vector<EdgePointSample>& samples) {
  std::vector<double> ratios;  // step / (slope sqrt(2 pi)): sigma erf(kStep / (sigma sqrt 2))
  for (const auto& s : samples) {
    if (s.slope_grey_per_px > 0)
      ratios.push_back(std::abs(s.step_grey) /
                       (s.slope_grey_per_px * std::sqrt(2 * std::numbers::pi)));
  }
  if (ratios.empty()) return 0;
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  const double ratio = ratios[ratios.size() / 2];
  // The step is taken over +-kStep px, so the ratio saturates at kStep sqrt(2 / pi) for wide
  // edges: solve sigma erf(kStep / (sigma sqrt 2)) = ratio by bisection on [0, 6] px.
  double lo = 0, hi = 6;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (mid * std::erf(kStep / (mid * std::sqrt(2.0))) < ratio ? lo : hi) = mid;
  }
  // The sampler's own width: central difference (variance 1/3) smoothed by [1 2 1] / 4
  // (variance 1/2), and bilinear interpolation (variance f (1 - f) at phase f: 1/6 on average).
  constexpr double kFilterVariance = 1.0 / 3 + 0.5 + 1.0 / 6;
  return std::sqrt(std::max(0.0, lo * lo - kFilterVariance));
}

std::optional<SurfaceShading> MeasureShadingAcrossStretch(const cv::Mat& grey,
                                                          const Eigen::Vector2d& start,
                                                          const Eigen::Vector2d& direction,
                                                          double length_px, double inner_px,
                                                          double outer_px) {
  if (grey.cols < 2 || grey.rows < 2 || !(outer_px > inner_px)) return std::nullopt;
  const Eigen::Vector2d d = direction.normalized();
  const Eigen::Vector2d n(-d.y(), d.x());
  std::array<std::array<double, 2>, 2> line{};  // per side: level at the edge, slope
  // Each row in three loops, as MeasureEdgeStretch samples its patch: the positions (checked
  // inside the image), the bilinear samples (checked unclipped), their sum. With
  // BilinearNonNegative, 1.7x faster than one Bilinear call per sample, the same values bit
  // for bit.
  const int samples = static_cast<int>(std::floor((length_px + 1e-9) / 2)) + 1;
  thread_local std::vector<double> xs, ys;
  thread_local std::vector<float> values;
  xs.resize(samples);
  ys.resize(samples);
  values.resize(samples);
  const double max_x = grey.cols - 1, max_y = grey.rows - 1;
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? -1.0 : 1.0;
    double su = 0, sv = 0, suu = 0, suv = 0, count = 0;
    for (double u = inner_px; u <= outer_px + 1e-9; u += 1) {
      const double o = sign * u;
      bool inside = true;
      for (int i = 0; i < samples; ++i) {
        const double t = 2.0 * i;
        xs[i] = start.x() + t * d.x() + o * n.x();
        ys[i] = start.y() + t * d.y() + o * n.y();
        inside &= xs[i] >= 0 && ys[i] >= 0 && xs[i] < max_x && ys[i] < max_y;
      }
      if (!inside) return std::nullopt;
      bool clipped = false;
      for (int i = 0; i < samples; ++i) {
        values[i] = BilinearNonNegative(grey, xs[i], ys[i]);
        clipped |= values[i] >= 250 || values[i] <= 5;
      }
      if (clipped) return std::nullopt;
      double sum = 0;
      for (int i = 0; i < samples; ++i) sum += values[i];
      const double mean = sum / samples;
      su += o, sv += mean, suu += o * o, suv += o * mean, count += 1;
    }
    const double denominator = count * suu - su * su;
    if (!(denominator > 0)) return std::nullopt;
    line[side][1] = (count * suv - su * sv) / denominator;
    line[side][0] = (sv - line[side][1] * su) / count;
  }
  return SurfaceShading{line[0][0], line[1][0], line[0][1], line[1][1]};
}

double ShadingPeakShiftPx(const SurfaceShading& shading, double blur_sigma_px,
                          double derivative_sigma_px) {
  const double step = shading.level_right - shading.level_left;
  if (!(std::abs(step) >= 1e-3)) return 0;
  // The default filter: central difference (variance 1/3) smoothed by [1 2 1] / 4 (1/2); a
  // Gaussian one, its sigma^2. Bilinear sampling adds 1/6 on average (EdgeBlurSigmaPx).
  const double filter_variance =
      derivative_sigma_px > 0 ? derivative_sigma_px * derivative_sigma_px : 1.0 / 3 + 0.5;
  const double s2 = blur_sigma_px * blur_sigma_px + filter_variance + 1.0 / 6;
  return (shading.slope_right - shading.slope_left) * s2 / step;
}

namespace {
// Below this blur (pixels: sharp renders, a well-focused lens) the default filter, itself
// ~0.9 px wide, is as good as any.
constexpr double kSharpBelowPx = 0.8;
}  // namespace

double EdgeDerivativeSigmaPx(double blur_sigma_px) {
  // The filter matched to the blur (sigma = blur) is the best detector of the edge, but its
  // peak is located with only a third of the pixels' information; a wider one locates it
  // better (to first order in the noise, with the levels known: sqrt(3 s^6 / (8 f^5 b)) times
  // the bound for a filter f, blur b and s^2 = b^2 + f^2; 1.73x at f = b, 1.27x at 1.6 b,
  // 1.22x at 1.9 b, least, 1.20x, at sqrt(5) b) and reaches further into each surface, where
  // a shading slope on one side moves the peak by (slope difference) * s^2 / step. 1.6x is
  // the measured balance where the shading is not read (client/cli/GUIDE.md, "The derivative
  // filter's width").
  constexpr double kWidthOverBlur = 1.6;
  return blur_sigma_px > kSharpBelowPx ? kWidthOverBlur * blur_sigma_px : 0.0;
}

double WeakViewEdgeDerivativeSigmaPx(double blur_sigma_px) {
  // Where the shading's shift is removed, a wider filter's larger bias is mostly removed with
  // it. Wider still, the shading the correction does not model (it grows with the filter's
  // width squared) outweighs the gain (tests/accuracy/corner_pose_notes.md, "Weak views
  // measured again, with a wider filter").
  constexpr double kWidthOverBlur = 1.9;
  return blur_sigma_px > kSharpBelowPx ? kWidthOverBlur * blur_sigma_px : 0.0;
}

std::vector<EdgePointSample> MajoritySign(std::vector<EdgePointSample> samples) {
  int balance = 0;
  for (const auto& s : samples) balance += s.step_grey > 0 ? 1 : -1;
  std::erase_if(samples,
                [&](const EdgePointSample& s) { return (s.step_grey > 0) != (balance > 0); });
  if (samples.size() < 3) samples.clear();  // a lone point or two in a chunk: noise
  return samples;
}

}  // namespace monocle
