// Grey levels around a circle in an image: what the other-ray check (corner_rays.h) reads
// around a corner, one ring at a time.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>

namespace monocle {

// Whether the circle of `radius_px` about `centre` lies wholly inside the image, with a pixel
// to spare for a bilinear read.
bool RingInsideImage(const cv::Mat& grey, const Eigen::Vector2d& centre, double radius_px);

// The image at `samples` points evenly around that circle, counter-clockwise in image angle
// from +x (sample i at angle 2 pi i / samples), bilinearly, into value[0, samples). `ok`:
// nullptr for a ring inside the image (RingInsideImage); otherwise ok[i] says whether sample i
// lay in the image (value[i] is 0 where it did not).
void SampleRing(const cv::Mat& grey, const Eigen::Vector2d& centre, double radius_px, int samples,
                float* value, uint8_t* ok);

}  // namespace monocle
