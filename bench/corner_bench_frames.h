// The frames both corner benchmarks use: 72 distinct 1280x1024 views, a third each clean,
// cluttered (lamp, door, fixture, cable, uneven light) and realistic (white-painted room,
// vignetting, hot-spot, blur, noise, JPEG), with their ground truth.
#pragma once

#include <opencv2/core.hpp>
#include <random>
#include <string>
#include <vector>

#include "camera/render/corner_renderer.h"
#include "service/geometry/corner_test_scenes.h"
#include "service/geometry/test_scenes.h"

namespace monocle::bench {

struct BenchFrame {
  cv::Mat image;
  CornerPose truth;
  std::string kind;  // clean, cluttered, realistic
};

inline std::vector<BenchFrame> RenderBenchFrames(int per_kind = 24) {
  const CameraIntrinsics k = testing::PaperCamera();
  std::mt19937_64 rng(42);
  std::vector<BenchFrame> frames;
  for (const std::string kind : {"clean", "cluttered", "realistic"}) {
    for (int i = 0; i < per_kind; ++i) {
      const auto pose = kind == "realistic" ? testing::RandomRealisticCornerPose(rng, k, i % 3 == 0)
                                            : testing::RandomCornerPose(rng, k, 60);
      if (!pose) continue;
      CornerScene scene;
      scene.seed = 4200 + frames.size();
      scene.room_height_m = pose->z_m + 1.2;
      scene.noise_sigma = 2;
      scene.clutter = scene.uneven_lighting = kind == "cluttered";
      if (kind == "realistic") scene.realistic = RandomRealisticLook(scene.seed, k);
      frames.push_back({RenderCornerScene(k, *pose, scene), *pose, kind});
    }
  }
  return frames;
}

}  // namespace monocle::bench
