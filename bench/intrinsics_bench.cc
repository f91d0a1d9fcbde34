// Intrinsic calibration from 30 views of 1280x1024 on one core: monocle's
// CalibrateIntrinsics (three distortion models fitted and compared, corner blunders
// screened, full covariance) side by side with the baseline a user would otherwise run, one
// cv::calibrateCamera with the k1 k2 p1 p2 model; and board detection per image.
// Run: build/bench/intrinsics_bench  (OpenCV is held to one thread).
#include <benchmark/benchmark.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "camera/render/board_renderer.h"
#include "service/geometry/test_scenes.h"
#include "service/vision/chessboard.h"
#include "service/vision/intrinsic_calibration.h"

namespace monocle {
namespace {

constexpr int kViews = 30;
const CheckerPattern kBoard{9, 6, 0.04};

struct Data {
  std::vector<cv::Mat> images;
  std::vector<IntrinsicView> views;
};

const Data& Views() {
  static const Data data = [] {
    cv::setNumThreads(1);
    Data d;
    const auto k = testing::PaperCamera();
    const auto poses = RandomBoardViews(k, kBoard, kViews, 11, ViewSpread::kGood);
    for (size_t i = 0; i < poses.size(); ++i) {
      CheckerPattern pattern = kBoard;
      const auto look = RandomBoardLook(500 + i, k, &pattern);
      d.images.push_back(RenderBoardView(k, poses[i], pattern, look, 500 + i));
      auto board = DetectChessboard(d.images.back(), {kBoard.cols, kBoard.rows, kBoard.square_m});
      if (board) d.views.push_back({"view", std::move(*board)});
    }
    return d;
  }();
  return data;
}

void BM_MonocleCalibrateIntrinsics(benchmark::State& state) {
  const auto& d = Views();
  for (auto _ : state) {
    auto cal = CalibrateIntrinsics(d.views, {1280, 1024});
    benchmark::DoNotOptimize(cal);
  }
  state.counters["views"] = static_cast<double>(d.views.size());
}
BENCHMARK(BM_MonocleCalibrateIntrinsics)->Unit(benchmark::kMillisecond);

void BM_BaselineCalibrateCamera(benchmark::State& state) {
  const auto& d = Views();
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  for (const auto& v : d.views) {
    object.emplace_back();
    image.emplace_back();
    for (int j = 0; j < v.board.rows; ++j)
      for (int i = 0; i < v.board.cols; ++i) {
        object.back().emplace_back(v.board.BoardPoint(i, j).x(), v.board.BoardPoint(i, j).y(), 0.f);
        image.back().emplace_back(v.board.Pixel(i, j).x(), v.board.Pixel(i, j).y());
      }
  }
  for (auto _ : state) {
    cv::Mat camera_matrix, dist;
    std::vector<cv::Mat> rvecs, tvecs;
    benchmark::DoNotOptimize(cv::calibrateCamera(object, image, {1280, 1024}, camera_matrix, dist,
                                                 rvecs, tvecs, cv::CALIB_FIX_K3));
  }
}
BENCHMARK(BM_BaselineCalibrateCamera)->Unit(benchmark::kMillisecond);

void BM_DetectBoard1280x1024(benchmark::State& state) {
  const auto& d = Views();
  size_t i = 0;
  for (auto _ : state) {
    auto board = DetectChessboard(d.images[i++ % d.images.size()],
                                  {kBoard.cols, kBoard.rows, kBoard.square_m});
    benchmark::DoNotOptimize(board);
  }
}
BENCHMARK(BM_DetectBoard1280x1024)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace monocle

BENCHMARK_MAIN();
