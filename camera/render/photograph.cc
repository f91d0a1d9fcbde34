#include "camera/render/photograph.h"

#include <opencv2/imgproc.hpp>
#include <vector>

#include "service/io/image_codec.h"

namespace monocle {

cv::Mat Expose(const cv::Mat& radiance, const PhotoEffects& look) {
  const int w = radiance.cols, h = radiance.rows;
  cv::Mat lit(h, w, CV_32F);
  const double half_diagonal2 = 0.25 * (w * w + h * h);
  const double r2_hot = 2 * look.hotspot_radius_px * look.hotspot_radius_px;
  for (int v = 0; v < h; ++v) {
    const auto* in = radiance.ptr<float>(v);
    auto* out = lit.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      const double dx = u - 0.5 * (w - 1), dy = v - 0.5 * (h - 1);
      const double r2 = (dx * dx + dy * dy) / half_diagonal2;       // 1 at the image's corners
      const double vignette = 1 - look.vignetting * r2 * (2 - r2);  // smooth, flat at the centre
      const double hx = u - look.hotspot_px.x(), hy = v - look.hotspot_px.y();
      const double hot = 1 + look.hotspot_gain * std::exp(-(hx * hx + hy * hy) / r2_hot);
      out[u] = static_cast<float>(in[u] * vignette * hot);
    }
  }
  if (look.blur_sigma_px > 0)
    cv::GaussianBlur(lit, lit, cv::Size(), look.blur_sigma_px, look.blur_sigma_px,
                     cv::BORDER_REFLECT);
  return lit;
}

cv::Mat Photograph(const cv::Mat& radiance, const PhotoEffects& look, uint64_t seed) {
  cv::Mat lit = Expose(radiance, look);
  const int w = lit.cols, h = lit.rows;
  if (look.noise_sigma > 0) {
    cv::Mat noise(h, w, CV_32F);
    cv::RNG rng(seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, look.noise_sigma);
    lit += noise;
  }
  cv::Mat grey;
  lit.convertTo(grey, CV_8U);  // rounds and saturates
  if (look.jpeg_quality > 0) {
    // Through libjpeg as OpenCV's imencode / imdecode would (image_codec_test checks the
    // bytes are the same).
    const auto jpeg = EncodeImage(grey, ".jpg", look.jpeg_quality);
    const auto decoded =
        jpeg ? DecodeGreyImage(
                   std::string_view(reinterpret_cast<const char*>(jpeg->data()), jpeg->size()),
                   "JPEG")
             : Result<cv::Mat>(jpeg.error());
    if (decoded) grey = *decoded;  // an 8-bit grey frame always encodes; kept raw otherwise
  }
  return grey;
}

}  // namespace monocle
