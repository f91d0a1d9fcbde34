// Corner pose per 1280x1024 frame on one core, beside the baseline a user would write:
// OpenCV Canny + HoughLines on the same frames (72 distinct: clean, cluttered, realistic).
// Beside OpenCV contrib's FastLineDetector and EdgeDrawing too (segments only, no pose).
// Goals (issues 11 and 62): full detection <= 0.4x Canny + HoughLines and <= 0.45x
// FastLineDetector; tracking <= 0.3 ms per frame.
// Failed frames are counted, and their time is counted too (a failure is not free).
// Run: taskset -c 0 build/bench/corner_bench
// Whole processes (start-up and image decoding included): build/bench/corner_process_bench.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/corner_bench_frames.h"
#include "bench/line_baselines.h"
#include "camera/render/driving_path.h"
#include "service/geometry/corner_intrinsics_uncertainty.h"
#include "service/geometry/mount_fit.h"
#include "service/geometry/robot_test_scenes.h"
#include "service/vision/corner_level.h"
#include "service/vision/corner_rays.h"
#include "service/vision/corner_tracker.h"
#include "service/vision/edge_profile.h"

namespace monocle {
namespace {

const std::vector<bench::BenchFrame>& Frames() {
  static const auto frames = bench::RenderBenchFrames();
  return frames;
}

// The baseline's settings: Canny's two thresholds and HoughLines' vote threshold.
struct BaselineSettings {
  double canny_low = 50, canny_high = 150;
  int hough_votes = 150;
};

void Baseline(const cv::Mat& image, cv::Mat* edges, std::vector<cv::Vec2f>* lines,
              const BaselineSettings& settings = {}) {
  cv::Canny(image, *edges, settings.canny_low, settings.canny_high);
  cv::HoughLines(*edges, *lines, 1, CV_PI / 360, settings.hough_votes);
}

// Whether the baseline's lines hold the corner's three edges (each within 3 px on average
// over its first 60 cm from the corner, in the image's own pixels): what a user of the
// baseline would need to go on and find the Y. Not timed.
bool BaselineSeesTheY(const bench::BenchFrame& frame, const std::vector<cv::Vec2f>& lines) {
  const auto k = testing::PaperCamera();
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<Eigen::Vector2d> edge_px;
    for (double t_m = 0.01; t_m <= 0.6; t_m += 0.01) {
      const Eigen::Vector3d p = CornerToCamera(frame.truth, t_m * Eigen::Vector3d::Unit(axis));
      if (p.z() <= 0) break;
      const Eigen::Vector2d px = NormalizedToPixel(k, p.head<2>() / p.z());
      if (px.x() < 0 || px.y() < 0 || px.x() > k.width_px || px.y() > k.height_px) break;
      edge_px.push_back(px);
    }
    const bool seen = std::any_of(lines.begin(), lines.end(), [&](const cv::Vec2f& line) {
      double sum_px = 0;
      for (const auto& q : edge_px)
        sum_px += std::abs(q.x() * std::cos(line[1]) + q.y() * std::sin(line[1]) - line[0]);
      return edge_px.size() > 5 && sum_px / edge_px.size() < 3;
    });
    if (!seen) return false;
  }
  return true;
}

void BM_CornerPose(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& frames = Frames();
  const auto k = testing::PaperCamera();
  size_t i = 0, failed = 0, total = 0;
  for (auto _ : state) {
    const auto r = LocateCorner(frames[i].image, k, frames[i].truth.z_m);
    failed += !r.ok();
    ++total;
    benchmark::DoNotOptimize(r);
    i = (i + 1) % frames.size();
  }
  state.counters["failed"] = static_cast<double>(failed) / total;
  state.SetLabel("monocle: detect + subpixel + closed form + refine, 72 frames");
}
BENCHMARK(BM_CornerPose)->Unit(benchmark::kMillisecond);

void BM_BaselineCannyHoughLines(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& frames = Frames();
  size_t i = 0;
  cv::Mat edges;
  std::vector<cv::Vec2f> lines;
  for (auto _ : state) {
    Baseline(frames[i].image, &edges, &lines);
    benchmark::DoNotOptimize(lines.data());
    i = (i + 1) % frames.size();
  }
  state.SetLabel("OpenCV Canny(50,150) + HoughLines(1 px, 0.5 deg)");
}
BENCHMARK(BM_BaselineCannyHoughLines)->Unit(benchmark::kMillisecond);

// Both on the same frames, alternately, so machine noise hits them alike: the ratio of
// their total times is the figure to read. Arguments: the kind of frame (0 clean,
// 1 cluttered, 2 realistic, 3 all), then the baseline's Canny thresholds and Hough votes.
// `baseline_sees_y`: the fraction of frames whose baseline lines hold the corner's three
// edges. With Canny(50,150) + 150 votes that is none of the realistic frames (and half the
// clean ones: short edges get fewer votes): there the baseline is quick because the
// white-on-white edges never pass its thresholds. The other rows lower the thresholds until
// it sees most Ys; Canny(15,45) saw more but returned hundreds of thousands of lines.
void BM_InterleavedRatio(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& all = Frames();
  static const char* kKinds[] = {"clean", "cluttered", "realistic"};
  std::vector<const bench::BenchFrame*> frames;
  for (const auto& f : all)
    if (state.range(0) == 3 || f.kind == kKinds[state.range(0)]) frames.push_back(&f);
  const BaselineSettings settings{static_cast<double>(state.range(1)),
                                  static_cast<double>(state.range(2)),
                                  static_cast<int>(state.range(3))};
  const auto k = testing::PaperCamera();
  cv::Mat edges;
  std::vector<cv::Vec2f> lines;
  double ours_s = 0, baseline_s = 0;
  size_t i = 0, round = 0, failed = 0, baseline_saw = 0;
  for (auto _ : state) {
    const auto& f = *frames[i];
    // Who goes first alternates: the first to touch a frame reads it from memory (72 frames
    // of 1.3 MB do not stay in the cache), the second from the cache. Always first, ours paid
    // that for both (0.5-0.6 ms more for Canny when it went first).
    bool located = false;
    auto time_ours = [&] {
      const auto t0 = std::chrono::steady_clock::now();
      const auto r = LocateCorner(f.image, k, f.truth.z_m);
      ours_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      located = r.ok();
    };
    auto time_baseline = [&] {
      const auto t0 = std::chrono::steady_clock::now();
      Baseline(f.image, &edges, &lines, settings);
      benchmark::DoNotOptimize(lines.data());
      baseline_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    if (round % 2 == 0) {
      time_ours();
      time_baseline();
    } else {
      time_baseline();
      time_ours();
    }
    failed += !located;
    state.PauseTiming();
    baseline_saw += BaselineSeesTheY(f, lines);
    state.ResumeTiming();
    if (++i == frames.size()) i = 0, ++round;
  }
  state.counters["monocle_ms"] = 1e3 * ours_s / state.iterations();
  state.counters["baseline_ms"] = 1e3 * baseline_s / state.iterations();
  state.counters["ratio"] = ours_s / baseline_s;
  state.counters["failed"] = static_cast<double>(failed) / state.iterations();
  state.counters["baseline_sees_y"] = static_cast<double>(baseline_saw) / state.iterations();
  state.SetLabel(std::string(state.range(0) == 3 ? "all" : kKinds[state.range(0)]) + ", Canny(" +
                 std::to_string(state.range(1)) + "," + std::to_string(state.range(2)) + ") + " +
                 std::to_string(state.range(3)) + " votes");
}
BENCHMARK(BM_InterleavedRatio)
    ->ArgsProduct({{0, 1, 2, 3}, {50}, {150}, {150}})
    ->Args({0, 50, 150, 60})
    ->Args({1, 50, 150, 60})
    ->Args({2, 20, 60, 60})
    ->Unit(benchmark::kMillisecond);

// Beside OpenCV contrib's segment finders on the same frames, alternately (as above):
// FastLineDetector and EdgeDrawing with their documented defaults. They return segments,
// not a corner: the edges' cost alone. Arguments: the kind of frame (as above), the method
// (1 FastLineDetector, 2 EdgeDrawing).
void BM_InterleavedVsSegments(benchmark::State& state) {
  cv::setNumThreads(1);
  static const char* kKinds[] = {"clean", "cluttered", "realistic"};
  std::vector<const bench::BenchFrame*> frames;
  for (const auto& f : Frames())
    if (state.range(0) == 3 || f.kind == kKinds[state.range(0)]) frames.push_back(&f);
  const auto method = static_cast<bench::LineMethod>(state.range(1));
  bench::LineFinder finder(method);
  const auto k = testing::PaperCamera();
  double ours_s = 0, theirs_s = 0;
  size_t i = 0, round = 0, segments = 0;
  for (auto _ : state) {
    const auto& f = *frames[i];
    auto time_ours = [&] {
      const auto t0 = std::chrono::steady_clock::now();
      benchmark::DoNotOptimize(LocateCorner(f.image, k, f.truth.z_m));
      ours_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    auto time_theirs = [&] {
      const auto t0 = std::chrono::steady_clock::now();
      segments += finder.Find(f.image);
      theirs_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
    if (round % 2 == 0) {
      time_ours();
      time_theirs();
    } else {
      time_theirs();
      time_ours();
    }
    if (++i == frames.size()) i = 0, ++round;
  }
  state.counters["monocle_ms"] = 1e3 * ours_s / state.iterations();
  state.counters["baseline_ms"] = 1e3 * theirs_s / state.iterations();
  state.counters["ratio"] = ours_s / theirs_s;
  state.counters["segments"] = static_cast<double>(segments) / state.iterations();
  state.SetLabel(std::string(state.range(0) == 3 ? "all" : kKinds[state.range(0)]) + ", " +
                 bench::LineMethodName(method));
}
BENCHMARK(BM_InterleavedVsSegments)->ArgsProduct({{2, 3}, {1, 2}})->Unit(benchmark::kMillisecond);

// Tracking along a realistic trajectory (1 cm and 0.25 degrees of pan per frame): every
// timed frame is tracked from the previous one (no periodic re-detection).
void BM_Tracking(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto k = testing::PaperCamera();
  static const auto trajectory = [&] {
    std::mt19937_64 rng(43);
    const auto start = testing::RandomRealisticCornerPose(rng, k, false);
    std::vector<std::pair<cv::Mat, CornerPose>> out;
    for (int i = 0; i < 40; ++i) {
      CornerPose p = *start;
      p.x_m += 0.01 * i;
      p.y_m -= 0.006 * i;
      p.pan_rad += 0.25 * std::numbers::pi / 180 * i;
      CornerScene scene;
      scene.room_height_m = p.z_m + 1.2;
      scene.realistic = RandomRealisticLook(11, k);
      scene.seed = 500 + i;
      out.emplace_back(RenderCornerScene(k, p, scene), p);
    }
    return out;
  }();
  CornerTrackerOptions options;
  options.detect_every_n_frames = 1 << 30;
  size_t tracked = 0, total = 0, i = 0;
  CornerTracker tracker(k, trajectory[0].second.z_m, options);
  for (auto _ : state) {
    i = i % (trajectory.size() - 1) + 1;
    if (i == 1) {  // (re)start: detect frame 0, untimed
      state.PauseTiming();
      tracker.Reset();
      (void)tracker.Process(trajectory[0].first);
      state.ResumeTiming();
    }
    const auto r = tracker.Process(trajectory[i].first);
    tracked += r.ok() && r->source == CornerSource::kTracked;
    ++total;
  }
  state.counters["tracked"] = static_cast<double>(tracked) / total;
  state.SetLabel("predict the three edges from the last pose, measure, refine");
}
BENCHMARK(BM_Tracking)->Unit(benchmark::kMillisecond);

// How many 30 fps 1280x1024 corner cameras one core keeps up with: a realistic drive
// (0.6 m/s, 25 deg/s, 4 ms motion blur, the paper's lens) through the tracker as monocled runs
// it (a full detection every 30th frame and whenever tracking fails), every frame timed.
// cameras_per_core = (1 s / 30) / the mean time per frame.
void BM_CamerasPerCore(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto k = testing::PaperCamera();
  static const auto drive = [&] {
    DrivingPath path;
    path.speed_mps = 0.6;
    path.turn_deg_per_s = 25;
    CornerScene scene;
    scene.room_height_m = path.ceiling_distance_m + 1.2;
    scene.realistic = RandomRealisticLook(21, k);
    scene.motion_samples = 3;
    std::vector<cv::Mat> frames;
    for (int i = 0; i < 90; ++i) {
      scene.exposure_end_pose = DrivingPoseAt(path, i / 30.0 + 0.002);
      scene.seed = 900 + i;
      frames.push_back(RenderCornerScene(k, DrivingPoseAt(path, i / 30.0 - 0.002), scene));
    }
    return frames;
  }();
  CornerTracker tracker(k, DrivingPath{}.ceiling_distance_m);
  size_t i = 0, tracked = 0, posed = 0, lap = 0;
  double tracked_ms = 0, other_ms = 0;  // each frame's own time, by how it got its pose
  for (auto _ : state) {
    // Laps run on in time, so the motion model sees one continuous drive per lap.
    if (i == 0) tracker.Reset();
    const auto start = std::chrono::steady_clock::now();
    const auto r = tracker.Process(drive[i], (lap * drive.size() + i) / 30.0);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    posed += r.ok();
    const bool was_tracked = r.ok() && r->source == CornerSource::kTracked;
    tracked += was_tracked;
    (was_tracked ? tracked_ms : other_ms) += ms;
    if (++i == drive.size()) i = 0, ++lap;
  }
  // A tracked frame's time on its own (the mean above includes the detections).
  state.counters["tracked_frame_ms"] = tracked ? tracked_ms / tracked : 0;
  const auto others = static_cast<size_t>(state.iterations()) - tracked;
  state.counters["detected_frame_ms"] = others ? other_ms / others : 0;
  state.counters["tracked"] = static_cast<double>(tracked) / state.iterations();
  state.counters["with_pose"] = static_cast<double>(posed) / state.iterations();
  state.counters["cameras_per_core"] = benchmark::Counter(
      static_cast<double>(state.iterations()) / 30.0, benchmark::Counter::kIsRate);
  state.SetLabel("90-frame realistic drive, tracked as monocled does, frames per second / 30");
}
BENCHMARK(BM_CamerasPerCore)->Unit(benchmark::kMillisecond);

// The check that no edge stronger than the Y's weakest leaves the corner (corner_rays.h),
// part of every pose above, detected or tracked: its share of a frame's time.
void BM_OtherRayCheck(benchmark::State& state) {
  const auto k = testing::PaperCamera();
  struct Y {
    Eigen::Vector2d corner_px;
    std::array<Eigen::Vector2d, 3> direction_px;
  };
  std::vector<Y> ys;
  for (const auto& frame : Frames()) {
    const Eigen::Vector3d c = CornerToCamera(frame.truth, Eigen::Vector3d::Zero());
    Y y{NormalizedToPixel(k, c.head<2>() / c.z()), {}};
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d a = CornerToCamera(frame.truth, 0.05 * Eigen::Vector3d::Unit(axis));
      y.direction_px[axis] = (NormalizedToPixel(k, a.head<2>() / a.z()) - y.corner_px).normalized();
    }
    ys.push_back(y);
  }
  size_t i = 0;
  for (auto _ : state) {
    const auto& frame = Frames()[i % ys.size()];
    benchmark::DoNotOptimize(StrongestOtherRay(frame.image, ys[i % ys.size()].corner_px,
                                               ys[i % ys.size()].direction_px));
    ++i;
  }
  state.SetLabel("10 rings of 24-96 px around the corner, 360 directions");
}
BENCHMARK(BM_OtherRayCheck)->Unit(benchmark::kMicrosecond);

// What carrying a calibration's intrinsics covariance into a located pose costs (added to
// every frame, detected or tracked, whose calibration has one): the located poses' own edges.
void BM_IntrinsicsUncertainty(benchmark::State& state) {
  const auto k = testing::PaperCamera();
  IntrinsicParams sigma;
  sigma << 2.0, 2.0, 3.0, 3.0, 0.01, 0.02, 0.0005, 0.0005, 0.0;
  const IntrinsicsCovariance c = sigma.array().square().matrix().asDiagonal();
  std::vector<std::pair<CornerPose, CornerEdgePixels>> located;
  for (const auto& frame : Frames()) {
    const auto got = LocateCorner(frame.image, k, frame.truth.z_m);
    if (!got) continue;
    CornerEdgePixels edges;
    for (int axis = 0; axis < 3; ++axis) {
      edges.points_px[axis] = got->edges.points_px[axis];
      edges.fitted_points[axis] = got->points_per_line[axis];
    }
    located.emplace_back(got->pose, std::move(edges));
  }
  size_t i = 0;
  for (auto _ : state) {
    const auto& [pose, edges] = located[i++ % located.size()];
    benchmark::DoNotOptimize(CornerPoseCovarianceFromIntrinsics(k, pose, edges, c));
  }
  state.SetLabel("9 intrinsics, the located frames' edge points");
}
BENCHMARK(BM_IntrinsicsUncertainty)->Unit(benchmark::kMicrosecond);

// The two noise estimates every detection starts with (edge_profile.h), over the 72 frames,
// and over the same frames with three quarters of each clipped white by glare: saturated pixels
// are left out, and a row without one skips the masking (bench/corner_speed_notes.md).
void BM_NoiseEstimates(benchmark::State& state) {
  const bool glare = state.range(0) != 0;
  std::vector<cv::Mat> images;
  for (const auto& frame : Frames()) {
    cv::Mat image = frame.image.clone();
    if (glare) image(cv::Rect(0, 0, image.cols * 3 / 4, image.rows)).setTo(255);
    images.push_back(image);
  }
  size_t i = 0;
  for (auto _ : state) {
    const cv::Mat& image = images[i++ % images.size()];
    benchmark::DoNotOptimize(EstimateNoiseSigma(image));
    benchmark::DoNotOptimize(EstimateMeasurementNoiseSigma(image));
  }
  state.SetLabel(glare ? "three quarters clipped white" : "as rendered");
}
BENCHMARK(BM_NoiseEstimates)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_ClosedFormOnly(benchmark::State& state) {
  const auto& frames = Frames();
  const auto rays = testing::ExactRays(frames[0].truth, {0, 1, 2});
  for (auto _ : state) benchmark::DoNotOptimize(SolveCornerClosedForm(rays, frames[0].truth.z_m));
}
BENCHMARK(BM_ClosedFormOnly)->Unit(benchmark::kMicrosecond);

// What the mount's level adds to a located pose (--mount, level_sigma_deg): beside
// BM_CornerPose's milliseconds, a few microseconds.
void BM_MountLevel(benchmark::State& state) {
  const auto& frames = Frames();
  const auto located = LocateCorner(frames[0].image, testing::PaperCamera(), frames[0].truth.z_m);
  if (!located) {
    state.SkipWithError("frame 0 has no pose");
    return;
  }
  const Eigen::Matrix3d corner_from_camera = RotationCameraFromCorner(located->pose).transpose();
  const Eigen::Vector3d axis = corner_from_camera.col(2);
  Eigen::Matrix3d base;
  base.col(0) = Eigen::Vector3d(axis.x(), axis.y(), 0).normalized();
  base.col(2) = -Eigen::Vector3d::UnitZ();
  base.col(1) = base.col(2).cross(base.col(0));
  const RigidTransform mount{Eigen::Quaterniond(base.transpose() * corner_from_camera), {}};
  for (auto _ : state) {
    CornerLocation c = *located;
    ApplyMountLevel(mount, {}, {}, &c);
    benchmark::DoNotOptimize(c.pose);
  }
  state.SetLabel("combine a located pose with its robot's level (an iterated update)");
}
BENCHMARK(BM_MountLevel)->Unit(benchmark::kMicrosecond);

// `corner fit-mount`'s fit over 40 poses (robots at headings all round, the example mount 50
// degrees up, each pose with frame 0's covariance): beside locating the 40 images (40 x
// BM_CornerPose), well under a millisecond.
void BM_FitMountLevel(benchmark::State& state) {
  const auto& frames = Frames();
  const auto located = LocateCorner(frames[0].image, testing::PaperCamera(), frames[0].truth.z_m);
  if (!located) {
    state.SkipWithError("frame 0 has no pose");
    return;
  }
  const RigidTransform mount = testing::MountLookingUp(50, 0);
  std::vector<MountFitPose> poses;
  for (int i = 0; i < 40; ++i) {
    const double heading = 2 * std::numbers::pi * i / 40;
    poses.push_back({testing::TruePose(testing::CornerFromBase(heading, 1e-3 * std::sin(3.0 * i),
                                                               1e-3 * std::cos(5.0 * i)),
                                       mount),
                     located->covariance});
  }
  for (auto _ : state) benchmark::DoNotOptimize(FitMountLevel(poses, mount));
  state.SetLabel("fit the mount's tilt and roll to 40 poses (Gauss-Newton, floor sigma, gate)");
}
BENCHMARK(BM_FitMountLevel)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace monocle

BENCHMARK_MAIN();
