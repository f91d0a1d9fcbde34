// The edge model of corner_edge_information against the renderer itself: the Fisher
// information the renderer's pixels carry about the pose, by central differences of
// noise-free renders, must be what the model integrates along the three edges.
#include "tests/accuracy/corner_edge_information.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <iomanip>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <random>

#include "camera/render/corner_renderer.h"
#include "camera/render/reference_camera.h"
#include "service/geometry/corner_test_scenes.h"
#include "service/geometry/test_scenes.h"

namespace monocle::testing {
namespace {

// A white-room look with nothing but the edges: no shading, vignetting or hot-spot (those
// would carry pose information through the renderer's lighting model, which the edge model
// leaves out on purpose). Rendered as the light on the sensor (RenderCornerExposure), before
// noise, rounding and JPEG: rounding would add noise to the differences.
CornerScene EdgesOnlyScene(double blur_sigma_px, const CornerPose& pose) {
  RealisticLook look;
  look.ceiling_grey = 210;
  look.wall_x0_grey = 90;
  look.wall_y0_grey = 150;
  look.vignetting = 0;
  look.hotspot_gain = 0;
  look.blur_sigma_px = blur_sigma_px;
  look.noise_sigma = 0;
  look.jpeg_quality = 0;
  CornerScene scene;
  scene.realistic = look;
  scene.room_height_m = pose.z_m + 1.2;
  return scene;
}

struct Comparison {
  PoseMatrix model, renderer;                    // information about (x, y, pan, tilt, swing)
  PoseMatrix model_in_basis, renderer_in_basis;  // in the model's scaled eigenbasis
};

// Both informations for noise sigma 1, over the pixels within 6 px of the edges and more than
// 10 px from where an edge ends (the corner, the far walls, the floor), where the model's
// straight steps give way to junctions.
Comparison CompareWithRenderer(const CornerPose& pose, double blur_sigma_px) {
  const CameraIntrinsics k = PaperCamera();
  const CornerScene scene = EdgesOnlyScene(blur_sigma_px, pose);
  const std::array<double, 3> lengths{scene.room_size_m, scene.room_size_m, scene.room_height_m};
  const Eigen::Matrix3d r = reference::RotationCameraFromCorner(pose);
  const Eigen::Vector3d t = -r * Eigen::Vector3d(pose.x_m, pose.y_m, pose.z_m);
  std::vector<Eigen::Vector3d> ends{Eigen::Vector3d::Zero()};
  for (int axis = 0; axis < 3; ++axis) {
    if ((r * (lengths[axis] * Eigen::Vector3d::Unit(axis)) + t).z() > 0.05)
      ends.push_back(lengths[axis] * Eigen::Vector3d::Unit(axis));
  }
  const auto end_px = reference::ProjectPoints(k, r, t, ends);
  auto near_an_end = [&](const Eigen::Vector2d& p) {
    for (const auto& e : end_px)
      if (std::hypot(p.x() - e.x, p.y() - e.y) < 10) return true;
    return false;
  };
  auto samples = SampleCornerEdges(k, pose, lengths);
  std::erase_if(samples, [&](const EdgeSample& s) { return near_an_end(s.pixel); });

  const cv::Mat image = RenderCornerExposure(k, pose, scene);
  Comparison out;
  // The model adds 8-bit rounding's 1/12 to the noise variance: make the total 1.
  out.model = CornerEdgeFisherInformation(samples, EdgeContrastGrey(samples, image), blur_sigma_px,
                                          /*noise_sigma_grey=*/std::sqrt(1 - 1.0 / 12));

  cv::Mat band = cv::Mat::zeros(k.height_px, k.width_px, CV_8U);
  for (size_t i = 0; i + 1 < samples.size(); ++i) {
    if (samples[i].axis != samples[i + 1].axis) continue;
    cv::line(band, cv::Point2d(samples[i].pixel.x(), samples[i].pixel.y()),
             cv::Point2d(samples[i + 1].pixel.x(), samples[i + 1].pixel.y()), 255, 13);
  }
  for (const auto& e : end_px) cv::circle(band, e, 10, 0, cv::FILLED);

  cv::Mat weight;
  band.convertTo(weight, CV_64F, 1.0 / 255);
  // The renderer's information in the model's eigenbasis, each direction scaled so that the
  // edges move 0.5 px at most: the weakest directions (eigenvalues 1e-6 of the largest) are
  // measured by their own differences, not as near-cancelling sums of the parameters'.
  const Eigen::SelfAdjointEigenSolver<PoseMatrix> eigen(out.model);
  PoseMatrix basis;  // columns: pose change of each direction
  std::array<cv::Mat, 5> difference;
  for (int e = 0; e < 5; ++e) {
    const PoseVector u = eigen.eigenvectors().col(e);
    double largest_shift = 0;
    for (const auto& sample : samples)
      largest_shift = std::max(largest_shift, std::abs(sample.normal_shift_px.dot(u)));
    basis.col(e) = 0.5 / largest_shift * u;
    cv::Mat plus, minus;
    RenderCornerExposure(k, MovedBy(pose, basis.col(e)), scene).convertTo(plus, CV_64F);
    RenderCornerExposure(k, MovedBy(pose, -basis.col(e)), scene).convertTo(minus, CV_64F);
    difference[e] = (plus - minus) / 2;
  }
  PoseMatrix in_basis;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) in_basis(i, j) = difference[i].dot(difference[j].mul(weight));
  const PoseMatrix basis_inverse = basis.inverse();
  out.renderer = basis_inverse.transpose() * in_basis * basis_inverse;
  out.model_in_basis = basis.transpose() * out.model * basis;
  out.renderer_in_basis = in_basis;
  return out;
}

double HorizontalSigma(const PoseMatrix& information) {
  return std::sqrt(HorizontalPositionBound(information).trace());
}

TEST(CornerEdgeInformationTest, TheModelCarriesTheInformationTheRenderersPixelsCarry) {
  // Three views of the realistic set's kind: seeded, the third with a short edge.
  std::mt19937_64 rng(20261125);
  for (int view = 0; view < 3; ++view) {
    const auto p = RandomRealisticCornerPose(rng, PaperCamera(), /*short_edge=*/view == 2);
    ASSERT_TRUE(p);
    for (const double blur : {0.8, 1.5}) {
      const Comparison c = CompareWithRenderer(*p, blur);
      const PoseVector ratio =
          c.renderer_in_basis.diagonal().array() / c.model_in_basis.diagonal().array();
      const double bound_ratio = HorizontalSigma(c.model) / HorizontalSigma(c.renderer);
      std::cout << "pose " << *p << ", blur " << blur
                << " px: information along the model's eigenvectors, weakest first, renderer / "
                << "model " << ratio.transpose() << "; horizontal 1 sigma bound "
                << std::setprecision(3) << 1e3 * HorizontalSigma(c.model)
                << " mm per grey level of noise, model / renderer " << bound_ratio << "\n";
      for (int e = 0; e < 5; ++e) EXPECT_NEAR(ratio[e], 1.0, 0.1) << "direction " << e;
      EXPECT_NEAR(bound_ratio, 1.0, 0.1);
    }
  }
}

}  // namespace
}  // namespace monocle::testing
