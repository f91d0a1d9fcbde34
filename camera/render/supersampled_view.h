// One radiance image of a ray-cast scene through the reference lens, shared by the corner and
// room renderers: one ray per pixel centre, and where a pixel's neighbour shows another
// surface, the average of 4 x 4 sub-pixel rays, so edges are antialiased where the detector
// measures them and flat surfaces cost one ray a pixel.
#pragma once

#include <algorithm>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "camera/render/reference_camera.h"
#include "service/geometry/camera_model.h"

namespace monocle {

// `shade(normalized_ray, &surface)` returns the radiance (grey levels) seen along the ray
// through normalized image point (x, y, 1) and sets which surface it hit (any id; only
// equality matters). Returns CV_32F grey levels. Pixel centres are at integer coordinates;
// each pixel spans +-0.5.
template <typename ShadeRay>
cv::Mat RenderSupersampledView(const CameraIntrinsics& k, ShadeRay shade) {
  const int w = k.width_px, h = k.height_px;
  const cv::Mat rays = reference::UndistortedPixelGrid(k);
  cv::Mat value(h, w, CV_32F), surface(h, w, CV_32S);
  for (int v = 0; v < h; ++v) {
    auto* val = value.ptr<float>(v);
    auto* surf = surface.ptr<int32_t>(v);
    const auto* ray = rays.ptr<cv::Point2d>(v);
    for (int u = 0; u < w; ++u) {
      int32_t hit = 0;
      val[u] = static_cast<float>(shade(ray[u], &hit));
      surf[u] = hit;
    }
  }
  std::vector<cv::Point> boundary;
  std::vector<cv::Point2d> samples;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const int32_t s = surface.at<int32_t>(v, u);
      bool is_boundary = false;
      for (int dv = -1; dv <= 1 && !is_boundary; ++dv) {
        for (int du = -1; du <= 1 && !is_boundary; ++du) {
          const int uu = std::clamp(u + du, 0, w - 1), vv = std::clamp(v + dv, 0, h - 1);
          is_boundary = surface.at<int32_t>(vv, uu) != s;
        }
      }
      if (!is_boundary) continue;
      boundary.emplace_back(u, v);
      for (int sy = 0; sy < 4; ++sy)
        for (int sx = 0; sx < 4; ++sx)
          samples.emplace_back(u + (sx + 0.5) / 4 - 0.5, v + (sy + 0.5) / 4 - 0.5);
    }
  }
  const auto sample_rays = reference::UndistortPixels(k, samples);
  for (size_t i = 0; i < boundary.size(); ++i) {
    double sum = 0;
    int32_t ignored = 0;
    for (int s = 0; s < 16; ++s) sum += shade(sample_rays[16 * i + s], &ignored);
    value.at<float>(boundary[i]) = static_cast<float>(sum / 16);
  }
  return value;
}

}  // namespace monocle
