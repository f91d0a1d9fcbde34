// What placing a corner pose in a room map costs per frame, beside what the frame's corner
// pose itself costs, in the same run: the example hall (7 corners in two rooms), 24 views of
// the example drive rendered with the realistic look. The map step tries every corner (scale,
// place, inside test, sight lines past every wall, edge extents) and the level update.
// Run: taskset -c 0 build/bench/map_bench
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>

#include "camera/render/room_renderer.h"
#include "service/geometry/map_pose_tracker.h"
#include "service/io/base_trajectory_file.h"
#include "service/io/calibration_file.h"
#include "service/io/room_map_file.h"
#include "service/vision/corner_locator.h"

namespace monocle {
namespace {

struct Scene {
  RoomMap map;
  RigidTransform mount;
  CameraIntrinsics k;
  std::vector<cv::Mat> images;
  std::vector<CornerLocation> located;  // the views with a corner pose
};

const Scene& Load() {
  static const Scene scene = [] {
    const std::string dir = std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/";
    Scene s;
    s.map = LoadRoomMapFile(dir + "room_map.pbtxt").value();
    s.mount = LoadCameraMountFile(dir + "camera_mount.pbtxt", s.map).value();
    s.k = LoadCalibrationFile(dir + "wide_camera.pbtxt").value().intrinsics;
    const auto drive = LoadBaseTrajectoryFile(dir + "drive.txt").value();
    for (size_t i = 0; i < drive.size(); ++i) {
      Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
      t.translate(Eigen::Vector3d(drive[i].x_m, drive[i].y_m, 0));
      t.rotate(Eigen::AngleAxisd(drive[i].heading_rad, Eigen::Vector3d::UnitZ()));
      t.translate(s.mount.translation);
      t.rotate(s.mount.rotation);
      RoomScene look;
      look.realistic = RandomRealisticLook(500 + i, s.k);
      look.seed = 500 + i;
      s.images.push_back(RenderRoomView(s.k, s.map.rooms[0], t, look));
      const auto r = LocateCorner(s.images.back(), s.k, 2.2);
      if (r) s.located.push_back(*r);
    }
    return s;
  }();
  return scene;
}

void BM_CornerPoseOfTheFrame(benchmark::State& state) {
  cv::setNumThreads(1);
  const Scene& s = Load();
  size_t i = 0;
  for (auto _ : state) {
    auto r = LocateCorner(s.images[i], s.k, 2.2);
    benchmark::DoNotOptimize(r);
    i = (i + 1) % s.images.size();
  }
  state.SetLabel("baseline: LocateCorner on the room views (1280x1024)");
}
BENCHMARK(BM_CornerPoseOfTheFrame)->Unit(benchmark::kMillisecond);

void BM_PlaceInMap(benchmark::State& state) {
  const Scene& s = Load();
  MapPoseTracker tracker(s.map, s.mount);
  tracker.SetPose({1.4, 1.3, -20 * M_PI / 180});
  size_t i = 0, decided = 0, total = 0;
  for (auto _ : state) {
    const CornerLocation& c = s.located[i];
    const auto where = tracker.Next(
        c.pose, c.covariance, SeenEdgeExtentsAtLeast(s.k, c.pose, c.corner_px, c.line_end_px));
    decided += where.decided();
    ++total;
    benchmark::DoNotOptimize(where);
    if (++i == s.located.size()) {
      i = 0;
      tracker.SetPose({1.4, 1.3, -20 * M_PI / 180});  // the drive starts over
    }
  }
  state.counters["decided"] = static_cast<double>(decided) / total;
  state.SetLabel("map step: 7 corners, tracker with prior");
}
BENCHMARK(BM_PlaceInMap)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace monocle

BENCHMARK_MAIN();
