// The picture of where a calibration is weak: the 1 sigma of where a ray lands (relative: the
// best common camera rotation taken out, so what shows is where the lens model is unsure), as
// colour over the image, with every corner the views covered: where to hold the board next.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "service/geometry/projection_uncertainty.h"
#include "service/vision/intrinsic_calibration.h"

namespace monocle::cli {

// The colour scale, logarithmic (a calibration is sure to a tenth of a pixel where boards were
// and unsure by pixels where none were): from `bottom_px` to `top_px`, the worst cell
// (relative) rounded up to 1, 2 or 5 times a power of ten, over two decades.
struct UncertaintyScale {
  double bottom_px = 0;
  double top_px = 0;
};
UncertaintyScale UncertaintyScaleOf(const ProjectionUncertaintyMap& map);

// The colour of `sigma_px` on `scale` (viridis: dark blue sure, yellow not).
cv::Vec3b UncertaintyColour(double sigma_px, const UncertaintyScale& scale);

// An image of the calibration's size: the map in colour, a scale bar, the views' corners as
// white dots, the worst cell circled, and a line of figures.
cv::Mat ProjectionUncertaintyPicture(const ProjectionUncertaintyMap& map, const cv::Size& size,
                                     const std::vector<IntrinsicView>& views);

}  // namespace monocle::cli
