// Corner pose per 1280x1024 frame on one core, beside the baseline a user would write:
// OpenCV Canny + HoughLines on the same frames. Goal (issue 3): <= 0.4x the baseline.
// Run: taskset -c 0 build/bench/corner_bench
#include <benchmark/benchmark.h>

#include <chrono>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "camera/render/corner_renderer.h"
#include "service/geometry/corner_test_scenes.h"
#include "service/geometry/test_scenes.h"
#include "service/vision/corner_locator.h"

namespace monocle {
namespace {

struct Frames {
  std::vector<cv::Mat> images;
  std::vector<CornerPose> truth;
};

const Frames& TestFrames() {
  static const Frames frames = [] {
    Frames f;
    const auto k = testing::PaperCamera();
    std::mt19937_64 rng(42);
    for (int i = 0; i < 8; ++i) {
      const auto pose = testing::RandomCornerPose(rng, k, 60);
      CornerScene scene;
      scene.noise_sigma = 2;
      scene.seed = i;
      scene.room_height_m = pose->z_m + 1.2;
      f.images.push_back(RenderCornerScene(k, *pose, scene));
      f.truth.push_back(*pose);
    }
    return f;
  }();
  return frames;
}

void BM_CornerPose(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& frames = TestFrames();
  const auto k = testing::PaperCamera();
  size_t i = 0, located = 0, total = 0;
  for (auto _ : state) {
    const auto r = LocateCorner(frames.images[i], k, frames.truth[i].z_m);
    located += r.ok();
    ++total;
    benchmark::DoNotOptimize(r);
    i = (i + 1) % frames.images.size();
  }
  state.counters["located"] = static_cast<double>(located) / total;
  state.SetLabel("monocle: detect + subpixel + closed form + refine");
}
BENCHMARK(BM_CornerPose)->Unit(benchmark::kMillisecond);

void BM_CornerDetectionOnly(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& frames = TestFrames();
  const auto k = testing::PaperCamera();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(DetectCornerEdges(frames.images[i], {}, &k));
    i = (i + 1) % frames.images.size();
  }
}
BENCHMARK(BM_CornerDetectionOnly)->Unit(benchmark::kMillisecond);

void BM_BaselineCannyHoughLines(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& frames = TestFrames();
  size_t i = 0;
  cv::Mat edges;
  std::vector<cv::Vec2f> lines;
  for (auto _ : state) {
    cv::Canny(frames.images[i], edges, 50, 150);
    cv::HoughLines(edges, lines, 1, CV_PI / 360, 150);
    benchmark::DoNotOptimize(lines.data());
    i = (i + 1) % frames.images.size();
  }
  state.SetLabel("OpenCV Canny(50,150) + HoughLines(1 px, 0.5 deg)");
}
BENCHMARK(BM_BaselineCannyHoughLines)->Unit(benchmark::kMillisecond);

// Both on the same frames, alternately, so machine noise hits them alike: the ratio of
// their total times is the figure to read.
void BM_InterleavedRatio(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& frames = TestFrames();
  const auto k = testing::PaperCamera();
  cv::Mat edges;
  std::vector<cv::Vec2f> lines;
  double ours_s = 0, baseline_s = 0;
  size_t i = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(LocateCorner(frames.images[i], k, frames.truth[i].z_m));
    const auto t1 = std::chrono::steady_clock::now();
    cv::Canny(frames.images[i], edges, 50, 150);
    cv::HoughLines(edges, lines, 1, CV_PI / 360, 150);
    benchmark::DoNotOptimize(lines.data());
    const auto t2 = std::chrono::steady_clock::now();
    ours_s += std::chrono::duration<double>(t1 - t0).count();
    baseline_s += std::chrono::duration<double>(t2 - t1).count();
    i = (i + 1) % frames.images.size();
  }
  state.counters["monocle_ms"] = 1e3 * ours_s / state.iterations();
  state.counters["baseline_ms"] = 1e3 * baseline_s / state.iterations();
  state.counters["ratio"] = ours_s / baseline_s;
}
BENCHMARK(BM_InterleavedRatio)->Unit(benchmark::kMillisecond);

void BM_ClosedFormOnly(benchmark::State& state) {
  const auto& frames = TestFrames();
  const auto rays = testing::ExactRays(frames.truth[0], {0, 1, 2});
  for (auto _ : state) benchmark::DoNotOptimize(SolveCornerClosedForm(rays, frames.truth[0].z_m));
}
BENCHMARK(BM_ClosedFormOnly)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace monocle

BENCHMARK_MAIN();
