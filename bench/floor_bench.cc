// Floor calibration and measurement speed. Run: build/bench/floor_bench
// Goals (issue 2): calibration of one 1280x1024 image <= 100 ms; measurement >= 1 M
// points/s on one core.
#include <benchmark/benchmark.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <random>

#include "camera/render/floor_renderer.h"
#include "service/geometry/floor_calibration.h"
#include "service/geometry/floor_model.h"
#include "service/geometry/test_scenes.h"
#include "service/vision/chessboard.h"

namespace monocle {
namespace {

using testing::Deg;

const FloorPose kPose{1.05, Deg(118), Deg(4), Deg(1.5)};

cv::Mat BoardImage() {
  FloorScene scene;
  scene.board_cols = 11;
  scene.board_rows = 8;
  scene.square_m = 0.05;
  scene.board_origin_robot_m = CenteredBoardOrigin(kPose, 11, 8, 0.05);
  scene.noise_sigma = 2;
  return RenderFloorScene(testing::PaperCamera(), kPose, scene);
}

std::vector<Eigen::Vector2d> FloorPixels(int n) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1279), v(600, 1023);
  std::vector<Eigen::Vector2d> px(n);
  for (auto& p : px) p = Eigen::Vector2d(u(rng), v(rng));
  return px;
}

void BM_DetectChessboard(benchmark::State& state) {
  cv::setNumThreads(1);
  const cv::Mat image = BoardImage();
  for (auto _ : state) benchmark::DoNotOptimize(DetectChessboard(image, BoardSpec{11, 8, 0.05}));
}
BENCHMARK(BM_DetectChessboard)->Unit(benchmark::kMillisecond);

void BM_CalibrateFromImage(benchmark::State& state) {
  cv::setNumThreads(1);
  const cv::Mat image = BoardImage();
  const auto method =
      state.range(0) ? FloorCalibrationMethod::kFull : FloorCalibrationMethod::kPaper;
  for (auto _ : state) {
    const auto board = DetectChessboard(image, BoardSpec{11, 8, 0.05});
    benchmark::DoNotOptimize(CalibrateFloor(testing::PaperCamera(), *board, method));
  }
  state.SetLabel(method == FloorCalibrationMethod::kFull ? "full" : "paper");
}
BENCHMARK(BM_CalibrateFromImage)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

void BM_FitOnly(benchmark::State& state) {
  const auto board = DetectChessboard(BoardImage(), BoardSpec{11, 8, 0.05});
  const auto method =
      state.range(0) ? FloorCalibrationMethod::kFull : FloorCalibrationMethod::kPaper;
  for (auto _ : state)
    benchmark::DoNotOptimize(CalibrateFloor(testing::PaperCamera(), *board, method));
  state.SetLabel(method == FloorCalibrationMethod::kFull ? "full" : "paper");
}
BENCHMARK(BM_FitOnly)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

void BM_MeasureFloorPoint(benchmark::State& state) {
  const auto k = testing::PaperCamera();
  const auto pixels = FloorPixels(4096);
  MeasurementNoise noise;
  noise.pose_covariance = FloorCovariance::Identity() * 1e-8;
  noise.pixel_sigma_px = 0.5;
  for (auto _ : state) {
    for (const auto& px : pixels) benchmark::DoNotOptimize(MeasureFloorPoint(k, kPose, noise, px));
  }
  state.SetItemsProcessed(state.iterations() * pixels.size());
  state.SetLabel("with 1-sigma");
}
BENCHMARK(BM_MeasureFloorPoint);

void BM_FloorPointOnly(benchmark::State& state) {
  const auto k = testing::PaperCamera();
  const auto pixels = FloorPixels(4096);
  for (auto _ : state) {
    for (const auto& px : pixels) benchmark::DoNotOptimize(FloorPointFromPixel(k, kPose, px));
  }
  state.SetItemsProcessed(state.iterations() * pixels.size());
  state.SetLabel("no sigma");
}
BENCHMARK(BM_FloorPointOnly);

void BM_MeasureVerticalPoint(benchmark::State& state) {
  const auto k = testing::PaperCamera();
  const auto pixels = FloorPixels(4096);
  MeasurementNoise noise;
  noise.pose_covariance = FloorCovariance::Identity() * 1e-8;
  noise.pixel_sigma_px = 0.5;
  for (auto _ : state) {
    for (const auto& px : pixels) {
      benchmark::DoNotOptimize(
          MeasureVerticalPoint(k, kPose, noise, px, px - Eigen::Vector2d(0, 50)));
    }
  }
  state.SetItemsProcessed(state.iterations() * pixels.size());
}
BENCHMARK(BM_MeasureVerticalPoint);

// Baseline: OpenCV's own undistortion of the same pixels (batched), to compare with ours.
void BM_OpenCvUndistortPoints(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto k = testing::PaperCamera();
  const auto pixels = FloorPixels(4096);
  std::vector<cv::Point2d> in, out;
  for (const auto& p : pixels) in.emplace_back(p.x(), p.y());
  const cv::Matx33d m(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  const std::vector<double> dist(k.distortion.begin(), k.distortion.begin() + 4);
  const auto criteria =
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, state.range(0), 1e-12);
  for (auto _ : state) {
    cv::undistortPoints(in, out, m, dist, cv::noArray(), cv::noArray(), criteria);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * pixels.size());
  state.SetLabel(state.range(0) == 5 ? "OpenCV default 5 iterations" : "OpenCV to 1e-12");
}
BENCHMARK(BM_OpenCvUndistortPoints)->Arg(5)->Arg(100);

void BM_OurUndistort(benchmark::State& state) {
  const auto k = testing::PaperCamera();
  const auto pixels = FloorPixels(4096);
  for (auto _ : state) {
    for (const auto& px : pixels) benchmark::DoNotOptimize(PixelToNormalized(k, px));
  }
  state.SetItemsProcessed(state.iterations() * pixels.size());
  state.SetLabel("Newton to 1e-15");
}
BENCHMARK(BM_OurUndistort);

}  // namespace
}  // namespace monocle

BENCHMARK_MAIN();
