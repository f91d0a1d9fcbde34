// An image's noise, estimated from the image itself: what the detector's thresholds and an
// edge's contrast are judged against.
#pragma once

#include <opencv2/core.hpp>

namespace monocle {

// Pixel noise of an image, grey levels (1 sigma): from the median absolute difference of
// horizontally adjacent pixels, which flat surfaces dominate in a room. Never much below
// 8-bit quantization (~0.26 for a constant image). Both estimates leave out saturated pixels
// (>= 253 or <= 2 grey), whose noise is clipped away: a frame mostly white with glare has the
// noise of its unclipped part (0 when nothing is unclipped).
double EstimateNoiseSigma(const cv::Mat& grey);

// The noise a measurement that averages pixels sees, grey levels (1 sigma, as white noise
// of that sigma would give): from the median second difference of neighbouring 8-pixel
// means along rows, so a linear shading cancels and edges are outliers. On a raw image it
// agrees with EstimateNoiseSigma. Compression (JPEG at quality 70-90) quantizes away most
// of the pixel-to-pixel noise but little of what averages keep: there EstimateNoiseSigma
// reads 2-5x low (noise sigma 3 at quality 80: 1.07 against 3.4 here), and a contrast
// against it would say an edge stands out of the noise 2-5x better than it does. This is
// the noise reported to users and the one an edge's contrast is judged against.
double EstimateMeasurementNoiseSigma(const cv::Mat& grey);

}  // namespace monocle
