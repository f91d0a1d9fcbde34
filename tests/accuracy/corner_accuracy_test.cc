// Accuracy of the corner pose on rendered 1280x1024 images (f ~ 1600 px, the paper camera's
// distortion) against the renderer's ground truth, in three looks:
// - clean: surfaces 50-100 grey levels apart, noise sigma 2;
// - cluttered: lamp, door frame, fixture, cable, picture, uneven light, noise sigma 2;
// - realistic (issue 11): white-painted rooms, surfaces 8-40 grey levels apart, shading,
//   hot-spot, vignetting, defocus, noise sigma 2-4, JPEG 70-90, the corner anywhere with
//   short edges. The detector's constants were set on development seeds only; the seeds
//   here were never looked at while tuning.
// Each test checks the product goals and, tighter, regression gates about 2-3x above the
// values measured when the gates were set (tests/accuracy/README.md).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>

#include "camera/render/corner_renderer.h"
#include "camera/render/reference_camera.h"
#include "service/geometry/corner_test_scenes.h"
#include "service/geometry/test_scenes.h"
#include "service/vision/corner_level.h"
#include "service/vision/corner_locator.h"
#include "tests/accuracy/corner_edge_information.h"
#include "tests/accuracy/corner_view_record.h"

namespace monocle {
namespace {

// kRealisticRaw: the realistic look without the JPEG step, as a GigE or USB3 camera
// delivers frames through Aravis.
enum class Look { kClean, kCluttered, kRealistic, kRealisticRaw };

// How level the robot stands, 1 sigma about each horizontal axis, degrees: a well-levelled
// floor and mount, and the room map's default.
constexpr double kLevelSigmasDeg[] = {0.1, 0.3};

struct Stats {
  int images = 0, located = 0, suspect = 0, unflagged_large = 0;
  int covered = 0, coverage_trials = 0;  // |error| < reported 1 sigma, for x and for y
  int covered_2sigma = 0;                // |error| < 2 sigma, for x and for y
  // Per pose whose reported horizontal 1 sigma is over 0.5 % of the distance (the weakly
  // determined views, where the large errors are): the mean over x and y of (error / 1 sigma)^2,
  // which is 1 on average for an honest Gaussian 1 sigma.
  std::vector<double> weak_view_z2;
  // Poses whose reported horizontal 1 sigma is over 1 % of the distance (the view's geometry
  // and edges allow no better), and how many of all poses are more than 1 % off.
  int sigma_over_1pct = 0, error_over_1pct = 0;
  // How many poses more than 1 % off the reported 1 sigma predicts: the sum over poses of
  // P(|error| > 1 % of the distance) for a round Gaussian of the same total variance.
  double expected_over_1pct = 0;
  std::vector<double> horizontal_rel, tilt_deg, pan_deg, swing_deg;
  std::vector<double> horizontal_rel_trusted;  // poses not flagged suspect
  // Realistic looks: the views drawn with one edge a fifth of the image's width or shorter (a
  // third of them), and the others, whose edges all run longer.
  std::vector<double> horizontal_rel_short_edge, horizontal_rel_long_edges;
  // With the bound (RenderAndLocate's `with_bound`), per located pose: the Cramér–Rao bound
  // of the horizontal position from the three edges (corner_edge_information.h), relative to
  // the distance, its covariance, the distance, and the pose's reported 1 sigma (both as the
  // root of the trace).
  std::vector<double> bound_rel, reported_rel, distance_m;
  std::vector<Eigen::Matrix2d> bound_xy_m2;
  // The same per view, to compare two versions of the locator view by view.
  std::vector<testing::CornerViewRecord> views;
  // Realistic looks: the same poses combined with the level of a robot they are mounted on
  // (ApplyMountLevel), for each level 1 sigma (degrees) of kLevelSigmasDeg.
  std::vector<std::pair<double, Stats>> levelled;

  // The median over the poses of |error| / the bound's sqrt(trace): 0.83 for an efficient
  // estimator (a round Gaussian's), more for a worse one.
  double MedianErrorOverBound() const {
    std::vector<double> ratio;
    for (size_t i = 0; i < bound_rel.size(); ++i) ratio.push_back(horizontal_rel[i] / bound_rel[i]);
    return Percentile(ratio, 0.5);
  }

  // The p95 of the relative error an efficient estimator (one whose errors are the bound's
  // Gaussian) makes over these views, for each of 2000 draws of its errors, sorted.
  std::vector<double> EfficientP95Draws() const {
    std::vector<double> p95s;
    if (bound_xy_m2.empty()) return p95s;
    std::mt19937_64 rng(1);
    std::normal_distribution<double> normal;
    for (int draw = 0; draw < 2000; ++draw) {
      std::vector<double> rel;
      for (size_t i = 0; i < bound_xy_m2.size(); ++i) {
        const Eigen::Matrix2d l = bound_xy_m2[i].llt().matrixL();
        rel.push_back((l * Eigen::Vector2d(normal(rng), normal(rng))).norm() / distance_m[i]);
      }
      p95s.push_back(Percentile(rel, 0.95));
    }
    std::sort(p95s.begin(), p95s.end());
    return p95s;
  }
  // Its typical p95: the median over the draws.
  double EfficientP95() const { return Percentile(EfficientP95Draws(), 0.5); }
  // How often an efficient estimator would meet p95 <= `goal` on these views: the fraction of
  // its draws that do. Near 0.5 the goal is at the limit of what the edges' pixels allow.
  double EfficientMeetsP95(double goal) const {
    const std::vector<double> p95s = EfficientP95Draws();
    if (p95s.empty()) return std::numeric_limits<double>::quiet_NaN();
    const auto met = std::upper_bound(p95s.begin(), p95s.end(), goal) - p95s.begin();
    return static_cast<double>(met) / static_cast<double>(p95s.size());
  }

  // Adds another set's views to these (pooling seeds): counts add, per-view lists join.
  void Merge(const Stats& o) {
    images += o.images, located += o.located, suspect += o.suspect;
    unflagged_large += o.unflagged_large;
    covered += o.covered, coverage_trials += o.coverage_trials, covered_2sigma += o.covered_2sigma;
    sigma_over_1pct += o.sigma_over_1pct, error_over_1pct += o.error_over_1pct;
    expected_over_1pct += o.expected_over_1pct;
    auto join = [](std::vector<double>* to, const std::vector<double>& from) {
      to->insert(to->end(), from.begin(), from.end());
    };
    join(&weak_view_z2, o.weak_view_z2);
    join(&horizontal_rel, o.horizontal_rel), join(&tilt_deg, o.tilt_deg);
    join(&pan_deg, o.pan_deg), join(&swing_deg, o.swing_deg);
    join(&horizontal_rel_trusted, o.horizontal_rel_trusted);
    join(&horizontal_rel_short_edge, o.horizontal_rel_short_edge);
    join(&horizontal_rel_long_edges, o.horizontal_rel_long_edges);
    join(&bound_rel, o.bound_rel), join(&reported_rel, o.reported_rel);
    join(&distance_m, o.distance_m);
    bound_xy_m2.insert(bound_xy_m2.end(), o.bound_xy_m2.begin(), o.bound_xy_m2.end());
    views.insert(views.end(), o.views.begin(), o.views.end());
    if (levelled.empty()) {
      levelled = o.levelled;
    } else {
      for (size_t i = 0; i < levelled.size() && i < o.levelled.size(); ++i)
        levelled[i].second.Merge(o.levelled[i].second);
    }
  }

  static double Percentile(std::vector<double> v, double q) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
  }
  double Coverage() const { return static_cast<double>(covered) / std::max(coverage_trials, 1); }
  double MeanWeakViewZ2() const {
    double sum = 0;
    for (double z2 : weak_view_z2) sum += z2 / static_cast<double>(weak_view_z2.size());
    return sum;
  }
  double Coverage2Sigma() const {
    return static_cast<double>(covered_2sigma) / std::max(coverage_trials, 1);
  }
  void Print(const char* name) const {
    std::cout << std::setprecision(3) << name << ": pose for " << located << "/" << images
              << " images (" << suspect << " flagged suspect); horizontal error median "
              << 100 * Percentile(horizontal_rel, 0.5) << " %, p95 "
              << 100 * Percentile(horizontal_rel, 0.95)
              << " % of the distance (p95 of the poses not "
              << "flagged " << 100 * Percentile(horizontal_rel_trusted, 0.95) << " %); tilt median "
              << Percentile(tilt_deg, 0.5) << " deg, p95 " << Percentile(tilt_deg, 0.95)
              << " deg; pan median " << Percentile(pan_deg, 0.5) << " p95 "
              << Percentile(pan_deg, 0.95) << " deg; swing median " << Percentile(swing_deg, 0.5)
              << " p95 " << Percentile(swing_deg, 0.95) << " deg; 1 sigma of x, y covers "
              << 100 * Coverage() << " % of the errors, 2 sigma " << 100 * Coverage2Sigma()
              << " %; on the " << weak_view_z2.size()
              << " views whose 1 sigma is over 0.5 %, (error / 1 sigma)^2 averages "
              << MeanWeakViewZ2() << " (1 if honest); unflagged > 5 %: " << unflagged_large
              << "; more than 1 % off: " << error_over_1pct << " (the 1 sigma predicts "
              << expected_over_1pct << ")"
              << ", reported 1 sigma over 1 %: " << sigma_over_1pct << "\n";
    if (!horizontal_rel_short_edge.empty()) {
      std::cout << "  one edge a fifth of the image or shorter: "
                << horizontal_rel_short_edge.size() << " poses, median "
                << 100 * Percentile(horizontal_rel_short_edge, 0.5) << " %, p95 "
                << 100 * Percentile(horizontal_rel_short_edge, 0.95)
                << " %; every edge longer: " << horizontal_rel_long_edges.size()
                << " poses, median " << 100 * Percentile(horizontal_rel_long_edges, 0.5)
                << " %, p95 " << 100 * Percentile(horizontal_rel_long_edges, 0.95) << " %\n";
    }
    if (bound_rel.empty()) return;
    std::vector<double> reported_over_bound;
    int bound_over_half_pct = 0;
    for (size_t i = 0; i < bound_rel.size(); ++i) {
      reported_over_bound.push_back(reported_rel[i] / bound_rel[i]);
      bound_over_half_pct += bound_rel[i] > 0.005;
    }
    std::cout << "  Cramer-Rao bound from the three edges: median "
              << 100 * Percentile(bound_rel, 0.5) << " %, p95 " << 100 * Percentile(bound_rel, 0.95)
              << " % of the distance; over 0.5 % in " << bound_over_half_pct
              << " views; an efficient estimator's p95 error " << 100 * EfficientP95()
              << " % (at most 1 % in " << 100 * EfficientMeetsP95(0.01)
              << " % of its noise draws); reported 1 sigma / bound: median "
              << Percentile(reported_over_bound, 0.5) << ", p95 "
              << Percentile(reported_over_bound, 0.95) << "; error / bound: median "
              << MedianErrorOverBound() << "\n";
  }
};

double AngleErrorDeg(double a, double b) {
  return std::abs(std::remainder(a - b, 2 * std::numbers::pi)) * 180 / std::numbers::pi;
}

// The scene of view `index` of a set rendered with `seed`.
CornerScene SceneOfView(const CameraIntrinsics& k, uint64_t seed, int index, Look look,
                        const CornerPose& truth) {
  CornerScene scene;
  scene.noise_sigma = 2;
  scene.seed = seed * 1000 + index;
  scene.clutter = scene.uneven_lighting = look == Look::kCluttered;
  if (look == Look::kRealistic || look == Look::kRealisticRaw)
    scene.realistic = RandomRealisticLook(scene.seed, k);
  if (look == Look::kRealisticRaw) scene.realistic->jpeg_quality = 0;
  scene.room_height_m = truth.z_m + 1.2;
  return scene;
}

double RelativeHorizontalError(const CornerLocation& got, const CornerPose& truth) {
  return std::hypot(got.pose.x_m - truth.x_m, got.pose.y_m - truth.y_m) /
         std::hypot(truth.x_m, truth.y_m);
}

// The Cramér–Rao bound's covariance of the horizontal position (m^2) for a realistic view,
// from a noise-free render of it. Clipped at 255 as the camera clips.
Eigen::Matrix2d HorizontalBound(const CameraIntrinsics& k, const CornerPose& truth,
                                const CornerScene& scene) {
  const cv::Mat exposure = cv::min(RenderCornerExposure(k, truth, scene), 255.0);
  const auto samples = testing::SampleCornerEdges(
      k, truth, {scene.room_size_m, scene.room_size_m, scene.room_height_m});
  const auto information = testing::CornerEdgeFisherInformation(
      samples, testing::EdgeContrastGrey(samples, exposure), scene.realistic->blur_sigma_px,
      scene.realistic->noise_sigma);
  return testing::HorizontalPositionBound(information);
}

// One located pose's errors, against the truth, into `stats`.
void Record(const CornerLocation& got, const CornerPose& truth, Stats* stats_out) {
  Stats& stats = *stats_out;
  ++stats.located;
  stats.suspect += got.suspect;
  const Eigen::Vector2d t(truth.x_m, truth.y_m), g(got.pose.x_m, got.pose.y_m);
  const double rel = (g - t).norm() / t.norm();
  stats.horizontal_rel.push_back(rel);
  if (!got.suspect) stats.horizontal_rel_trusted.push_back(rel);
  stats.tilt_deg.push_back(AngleErrorDeg(got.pose.tilt_rad, truth.tilt_rad));
  stats.pan_deg.push_back(AngleErrorDeg(got.pose.pan_rad, truth.pan_rad));
  stats.swing_deg.push_back(AngleErrorDeg(got.pose.swing_rad, truth.swing_rad));
  const auto sigma = got.Sigma();
  stats.covered += (std::abs(g.x() - t.x()) < sigma[0]) + (std::abs(g.y() - t.y()) < sigma[1]);
  stats.covered_2sigma +=
      (std::abs(g.x() - t.x()) < 2 * sigma[0]) + (std::abs(g.y() - t.y()) < 2 * sigma[1]);
  stats.coverage_trials += 2;
  if (std::hypot(sigma[0], sigma[1]) > 0.005 * t.norm()) {
    stats.weak_view_z2.push_back(
        0.5 * ((g - t).cwiseQuotient(Eigen::Vector2d(sigma[0], sigma[1]))).squaredNorm());
  }
  stats.error_over_1pct += rel > 0.01;
  const double sigma2 = sigma[0] * sigma[0] + sigma[1] * sigma[1];
  stats.sigma_over_1pct += sigma2 > std::pow(0.01 * t.norm(), 2);
  stats.expected_over_1pct += std::exp(-std::pow(0.01 * t.norm(), 2) / sigma2);
  if (rel > 0.05) {
    stats.unflagged_large += !got.suspect;
    std::cout << "large error " << 100 * rel << " %: truth " << truth << " got " << got << "\n";
  }
}

// The mount of a camera at `truth` on a robot base standing level, told to the locator,
// when the base in fact stands tipped by `tip_x_rad`, `tip_y_rad` about the corner frame's X
// and Y axes (the floor's slope): the base's heading is the camera's, and the mount is the
// truth's orientation in the level base. Written from the rotation alone.
RigidTransform LevelMountOf(const CornerPose& truth, double tip_x_rad, double tip_y_rad) {
  const Eigen::Matrix3d corner_from_camera = RotationCameraFromCorner(truth).transpose();
  const Eigen::Vector3d axis = corner_from_camera.col(2);
  Eigen::Matrix3d corner_from_level_base;
  corner_from_level_base.col(0) = Eigen::Vector3d(axis.x(), axis.y(), 0).normalized();
  corner_from_level_base.col(2) = -Eigen::Vector3d::UnitZ();  // up: the corner frame's Z is down
  corner_from_level_base.col(1) =
      corner_from_level_base.col(2).cross(corner_from_level_base.col(0));
  const Eigen::Matrix3d corner_from_base = (Eigen::AngleAxisd(tip_x_rad, Eigen::Vector3d::UnitX()) *
                                            Eigen::AngleAxisd(tip_y_rad, Eigen::Vector3d::UnitY()))
                                               .toRotationMatrix() *
                                           corner_from_level_base;
  RigidTransform mount;
  mount.rotation = Eigen::Quaterniond(corner_from_base.transpose() * corner_from_camera);
  return mount;
}

// `ceiling_scale`: the ceiling distance given to the locator, relative to the truth.
// `with_bound`: also compute each located view's Cramér–Rao bound (realistic looks only).
// Whether RenderAndLocate renders view `index` of `seed`: all of them, unless
// MONOCLE_CORNER_ONLY=FILE lists some ("seed index" per line, as a per-view file of
// MONOCLE_CORNER_VIEWS_OUT starts its lines), to judge a change on the views it can touch (the
// weakly determined ones) in a fraction of the time. The others' random draws are still made,
// so each listed view is the one the full set renders.
bool ViewWanted(uint64_t seed, int index) {
  static const std::set<std::pair<uint64_t, int>>* wanted = [] {
    auto* set = new std::set<std::pair<uint64_t, int>>;
    if (const char* path = std::getenv("MONOCLE_CORNER_ONLY")) {
      std::ifstream in(path);
      uint64_t s;
      int i;
      while (in >> s >> i) set->insert({s, i});
    }
    return set;
  }();
  return wanted->empty() || wanted->count({seed, index}) > 0;
}

Stats RenderAndLocate(int count, uint64_t seed, Look look, double ceiling_scale = 1.0,
                      bool with_bound = false) {
  const CameraIntrinsics k = testing::PaperCamera();
  std::mt19937_64 rng(seed);
  std::mt19937_64 tip_rng(seed + 99);
  std::normal_distribution<double> tip_normal;
  Stats stats;
  for (int i = 0; i < count; ++i) {
    const auto truth = look == Look::kRealistic || look == Look::kRealisticRaw
                           ? testing::RandomRealisticCornerPose(rng, k, /*short_edge=*/i % 3 == 0)
                           : testing::RandomCornerPose(rng, k, /*margin_px=*/60);
    if (!truth) continue;
    if (!ViewWanted(seed, i)) {
      tip_normal(tip_rng), tip_normal(tip_rng);
      continue;
    }
    const CornerScene scene = SceneOfView(k, seed, i, look, *truth);
    const cv::Mat image = RenderCornerScene(k, *truth, scene);
    ++stats.images;
    const auto got = LocateCorner(image, k, ceiling_scale * truth->z_m);
    const bool realistic = look == Look::kRealistic || look == Look::kRealisticRaw;
    const double tip_x = tip_normal(tip_rng), tip_y = tip_normal(tip_rng);
    if (realistic && stats.levelled.empty())
      for (double sigma_deg : kLevelSigmasDeg) stats.levelled.push_back({sigma_deg, {}});
    for (auto& levelled : stats.levelled) ++levelled.second.images;
    if (!got) {
      std::cout << "no pose: " << got.error() << " for " << *truth << "\n";
      continue;
    }
    if (with_bound) {
      const Eigen::Vector2d t(truth->x_m, truth->y_m);
      const Eigen::Matrix2d bound = HorizontalBound(k, *truth, scene);
      stats.bound_xy_m2.push_back(bound);
      stats.bound_rel.push_back(std::sqrt(bound.trace()) / t.norm());
      stats.distance_m.push_back(t.norm());
      stats.reported_rel.push_back(std::hypot(got->Sigma()[0], got->Sigma()[1]) / t.norm());
      stats.views.push_back({seed, i, 100 * RelativeHorizontalError(*got, *truth),
                             100 * stats.bound_rel.back(), 100 * stats.reported_rel.back(),
                             got->suspect, i % 3 == 0});
    }
    Record(*got, *truth, &stats);
    if (realistic) {
      (i % 3 == 0 ? stats.horizontal_rel_short_edge : stats.horizontal_rel_long_edges)
          .push_back(RelativeHorizontalError(*got, *truth));
    }
    // The same pose from a camera on a robot (realistic looks): the floor tips the base by a
    // fresh draw of each level's 1 sigma about each horizontal axis, and the mount the locator
    // is given is the level one.
    for (auto& [sigma_deg, levelled] : stats.levelled) {
      const double sigma_rad = sigma_deg * std::numbers::pi / 180;
      CornerLocation on_robot = *got;
      MountLevelOptions level;
      level.level_sigma_rad = sigma_rad;
      ApplyMountLevel(LevelMountOf(*truth, sigma_rad * tip_x, sigma_rad * tip_y), level, {},
                      &on_robot);
      Record(on_robot, *truth, &levelled);
    }
  }
  return stats;
}

TEST(CornerAccuracyTest, CleanRoomsMeetTheGoalsAndTheRegressionGates) {
  const Stats s = RenderAndLocate(150, 1986, Look::kClean);
  s.Print("clean");
  ASSERT_GT(s.images, 140);
  // Product goals (issue 3).
  EXPECT_GE(s.located, 0.99 * s.images);
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.5), 0.003);
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.95), 0.01);
  EXPECT_LE(Stats::Percentile(s.tilt_deg, 0.5), 0.1);
  // Regression gates, 2-3x above the measured (tests/accuracy/README.md).
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.5), 0.0003);
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.95), 0.002);
  EXPECT_LE(Stats::Percentile(s.tilt_deg, 0.5), 0.004);
  EXPECT_LE(Stats::Percentile(s.tilt_deg, 0.95), 0.035);
  EXPECT_LE(Stats::Percentile(s.pan_deg, 0.5), 0.008);
  EXPECT_LE(Stats::Percentile(s.swing_deg, 0.5), 0.004);
  EXPECT_EQ(s.unflagged_large, 0);
}

TEST(CornerAccuracyTest, ClutterAndUnevenLighting) {
  const Stats s = RenderAndLocate(60, 2024, Look::kCluttered);
  s.Print("cluttered");
  // Product goals, and regression gates 2-3x above the measured (tests/accuracy/README.md).
  EXPECT_GE(s.located, 0.95 * s.images);
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.5), 0.0005);
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.95), 0.012);
  EXPECT_LE(Stats::Percentile(s.tilt_deg, 0.5), 0.008);
  // Known miss (tests/accuracy/README.md): a door frame's corner makes a Y the pose accepts, 23 %
  // off and not flagged. One at most.
  EXPECT_LE(s.unflagged_large, 1);
}

void ExpectRealisticGoals(const Stats& s) {
  ASSERT_GE(s.images, 60);
  // Issue 11's goals.
  EXPECT_GE(s.located, 0.95 * s.images);
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.5), 0.003);
  // p95 <= 1 % is checked over 1152 views (RealisticRoomsOverSixteenSeeds): over one set of
  // 72 views it is the fourth-worst error, which an efficient estimator misses by chance in a
  // third of noise draws. Here, per set, the poses not flagged suspect, gated at about twice
  // the measured value (tests/accuracy/README.md) so it cannot slip.
  EXPECT_LE(Stats::Percentile(s.horizontal_rel_trusted, 0.95), 0.02);
  // Where the tail is: the third of the views drawn with one edge a fifth of the image or
  // shorter. The views whose edges all run longer stay well inside the goal: a regression
  // gate at its 1 %.
  EXPECT_LE(Stats::Percentile(s.horizontal_rel_long_edges, 0.95), 0.01);
  EXPECT_LE(Stats::Percentile(s.tilt_deg, 0.5), 0.1);
  EXPECT_EQ(s.unflagged_large, 0) << "a pose more than 5 % off was not flagged suspect";
  // The reported 1 sigma is honest: it covers 68 +- 10 % of the errors (the current figures:
  // tests/accuracy/README.md).
  EXPECT_GE(s.Coverage(), 0.58);
  EXPECT_LE(s.Coverage(), 0.78);
  // Honest in the tail too, where p95 lives: the large errors come from the weakly
  // determined views, and their 1 sigma must say so, or a user would trust the poses to
  // distrust. 2 sigma covers 95.4 % of a Gaussian's errors (140 trials: +-1.8 % by chance).
  // The weak views' mean (error / 1 sigma)^2 is the check that fails when their 1 sigma is
  // halved; the coverages alone would still pass (tests/accuracy/corner_pose_notes.md).
  EXPECT_GE(s.Coverage2Sigma(), 0.90);
  if (s.weak_view_z2.size() >= 5) {
    EXPECT_LE(s.MeanWeakViewZ2(), 2.0) << "the weakly determined views' 1 sigma is too small";
  }
  // No estimator beats the Cramér–Rao bound: errors as small as its Gaussian's would give a
  // median of 0.83 here, and sampling 70 views moves that by less than 0.1. Below 0.65 the
  // bound would be overstated (corner_edge_information_test checks it against the renderer).
  if (!s.bound_rel.empty()) {
    EXPECT_GE(s.MedianErrorOverBound(), 0.65);
  }
}

// The same views from a camera on a robot standing level to 0.1 and 0.3 degrees (1 sigma
// about each horizontal axis; the floor tipped by a fresh draw of it for each view): the
// mount's level fixes what a weakly determined view leaves open, its tilt (client/cli/GUIDE.md,
// "The mount's level, without a map"). At 0.1 degrees issue 11's goals are met in full, p95 too; at
// 0.3 (the room map's default) the tail gains less. In both the 1 sigma stays honest.
void ExpectLevelledGoals(const Stats& s) {
  ASSERT_EQ(s.levelled.size(), 2u);
  for (const auto& [sigma_deg, l] : s.levelled) {
    const std::string name =
        "  on a robot level to " + std::to_string(sigma_deg).substr(0, 3) + " deg (1 sigma)";
    l.Print(name.c_str());
    EXPECT_EQ(l.located, s.located) << name;
    EXPECT_LE(Stats::Percentile(l.horizontal_rel, 0.5), 0.003) << name;
    EXPECT_LE(Stats::Percentile(l.tilt_deg, 0.5), 0.1) << name;
    EXPECT_EQ(l.unflagged_large, 0) << name;
    EXPECT_GE(l.Coverage(), 0.58) << name;
    EXPECT_LE(l.Coverage(), 0.78) << name;
    EXPECT_GE(l.Coverage2Sigma(), 0.90) << name;
    if (l.weak_view_z2.size() >= 5) {
      EXPECT_LE(l.MeanWeakViewZ2(), 2.0) << name;
    }
    // The level is information: hardly more poses far off than without it. (Not p95 itself:
    // where a view's own tilt is as good as the level's, the tipped floor's draw can move the
    // 95th percentile of 66 views either way.)
    EXPECT_LE(l.error_over_1pct, s.error_over_1pct + 2) << name;
    if (sigma_deg <= 0.1) {
      EXPECT_LE(Stats::Percentile(l.horizontal_rel, 0.95), 0.01) << name;
    }
  }
}

TEST(CornerAccuracyTest, RealisticRooms) {
  const Stats s = RenderAndLocate(72, 2611, Look::kRealistic, 1.0, /*with_bound=*/true);
  s.Print("realistic");
  ExpectRealisticGoals(s);
  ExpectLevelledGoals(s);
  // Regression gates about 2.5x above this seed's measured values (tests/accuracy/README.md);
  // the median's gate is the goal above.
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.95), 0.035);
  EXPECT_LE(Stats::Percentile(s.tilt_deg, 0.5), 0.06);
  EXPECT_LE(Stats::Percentile(s.tilt_deg, 0.95), 1.1);
  EXPECT_LE(Stats::Percentile(s.pan_deg, 0.5), 0.09);
  EXPECT_LE(Stats::Percentile(s.swing_deg, 0.5), 0.05);
}

TEST(CornerAccuracyTest, RealisticRoomsSecondSeed) {
  const Stats s = RenderAndLocate(66, 90210, Look::kRealistic, 1.0, /*with_bound=*/true);
  s.Print("realistic, second seed");
  ExpectRealisticGoals(s);
  ExpectLevelledGoals(s);
}

// Issue 11's goals over many views. The p95 of one set of 72 views is its fourth-worst error,
// and it scatters from set to set far more than the estimator's quality does: even an
// efficient estimator (errors of the Cramér–Rao bound's Gaussian) meets p95 <= 1 % on seed
// 2611's views in only 66 % of noise draws (RealisticRooms prints it). So every goal is
// checked here on 1152 views: sixteen seeds, 1400001-1400016, first rendered on 2026-11-27 and
// run once before this test was written, nothing tuned on them. Measured then: 1144 / 1152
// located (57 suspect), median 0.082 %, p95 0.91 %, tilt median 0.012 deg, 1 sigma coverage
// 73 %, none more than 5 % off unflagged. The p95 gate is the goal's 1 %, and this set meets
// it; the population sits on it rather than under it: over 4032 views of 56 fresh seeds
// (FreshSeedsOnDemand) p95 is 0.98 % (bootstrap 95 % interval 0.91-1.11 %), over 1600001-1600016
// 1.03 %, per set of 72 0.37-4.9 % (tests/accuracy/README.md). Since the shading beside the edges
// is read on weakly determined views (2026-11-28): 72 suspect, median 0.083 %, p95 0.92 %;
// since a Y flagged for more than imprecision gives way to the next (2026-11-28, later): 71
// suspect, p95 0.91 % (view 63 of 1400006, a floor corner 51 % off, is now the ceiling's);
// since weak views are measured twice (2026-11-28, a third sitting): 76 suspect, p95 0.86 %,
// and over 11,993 views of 168 fresh seeds p95 0.92 % (0.86-0.98 %): the population is now
// under the goal too.
TEST(CornerAccuracyTest, RealisticRoomsOverSixteenSeeds) {
  Stats s;
  for (uint64_t seed = 1400001; seed <= 1400016; ++seed)
    s.Merge(RenderAndLocate(72, seed, Look::kRealistic));
  s.Print("realistic, 16 seeds pooled");
  ASSERT_EQ(s.images, 16 * 72);
  ExpectRealisticGoals(s);
  // And p95 itself (see above: a gate at the goal on a set that meets it).
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.95), 0.01);
  // Regression gates, 2-3x above what was measured (median 0.082 %, tilt 0.012 / 0.14 deg,
  // pan 0.021 deg, swing 0.0096 deg; the views with one short edge p95 ~1.9 %).
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.5), 0.002);
  EXPECT_LE(Stats::Percentile(s.tilt_deg, 0.5), 0.03);
  EXPECT_LE(Stats::Percentile(s.tilt_deg, 0.95), 0.4);
  EXPECT_LE(Stats::Percentile(s.pan_deg, 0.5), 0.05);
  EXPECT_LE(Stats::Percentile(s.swing_deg, 0.5), 0.025);
  EXPECT_LE(Stats::Percentile(s.horizontal_rel_short_edge, 0.95), 0.04);
}

// The same views as RealisticRooms, uncompressed, as a machine-vision camera delivers them.
// Edges are judged against the noise an edge measurement sees (EstimateMeasurementNoiseSigma),
// which compression leaves alone; judged against the pixel-to-pixel noise, which JPEG
// removes 2-5x of, the raw frames' faint edges were flagged where the JPEG frames' were not.
TEST(CornerAccuracyTest, RealisticRoomsFromARawCamera) {
  const Stats s = RenderAndLocate(72, 2611, Look::kRealisticRaw, 1.0, /*with_bound=*/true);
  s.Print("realistic, raw frames");
  ExpectRealisticGoals(s);
  ExpectLevelledGoals(s);
  EXPECT_LE(s.suspect, 0.15 * s.located) << "faint but measurable edges flagged";
  EXPECT_LE(Stats::Percentile(s.horizontal_rel, 0.95), 0.04);
}

// The ceiling distance is an input. Every length in the solution scales with it, so a 1 %
// error in it moves the position by 1 % of the distance and leaves the angles alone.
TEST(CornerAccuracyTest, OnePercentCeilingDistanceErrorMovesThePositionByOnePercent) {
  const Stats s = RenderAndLocate(24, 2611, Look::kRealistic, 1.01);
  s.Print("realistic, ceiling distance +1 %");
  ASSERT_GE(s.located, 20);
  EXPECT_NEAR(Stats::Percentile(s.horizontal_rel, 0.5), 0.01, 0.002);
  EXPECT_LE(Stats::Percentile(s.tilt_deg, 0.5), 0.1);
}

// View `index` of RenderAndLocate's realistic set with `seed`, rendered alone.
struct RealisticView {
  CornerPose truth;
  CornerScene scene;
  cv::Mat image;
};
RealisticView RenderRealisticView(const CameraIntrinsics& k, uint64_t seed, int index) {
  std::mt19937_64 rng(seed);
  std::optional<CornerPose> truth;
  for (int i = 0; i <= index; ++i)
    truth = testing::RandomRealisticCornerPose(rng, k, /*short_edge=*/i % 3 == 0);
  RealisticView view;
  view.truth = truth.value();
  view.scene = SceneOfView(k, seed, index, Look::kRealistic, view.truth);
  view.image = RenderCornerScene(k, view.truth, view.scene);
  return view;
}

// How much a view's horizontal position scatters over 16 draws of its sensor noise (the same
// room, pose and look), relative to the distance, beside the Cramér–Rao bound for that view
// (both as the root of the covariance's trace). `raw`: without the JPEG step.
struct NoiseDrawScatter {
  double scatter_rel = 0, bound_rel = 0;
};
NoiseDrawScatter ScatterOverNoiseDraws(const CameraIntrinsics& k, RealisticView view, bool raw) {
  if (raw) view.scene.realistic->jpeg_quality = 0;
  const double distance = std::hypot(view.truth.x_m, view.truth.y_m);
  std::vector<Eigen::Vector2d> errors;
  for (int draw = 0; draw < 16; ++draw) {
    CornerScene scene = view.scene;
    scene.seed = 777000 + draw;
    const auto got = LocateCorner(RenderCornerScene(k, view.truth, scene), k, view.truth.z_m);
    if (got) errors.emplace_back(got->pose.x_m - view.truth.x_m, got->pose.y_m - view.truth.y_m);
  }
  NoiseDrawScatter out;
  out.bound_rel = std::sqrt(HorizontalBound(k, view.truth, view.scene).trace()) / distance;
  if (errors.size() < 12) return out;  // scatter 0: the caller's check fails
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& e : errors) mean += e / static_cast<double>(errors.size());
  double sum2 = 0;
  for (const auto& e : errors) sum2 += (e - mean).squaredNorm();
  out.scatter_rel = std::sqrt(sum2 / (errors.size() - 1)) / distance;
  std::cout << "  scatter over " << errors.size() << " noise draws " << 100 * out.scatter_rel
            << " % of the distance, Cramer-Rao bound " << 100 * out.bound_rel << " %\n";
  return out;
}

// View `index` of seed `seed`'s realistic set (`raw`: without JPEG) scatters over noise
// draws no less than the Cramér–Rao bound allows and less than `max_over_bound` times it.
void ExpectScatterWithinBound(uint64_t seed, int index, bool raw, double max_over_bound) {
  const CameraIntrinsics k = testing::PaperCamera();
  const NoiseDrawScatter s = ScatterOverNoiseDraws(k, RenderRealisticView(k, seed, index), raw);
  EXPECT_GT(s.scatter_rel, s.bound_rel) << "no estimator beats the bound";
  EXPECT_LT(s.scatter_rel, max_over_bound * s.bound_rel);
}

// One realistic view, on demand, over draws of its sensor noise (the same room, pose and
// look): MONOCLE_CORNER_VIEW=SEED:INDEX (the index as the fresh sets count views, from 0),
// MONOCLE_CORNER_DRAWS=N (default 8; draw 0 is the view as the sets render it). Prints each
// draw's error and 1 sigma in x and y, the shift the shading beside the edges predicts (all in
// % of the horizontal distance) and why the pose is suspect: to take apart a view a fresh set
// showed.
TEST(CornerAccuracyTest, OneViewOnDemand) {
  const char* text = std::getenv("MONOCLE_CORNER_VIEW");
  if (text == nullptr) GTEST_SKIP() << "set MONOCLE_CORNER_VIEW=SEED:INDEX to take one view apart";
  uint64_t seed = 0;
  int index = -1;
  ASSERT_EQ(std::sscanf(text, "%" SCNu64 ":%d", &seed, &index), 2)
      << "MONOCLE_CORNER_VIEW: give SEED:INDEX, e.g. 2100011:34";
  ASSERT_GE(index, 0) << "MONOCLE_CORNER_VIEW: the index counts from 0";
  const char* draws_text = std::getenv("MONOCLE_CORNER_DRAWS");
  const int draws = draws_text != nullptr ? std::atoi(draws_text) : 8;
  ASSERT_GT(draws, 0) << "MONOCLE_CORNER_DRAWS: a count of noise draws, e.g. 8";
  const CameraIntrinsics k = testing::PaperCamera();
  const RealisticView view = RenderRealisticView(k, seed, index);
  const double distance = std::hypot(view.truth.x_m, view.truth.y_m);
  std::cout << "view " << index << " of seed " << seed << ": truth " << view.truth
            << "; errors, 1 sigma and the shading's shift in % of the distance " << distance
            << " m\n";
  for (int draw = 0; draw < draws; ++draw) {
    CornerScene scene = view.scene;
    if (draw > 0) scene.seed = 777000 + draw;
    const auto got = LocateCorner(RenderCornerScene(k, view.truth, scene), k, view.truth.z_m);
    if (!got) {
      std::cout << "draw " << draw << ": " << got.error() << "\n";
      continue;
    }
    const auto sigma = got->Sigma();
    const auto percent = [&](double metres) { return 100 * metres / distance; };
    std::cout << std::setprecision(3) << "draw " << draw << ": error "
              << percent(got->pose.x_m - view.truth.x_m) << ", "
              << percent(got->pose.y_m - view.truth.y_m) << " ("
              << 100 * RelativeHorizontalError(*got, view.truth) << "); 1 sigma "
              << percent(sigma[0]) << ", " << percent(sigma[1]) << "; shading's shift "
              << percent(got->shading_shift[0]) << ", " << percent(got->shading_shift[1])
              << (got->suspect ? "; SUSPECT: " + got->suspect_reason : std::string()) << "\n";
  }
}

// View 37 of seed 2611: one edge's contrast fades along it (14 grey levels near the corner,
// its points follow each other for 108 of its 659 px). Fitted with every point alike, the
// faded stretch's noisy points set the direction: the position scattered 4.2x the bound over
// 16 noise draws (0.070 % against 0.017 %). Each point is now weighted by its step squared
// (RobustLineFit): 2.5x (0.042 %; checked by putting equal weights back); 1.3x (0.022 %)
// since each edge is weighted by its own scatter.
TEST(CornerAccuracyTest, AnEdgeWhoseContrastFadesIsFittedByItsClearStretch) {
  ExpectScatterWithinBound(2611, 37, /*raw=*/false, 3.3);
}

// View 36 of seed 2611, raw: two of its edges are short (130 and 200 px to the image's
// border), and the last pixels before the border fix much of a short edge's direction. Edge
// points used to stop 10.5 px from any border (a margin as wide as the profile in every
// direction); they now stop where the profile's own rectangle leaves the image
// (ProfileInside). The position's scatter over 16 noise draws went 1.98x -> 1.64x the bound
// (0.81 % -> 0.67 % against 0.41 %; checked by putting the old margin back).
TEST(CornerAccuracyTest, ShortEdgesAreMeasuredUpToTheBorder) {
  ExpectScatterWithinBound(2611, 36, /*raw=*/true, 1.85);
}

// View 9 of seed 2611, raw: a clear edge (34 grey levels, 200 px) and two faint ones (12 and
// 9 grey levels, 890 and 150 px) whose points scatter 4-5x as much. With one scatter pooled
// over the three edges, the faint edges' points counted as much as the clear one's and pulled
// the corner: the position scattered 2.7x the bound over 16 noise draws (2.63 % against
// 0.96 %). Each edge is now weighted by its own points' scatter (LocateCornerFromEdges): 1.9x
// (1.83 %; checked by pooling again).
TEST(CornerAccuracyTest, AFaintEdgeIsWeightedByItsOwnScatter) {
  ExpectScatterWithinBound(2611, 9, /*raw=*/true, 2.2);
}

// Views where a lamp's glare clips both walls white around the corner. No edge point is
// measured beside a clipped side (edge_profile.cc: clipping moves the steepest rise off the
// edge), so each edge of the Y shows only beyond the glare, up to 300 px from the corner. The
// detector accepts a Y edge that starts that far off only where the image between is
// clipped, and its trace crosses clipped stretches without counting them as misses. Before,
// these views had no pose ("the surfaces around the corner are saturated").
TEST(CornerAccuracyTest, ACornerInGlareIsLocatedFromItsEdgesBeyondTheGlare) {
  const CameraIntrinsics k = testing::PaperCamera();
  for (const auto& [seed, index] :
       {std::pair<uint64_t, int>{2611, 22}, {557123, 49}, {557123, 68}}) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " view " + std::to_string(index));
    const RealisticView view = RenderRealisticView(k, seed, index);
    // The glare is there: a quarter or more of the pixels within 40 px of the true corner
    // (projected with the reference camera) are clipped white.
    const Eigen::Matrix3d r = reference::RotationCameraFromCorner(view.truth);
    const Eigen::Vector3d position(view.truth.x_m, view.truth.y_m, view.truth.z_m);
    const cv::Point2d corner =
        reference::ProjectPoints(k, r, -r * position, {Eigen::Vector3d::Zero()})[0];
    const cv::Rect box =
        cv::Rect(static_cast<int>(corner.x) - 40, static_cast<int>(corner.y) - 40, 81, 81) &
        cv::Rect(0, 0, view.image.cols, view.image.rows);
    ASSERT_GT(box.area(), 0);
    EXPECT_GE(4 * cv::countNonZero(view.image(box) >= 250), box.area());
    const auto got = LocateCorner(view.image, k, view.truth.z_m);
    ASSERT_TRUE(got.ok()) << got.error();
    EXPECT_LT(RelativeHorizontalError(*got, view.truth), 0.01) << *got;
    EXPECT_LT(AngleErrorDeg(got->pose.tilt_rad, view.truth.tilt_rad), 0.2) << *got;
  }
  // Where the wall-wall edge is clipped on one side all along (view 71 of seed 606060), no
  // pose; the reason names the glare and what to do, not a weak edge.
  const RealisticView clipped = RenderRealisticView(k, 606060, 71);
  const auto none = LocateCorner(clipped.image, k, clipped.truth.z_m);
  ASSERT_FALSE(none.ok()) << *none;
  EXPECT_NE(none.error().message.find("saturated"), std::string::npos) << none.error();
  EXPECT_NE(none.error().message.find("lower the exposure"), std::string::npos) << none.error();
  // Where the glare lies along the wall-wall edge rather than around the corner (view 41 of
  // seed 2611: the edge shows for 150 px, then only beside a clipped wall), the same: the
  // edge is not too faint, its surroundings are clipped.
  const RealisticView along = RenderRealisticView(k, 2611, 41);
  const auto no_pose = LocateCorner(along.image, k, along.truth.z_m);
  ASSERT_FALSE(no_pose.ok()) << *no_pose;
  EXPECT_NE(no_pose.error().message.find("saturated"), std::string::npos) << no_pose.error();
}

// View 7 of realistic seed 735911: at a quarter of the resolution the Y was found 9 px beside the
// corner, its "Y" edge a faint line in the textured strip along the walls (step 3.4 grey levels
// near the corner, the X edge's 12), and the pose was 17 % off, not flagged. The three steps do not
// add up, which a corner's must (CornerQualityOptions::max_step_excess): the pose is suspect, and
// the next Y decides (the quarter resolution's next Y is the corner's own). Its faint edge is also
// fainter than the noise an edge measurement sees (a median step of 2.3 grey levels at noise 2.5;
// CornerQualityOptions::min_contrast_to_noise), which flags it on its own as well.
TEST(CornerAccuracyTest, AYWhoseStepsDoNotAddUpIsSuspect) {
  const CameraIntrinsics k = testing::PaperCamera();
  const RealisticView view = RenderRealisticView(k, 735911, 7);
  const cv::Mat& image = view.image;
  const CornerPose& truth = view.truth;
  // The wrong Y arose with the trace every 2 px (since every 4 px, this view's quarter
  // resolution Y is the corner, 2.4 % off and flagged as imprecise): the checks are tested
  // where it arises.
  CornerDetectorOptions detector;
  detector.trace_spacing_px = 2;
  // Without any of the three checks, the quarter's wrong Y stands: far off and not flagged.
  CornerQualityOptions unchecked;
  unchecked.max_step_excess = 1e9;
  unchecked.min_contrast_to_noise = 0;
  unchecked.max_other_ray_ratio = 1e9;
  // (The shading beside the edges, read since, flags this Y too, through its 1 sigma: left out
  // here, where the three checks are tested alone.)
  unchecked.shading_check_above_relative_sigma = std::numeric_limits<double>::infinity();
  const auto wrong = LocateCorner(image, k, truth.z_m, detector, unchecked);
  ASSERT_TRUE(wrong.ok()) << wrong.error();
  EXPECT_GT(RelativeHorizontalError(*wrong, truth), 0.05);
  EXPECT_FALSE(wrong->suspect) << wrong->suspect_reason;
  // With any one of them, or all (the default): the corner's own Y, within 5 % (or at least
  // flagged). The edge that leaves the corner beside the Y (corner_rays.h) came later and
  // catches this Y too.
  const Eigen::Vector3d corner_camera = CornerToCamera(truth, Eigen::Vector3d::Zero());
  const Eigen::Vector2d corner_px =
      NormalizedToPixel(k, corner_camera.head<2>() / corner_camera.z());
  EXPECT_GT((wrong->corner_px - corner_px).norm(), 5) << "the wrong Y lies beside the corner";
  CornerQualityOptions steps_only = unchecked, contrast_only = unchecked, rays_only = unchecked;
  steps_only.max_step_excess = CornerQualityOptions{}.max_step_excess;
  contrast_only.min_contrast_to_noise = CornerQualityOptions{}.min_contrast_to_noise;
  rays_only.max_other_ray_ratio = CornerQualityOptions{}.max_other_ray_ratio;
  for (const auto& [name, quality] : {std::pair{"steps", steps_only},
                                      {"contrast", contrast_only},
                                      {"rays", rays_only},
                                      {"all", {}}}) {
    const auto got = LocateCorner(image, k, truth.z_m, detector, quality);
    ASSERT_TRUE(got.ok()) << got.error();
    std::cout << "  without the checks " << 100 * RelativeHorizontalError(*wrong, truth)
              << " % off; checking " << name << " " << 100 * RelativeHorizontalError(*got, truth)
              << " % off" << (got->suspect ? ", suspect: " : "") << got->suspect_reason << "\n";
    EXPECT_TRUE(RelativeHorizontalError(*got, truth) < 0.05 || got->suspect) << name;
    EXPECT_LT((got->corner_px - corner_px).norm(), 3) << name;
  }
}

// View 16 of realistic seed 557123: the camera looks almost level
// (tilt 84 degrees) at a corner 7.6 m away, and the best supported Y is the floor corner
// 1.2 m below it. A floor corner fits a ceiling-corner pose exactly, one rolled far over:
// 68 % off, with a 1 sigma of 0.2 %. No upright robot camera is rolled that far
// (CornerQualityOptions::max_swing_rad), so that pose is flagged, and the locator goes on to
// the next Y the detector found. The ceiling's own Y, above it, gives a pose nothing
// doubts, and that is the answer. (Until 2026-11-28 the flagged floor corner was the answer:
// 25 of 8571 fresh realistic views were 50-92 % off that way; four of them below.)
TEST(CornerAccuracyTest, AFloorCornerTakenFirstGivesWayToTheCeilings) {
  const CameraIntrinsics k = testing::PaperCamera();
  const RealisticView view = RenderRealisticView(k, 557123, 16);
  const cv::Mat& image = view.image;
  const CornerPose& truth = view.truth;
  const CornerScene& scene = view.scene;
  const double relative_error_limit = 0.05;
  // The floor corner, room_height_m below the ceiling's along the vertical edge.
  const Eigen::Vector3d floor_corner =
      CornerToCamera(truth, Eigen::Vector3d(0, 0, scene.room_height_m));
  ASSERT_GT(floor_corner.z(), 0);
  const Eigen::Vector2d floor_px = NormalizedToPixel(k, floor_corner.head<2>() / floor_corner.z());
  CornerQualityOptions unchecked;
  unchecked.max_swing_rad = 1e9;
  const auto wrong = LocateCorner(image, k, truth.z_m, {}, unchecked);
  ASSERT_TRUE(wrong.ok()) << wrong.error();
  EXPECT_GT(RelativeHorizontalError(*wrong, truth), relative_error_limit);
  EXPECT_FALSE(wrong->suspect);
  EXPECT_LT((wrong->corner_px - floor_px).norm(), 10)
      << "the floor corner is at " << floor_px.transpose();
  // The same Y, located alone, is flagged for its roll.
  const auto floor_y = LocateCornerFromEdges(image, k, truth.z_m, wrong->edges, {}, {});
  ASSERT_TRUE(floor_y.ok()) << floor_y.error();
  EXPECT_TRUE(floor_y->suspect);
  EXPECT_NE(floor_y->suspect_reason.find("rolled"), std::string::npos) << floor_y->suspect_reason;
  for (const auto& [seed, index] : {std::pair<uint64_t, int>{557123, 16},
                                    {2500007, 5},
                                    {1300005, 21},
                                    {1800009, 68},
                                    {2600002, 43}}) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " view " + std::to_string(index));
    const RealisticView v = RenderRealisticView(k, seed, index);
    const auto got = LocateCorner(v.image, k, v.truth.z_m);
    ASSERT_TRUE(got.ok()) << got.error();
    std::cout << "  view " << index << " of seed " << seed << ": "
              << 100 * RelativeHorizontalError(*got, v.truth) << " % off"
              << (got->suspect ? ", suspect: " : "") << got->suspect_reason << "\n";
    EXPECT_LT(RelativeHorizontalError(*got, v.truth), 0.01);
    EXPECT_FALSE(got->suspect) << got->suspect_reason;
  }
}

// View 0 of realistic seed 440002: the
// corner lies 140 px from the left border under a lamp's glare, its short ceiling edge runs
// 160 px to the border with a step of 30 grey levels. The quarter-resolution search lost
// that edge and took a faint line into the glare instead (2.3 grey levels at noise 1.6,
// 1.45 times, above the contrast check): a pose 62.6 % off, its edges agreeing with it, and
// flagged by nothing. Rings around the corner show the lost edge as a ray stronger than the
// faint one (corner_rays.h), so the pose is flagged, and the half-resolution search it
// then runs finds the corner's own three edges. (Since the noise estimates leave saturated
// pixels out, 2026-11-27, the glare no longer hides this frame's noise: it reads 2.5, not 1.6,
// and the faint line, 0.9x the noise, is flagged by the contrast check too. That check is
// switched off below with the ray check, so the ray check alone is what is shown here.)
TEST(CornerAccuracyTest, AStrongerEdgeLeavingTheCornerMeansAWrongThirdEdge) {
  const CameraIntrinsics k = testing::PaperCamera();
  const RealisticView view = RenderRealisticView(k, 440002, 0);
  CornerQualityOptions unchecked;
  unchecked.max_other_ray_ratio = 1e9;
  unchecked.min_contrast_to_noise = 0;
  const auto wrong = LocateCorner(view.image, k, view.truth.z_m, {}, unchecked);
  ASSERT_TRUE(wrong.ok()) << wrong.error();
  EXPECT_GT(RelativeHorizontalError(*wrong, view.truth), 0.05);
  EXPECT_FALSE(wrong->suspect) << wrong->suspect_reason;
  EXPECT_EQ(wrong->edges.detection_scale, 0.25);
  // The quarter resolution's Y, checked: flagged for the edge it lost.
  const auto quarter_edges = DetectCornerEdges(view.image, {}, &k);
  ASSERT_TRUE(quarter_edges.ok()) << quarter_edges.error();
  CornerQualityOptions rays_only;
  rays_only.min_contrast_to_noise = 0;
  const auto flagged =
      LocateCornerFromEdges(view.image, k, view.truth.z_m, *quarter_edges, {}, rays_only);
  ASSERT_TRUE(flagged.ok()) << flagged.error();
  EXPECT_GT(RelativeHorizontalError(*flagged, view.truth), 0.05);
  EXPECT_TRUE(flagged->suspect);
  EXPECT_FALSE(flagged->suspect_only_imprecise);
  EXPECT_NE(flagged->suspect_reason.find("leaves the corner"), std::string::npos)
      << flagged->suspect_reason;
  std::cout << "  the quarter resolution's Y: " << flagged->suspect_reason << "\n";
  // The whole search: the corner's own edges, a good pose.
  const auto got = LocateCorner(view.image, k, view.truth.z_m);
  ASSERT_TRUE(got.ok()) << got.error();
  std::cout << "  then " << 100 * RelativeHorizontalError(*got, view.truth) << " % off"
            << (got->suspect ? ", suspect: " : "") << got->suspect_reason << "\n";
  EXPECT_LT(RelativeHorizontalError(*got, view.truth), 0.01);
  EXPECT_FALSE(got->suspect) << got->suspect_reason;
  EXPECT_EQ(got->edges.detection_scale, 0.5);
}

// A weakly determined view of a realistic seed: under an older imprecision flag
// (`old_max_relative_sigma`, and before the shading beside the edges was read) its pose went
// unflagged though more than `min_error_then` off; under today's it is flagged for its 1 sigma.
void ExpectFlaggedSinceTheOldLimit(uint64_t seed, int index, double old_max_relative_sigma,
                                   double min_error_then) {
  const CameraIntrinsics k = testing::PaperCamera();
  const RealisticView view = RenderRealisticView(k, seed, index);
  CornerQualityOptions old_limit;
  old_limit.max_relative_sigma = old_max_relative_sigma;
  old_limit.shading_check_above_relative_sigma = std::numeric_limits<double>::infinity();
  const auto unflagged = LocateCorner(view.image, k, view.truth.z_m, {}, old_limit);
  ASSERT_TRUE(unflagged.ok()) << unflagged.error();
  EXPECT_GT(RelativeHorizontalError(*unflagged, view.truth), min_error_then);
  EXPECT_FALSE(unflagged->suspect) << unflagged->suspect_reason;
  const auto got = LocateCorner(view.image, k, view.truth.z_m);
  ASSERT_TRUE(got.ok()) << got.error();
  const double sigma_h = std::sqrt(got->covariance(0, 0) + got->covariance(1, 1));
  const double distance = std::hypot(got->pose.x_m, got->pose.y_m);
  std::cout << "  " << 100 * RelativeHorizontalError(*got, view.truth) << " % off, 1 sigma "
            << 100 * sigma_h / distance << " %: " << got->suspect_reason << "\n";
  EXPECT_GT(sigma_h, CornerQualityOptions{}.max_relative_sigma * distance);
  EXPECT_TRUE(got->suspect);
  EXPECT_NE(got->suspect_reason.find("position uncertain"), std::string::npos)
      << got->suspect_reason;
  EXPECT_NE(got->suspect_reason.find("(more than 1.25)"), std::string::npos) << got->suspect_reason;
}

// View 20 of realistic seed 271828: a camera 5.9 m from one wall and
// 0.3 m from the other, tilt 65 degrees. The corner determines its distance weakly, and it
// says so: a 1 sigma of 1.6-1.8 % of the distance. The pose was 5.3-5.6 % off, 3.1-3.4 sigma,
// which an honest 1 sigma allows now and then (4.5 % since edge points are weighted by their
// contrast, 3.8 % since each edge is weighted by its own scatter). A pose whose 1 sigma is
// above 1.5 % of the distance (5 % within 3.3 sigma) was then flagged, and since above 1.25 %
// (CornerQualityOptions::max_relative_sigma, the next test); at the old limit, 2 %, it was not.
TEST(CornerAccuracyTest, AWeaklyDeterminedFarPoseIsSuspect) {
  ExpectFlaggedSinceTheOldLimit(271828, 20, 0.02, 0.035);
}

// View 49 of realistic seed 1900006: a camera 0.51 m under the ceiling and
// 4.75 m from the corner, tilt 74 degrees. Its 1 sigma, 1.31 % of the distance, was under the
// flag's 1.5 %, and the pose 5.1 % off: 3.9 sigma, more than an honest Gaussian allows in the
// few thousand views the fresh sets hold. Flagged from 1.25 % (5 % within 4 sigma).
TEST(CornerAccuracyTest, AFarPoseWhose4SigmaReaches5PercentIsSuspect) {
  ExpectFlaggedSinceTheOldLimit(1900006, 49, 0.015, 0.05);
}

// View 34 of realistic seed 2100011: its vertical edge Z runs 460 px but
// steps only 4.5 grey levels at noise 2.5, and one of its walls brightens away from it (0.1-0.17
// grey levels a pixel) while the other stays flat. That moves every one of its points the
// same way, 0.1-0.5 px, which their scatter and the lines' agreement cannot show: the pose was
// 5.25 % off at a 1 sigma of 0.88 % (6 sigma; over 8 noise draws 2.5 % off on average), more
// than 5 % off and not flagged. Now the shading is read beside the edges: the shift it
// predicts (about 1.3 % of the distance) is removed from the pose and counted in its 1 sigma,
// so the pose is nearer the truth, flagged, and the reason says why.
TEST(CornerAccuracyTest, AFaintEdgesShadingIsRemovedAndCounted) {
  const CameraIntrinsics k = testing::PaperCamera();
  const RealisticView view = RenderRealisticView(k, 2100011, 34);
  CornerQualityOptions unread;
  unread.shading_check_above_relative_sigma = std::numeric_limits<double>::infinity();
  const auto then = LocateCorner(view.image, k, view.truth.z_m, {}, unread);
  ASSERT_TRUE(then.ok()) << then.error();
  EXPECT_GT(RelativeHorizontalError(*then, view.truth), 0.05);
  EXPECT_FALSE(then->suspect) << then->suspect_reason;
  EXPECT_EQ(then->shading_shift.norm(), 0);
  const auto got = LocateCorner(view.image, k, view.truth.z_m);
  ASSERT_TRUE(got.ok()) << got.error();
  const double distance = std::hypot(got->pose.x_m, got->pose.y_m);
  const double sigma_h = std::sqrt(got->covariance(0, 0) + got->covariance(1, 1));
  std::cout << "  " << 100 * RelativeHorizontalError(*then, view.truth) << " % off, then "
            << 100 * RelativeHorizontalError(*got, view.truth) << " % (1 sigma "
            << 100 * sigma_h / distance << " %): " << got->suspect_reason << "\n";
  EXPECT_GT(got->shading_shift.head<2>().norm(), 0.005 * distance);
  EXPECT_LT(RelativeHorizontalError(*got, view.truth),
            0.85 * RelativeHorizontalError(*then, view.truth));
  // The shift is what moved it: with the edges measured once (as before, not again with the
  // wider filter), the same pose before it.
  CornerQualityOptions once;
  once.remeasure_above_relative_sigma = std::numeric_limits<double>::infinity();
  const auto shifted = LocateCorner(view.image, k, view.truth.z_m, {}, once);
  ASSERT_TRUE(shifted.ok()) << shifted.error();
  EXPECT_FALSE(shifted->edges_measured_again);
  EXPECT_GT(shifted->shading_shift.head<2>().norm(), 0.005 * distance);
  EXPECT_NEAR(shifted->pose.x_m - shifted->shading_shift[0], then->pose.x_m, 1e-6);
  EXPECT_NEAR(shifted->pose.y_m - shifted->shading_shift[1], then->pose.y_m, 1e-6);
  EXPECT_TRUE(got->edges_measured_again) << "its 1 sigma is over 0.6 % of the distance";
  EXPECT_TRUE(got->suspect_only_imprecise) << got->suspect_reason;
  EXPECT_NEAR(got->noise_sigma_grey, then->noise_sigma_grey, 1e-12) << "the same image's noise";
  EXPECT_GT(got->noise_sigma_grey, 1.0);
  EXPECT_GT(sigma_h, CornerQualityOptions{}.max_relative_sigma * distance);
  EXPECT_NE(got->suspect_reason.find("the shading beside the edges moved it"), std::string::npos)
      << got->suspect_reason;
}

// The first 100 weakly determined realistic views of seeds 1200001-1300002 (picked by the 1
// sigma main's code reported before this change, 0.6-1.2 % of the distance, and by nothing
// else), each located twice: measured once, and, where the first fit's 1 sigma is over 0.6 %,
// measured again along the fitted lines with a derivative filter 1.9x the edges' blur and the
// shading beside them read. The wider filter locates a faint edge more precisely; the shading's
// correction removes most of its larger bias (corner_pose_notes.md, "Weak views measured again,
// with a wider filter"). These seeds are among those the filter's width was chosen on.
TEST(CornerAccuracyTest, WeakViewsMeasuredAgainWithAWiderFilterAreNearerTheTruth) {
  const std::vector<std::pair<uint64_t, std::vector<int>>> views = {
      {1200001, {13, 21, 27, 59, 60, 69}},
      {1200002, {33, 63}},
      {1200003, {9, 12, 21, 25, 27, 42, 59, 60, 66, 69}},
      {1200004, {0, 4, 9, 15, 19, 27, 29, 42, 60, 63, 69}},
      {1200005, {15}},
      {1200006, {3, 6, 9, 18, 32, 51, 60, 65, 69}},
      {1200007, {15, 18, 54, 68}},
      {1200008, {33, 41, 45, 68}},
      {1200009, {11, 17, 24, 36, 42, 62, 66, 69}},
      {1200010, {1, 6, 48}},
      {1200011, {0, 21, 33, 39, 60, 63, 66}},
      {1200012, {7, 9, 16, 25, 33, 36, 42}},
      {1200013, {23, 29, 57}},
      {1200014, {26, 45, 60, 61, 66, 71}},
      {1200015, {14, 34, 42}},
      {1200016, {16, 26, 33, 39, 40, 42, 66}},
      {1300001, {0, 5, 36, 45, 63}},
      {1300002, {1, 27, 36, 45}}};
  const CameraIntrinsics k = testing::PaperCamera();
  CornerQualityOptions once;
  once.remeasure_above_relative_sigma = std::numeric_limits<double>::infinity();
  double sum2_once = 0, sum2_again = 0;
  int located = 0, measured_again = 0, over_1_once = 0, over_1_again = 0;
  for (const auto& [seed, indices] : views) {
    for (int index : indices) {
      const RealisticView view = RenderRealisticView(k, seed, index);
      const auto a = LocateCorner(view.image, k, view.truth.z_m, {}, once);
      const auto b = LocateCorner(view.image, k, view.truth.z_m);
      if (!a.ok() || !b.ok()) continue;
      EXPECT_FALSE(a->edges_measured_again);
      const double e_once = RelativeHorizontalError(*a, view.truth);
      const double e_again = RelativeHorizontalError(*b, view.truth);
      sum2_once += e_once * e_once;
      sum2_again += e_again * e_again;
      over_1_once += e_once > 0.01;
      over_1_again += e_again > 0.01;
      measured_again += b->edges_measured_again;
      ++located;
    }
  }
  const double rms_once = std::sqrt(sum2_once / located),
               rms_again = std::sqrt(sum2_again / located);
  std::cout << "  " << located << " views, " << measured_again << " measured again: RMS error "
            << 100 * rms_once << " % measured once, " << 100 * rms_again
            << " % again; more than 1 % off " << over_1_once << " -> " << over_1_again << "\n";
  ASSERT_GE(located, 95);
  EXPECT_GT(measured_again, located / 2);
  EXPECT_LT(rms_again, 0.97 * rms_once);
  EXPECT_LE(over_1_again, over_1_once);
}

// A corner near the image's border: the vertical edge runs 90 px to it, the ceiling's
// 1160 and 510 px. The pose is flagged for its 1 sigma, and the reason names that edge as
// where most of the position's variance comes from, with its length and contrast. (Over
// 785 realistic views of 11 seeds, the third drawn with one edge a fifth of the image or
// shorter hold 28 of the 40 poses more than 1 % off.)
TEST(CornerAccuracyTest, AnImprecisePoseNamesTheEdgeThatLimitsIt) {
  const CameraIntrinsics k = testing::PaperCamera();
  const RealisticView view = RenderRealisticView(k, 7, 33);
  const auto got = LocateCorner(view.image, k, view.truth.z_m);
  ASSERT_TRUE(got.ok()) << got.error();
  std::cout << "  " << got->suspect_reason << "\n";
  EXPECT_TRUE(got->suspect_only_imprecise) << got->suspect_reason;
  double shares = 0;
  for (const auto& s : got->support) shares += s.position_variance_share;
  EXPECT_NEAR(shares, 1.0, 1e-9);
  // The shortest edge in the image gives most of the variance.
  int shortest = 0;
  for (int axis = 1; axis < 3; ++axis)
    if (got->support[axis].visible_length_px < got->support[shortest].visible_length_px)
      shortest = axis;
  EXPECT_LT(got->support[shortest].visible_length_px, 0.1 * k.width_px);
  EXPECT_GT(got->support[shortest].position_variance_share, 0.5);
  const std::string named = std::string("of its variance from edge ") + "XYZ"[shortest] + ": ";
  EXPECT_NE(got->suspect_reason.find(named), std::string::npos) << got->suspect_reason;
  EXPECT_NE(got->suspect_reason.find(" px long, contrast "), std::string::npos)
      << got->suspect_reason;
}

// The same view: its quarter-resolution pose is flagged only because the view fixes the
// position weakly; its edges agree with it. A search at half resolution finds the same Y, and
// its edges are measured at full resolution either way, so it is not run: the quarter's pose
// is kept. That the half search would agree within the pose's own 1 sigma is checked too.
TEST(CornerAccuracyTest, APoseFlaggedOnlyAsImpreciseIsNotSearchedAgain) {
  const CameraIntrinsics k = testing::PaperCamera();
  const RealisticView view = RenderRealisticView(k, 271828, 20);
  const auto got = LocateCorner(view.image, k, view.truth.z_m);
  ASSERT_TRUE(got.ok()) << got.error();
  EXPECT_TRUE(got->suspect);
  EXPECT_TRUE(got->suspect_only_imprecise) << got->suspect_reason;
  EXPECT_EQ(got->suspect_reason.find(';'), std::string::npos) << got->suspect_reason;
  EXPECT_EQ(got->edges.detection_scale, 0.25);
  CornerDetectorOptions half_only;
  half_only.quarter_resolution_first = false;
  const auto half = LocateCorner(view.image, k, view.truth.z_m, half_only);
  ASSERT_TRUE(half.ok()) << half.error();
  const double apart_m = std::hypot(got->pose.x_m - half->pose.x_m, got->pose.y_m - half->pose.y_m);
  const double sigma_h = std::sqrt(got->covariance(0, 0) + got->covariance(1, 1));
  std::cout << "  quarter and half searches " << 1000 * apart_m << " mm apart, 1 sigma "
            << 1000 * sigma_h << " mm\n";
  EXPECT_LT(apart_m, sigma_h);
}

// View 3 of the cluttered set (seed 2024): the quarter-resolution search finds the corner,
// the half-resolution search alone finds no Y that makes a pose. When the quarter's pose is
// flagged for its edges (here every pose is, by asking each edge to be found beyond its
// whole visible length), the half-resolution search is asked again; finding nothing, it must
// not lose the view: the quarter's pose stands, still flagged.
TEST(CornerAccuracyTest, AFlaggedCoarsePoseStandsWhenTheFinerSearchFindsNone) {
  const CameraIntrinsics k = testing::PaperCamera();
  std::mt19937_64 rng(2024);
  std::optional<CornerPose> truth;
  for (int i = 0; i <= 3; ++i) truth = testing::RandomCornerPose(rng, k, /*margin_px=*/60);
  ASSERT_TRUE(truth);
  const cv::Mat image =
      RenderCornerScene(k, *truth, SceneOfView(k, 2024, 3, Look::kCluttered, *truth));
  CornerDetectorOptions half_only;
  half_only.quarter_resolution_first = false;
  ASSERT_FALSE(LocateCorner(image, k, truth->z_m, half_only).ok())
      << "the half-resolution search alone finds a pose here";
  CornerQualityOptions strict;
  strict.min_coverage = 1.01;
  const auto got = LocateCorner(image, k, truth->z_m, {}, strict);
  ASSERT_TRUE(got.ok()) << got.error();
  EXPECT_EQ(got->edges.detection_scale, 0.25);
  EXPECT_TRUE(got->suspect);
  EXPECT_FALSE(got->suspect_only_imprecise) << got->suspect_reason;
  EXPECT_LT(RelativeHorizontalError(*got, *truth), 0.01);
}

// The p95 of `rel` with a bootstrap 95 % interval (2000 resamples of the views, which are
// independent draws of pose, room and noise): {low, p95, high}.
std::array<double, 3> P95WithInterval(const std::vector<double>& rel) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (rel.empty()) return {nan, nan, nan};
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<size_t> pick(0, rel.size() - 1);
  std::vector<double> p95s, resample(rel.size());
  for (int draw = 0; draw < 2000; ++draw) {
    for (double& r : resample) r = rel[pick(rng)];
    p95s.push_back(Stats::Percentile(resample, 0.95));
  }
  return {Stats::Percentile(p95s, 0.025), Stats::Percentile(rel, 0.95),
          Stats::Percentile(p95s, 0.975)};
}

// Seeds as MONOCLE_CORNER_SEEDS gives them: "FIRST-LAST", "SEED", or several of either joined
// by commas. Empty when the text is not that (or names over 1000 seeds).
std::vector<uint64_t> ParseSeeds(const std::string& text) {
  std::vector<uint64_t> seeds;
  std::stringstream parts(text);
  std::string part;
  while (std::getline(parts, part, ',')) {
    char* rest = nullptr;
    const unsigned long long first = std::strtoull(part.c_str(), &rest, 10);
    unsigned long long last = first;
    if (*rest == '-') last = std::strtoull(rest + 1, &rest, 10);
    if (*rest != '\0' || first == 0 || last < first || seeds.size() + (last - first) >= 1000)
      return {};
    for (unsigned long long seed = first; seed <= last; ++seed) seeds.push_back(seed);
  }
  return seeds;
}

// Fresh seeds, on demand: MONOCLE_CORNER_SEEDS=FIRST-LAST[,FIRST-LAST...] renders 72 realistic
// views per seed (MONOCLE_CORNER_RAW=1: without JPEG) and prints each set and the pooled set as
// the tests above do, with each view's Cramér–Rao bound, how often an efficient estimator
// would meet p95 <= 1 %, and the pooled p95's bootstrap interval. Skipped without the
// variable. To judge a change to the locator view by view (corner_view_record.h):
// MONOCLE_CORNER_VIEWS_OUT=FILE writes each view's error, bound and 1 sigma, and
// MONOCLE_CORNER_VIEWS_BEFORE=FILE, a file written so before the change on the same seeds,
// prints how each view's error moved; MONOCLE_CORNER_ONLY=FILE renders only the views it lists
// (ViewWanted). This is how the fresh-seed figures in README.md and
// tests/accuracy/corner_pose_notes.md are measured (run a seed once, and never tune on it);
// it asserts only that every set is large enough to judge.
TEST(CornerAccuracyTest, FreshSeedsOnDemand) {
  const char* text = std::getenv("MONOCLE_CORNER_SEEDS");
  if (text == nullptr || *text == '\0')
    GTEST_SKIP() << "set MONOCLE_CORNER_SEEDS=FIRST-LAST to render and judge fresh seeds";
  const std::vector<uint64_t> seeds = ParseSeeds(text);
  ASSERT_FALSE(seeds.empty()) << "MONOCLE_CORNER_SEEDS: give FIRST-LAST[,FIRST-LAST...], e.g. "
                                 "1400001-1400016 (at most 1000 seeds), not \""
                              << text << "\"";
  const char* raw = std::getenv("MONOCLE_CORNER_RAW");
  const Look look =
      raw != nullptr && std::string(raw) == "1" ? Look::kRealisticRaw : Look::kRealistic;
  Stats pooled;
  int seeds_meeting_p95 = 0;
  for (uint64_t seed : seeds) {
    const Stats s = RenderAndLocate(72, seed, look, 1.0, /*with_bound=*/true);
    s.Print(("seed " + std::to_string(seed)).c_str());
    if (std::getenv("MONOCLE_CORNER_ONLY") == nullptr) {
      ASSERT_GE(s.images, 60) << "seed " << seed;
    }
    seeds_meeting_p95 += Stats::Percentile(s.horizontal_rel, 0.95) <= 0.01;
    pooled.Merge(s);
  }
  pooled.Print(("pooled over seeds " + std::string(text)).c_str());
  for (const auto& [sigma_deg, l] : pooled.levelled) {
    const std::string name = "  pooled, on a robot level to " +
                             std::to_string(sigma_deg).substr(0, 3) + " deg (1 sigma)";
    l.Print(name.c_str());
  }
  const auto [low, p95, high] = P95WithInterval(pooled.horizontal_rel);
  std::cout << "pooled p95 " << 100 * p95 << " % of the distance, 95 % interval " << 100 * low
            << "-" << 100 * high << " % (bootstrap over the views); p95 <= 1 % on "
            << seeds_meeting_p95 << " of " << seeds.size() << " seeds\n";
  if (const char* out_path = std::getenv("MONOCLE_CORNER_VIEWS_OUT")) {
    std::ofstream out(out_path);
    ASSERT_TRUE(out) << "MONOCLE_CORNER_VIEWS_OUT: cannot write " << out_path;
    out << "# corner_accuracy_test FreshSeedsOnDemand, seeds " << text
        << (look == Look::kRealisticRaw ? ", raw" : ", JPEG")
        << "\n# seed index error_pct bound_pct sigma_pct suspect short_edge\n";
    for (const auto& view : pooled.views) testing::WriteCornerViewRecord(out, view);
    std::cout << "each view written to " << out_path << "\n";
  }
  if (const char* before_path = std::getenv("MONOCLE_CORNER_VIEWS_BEFORE")) {
    std::string error;
    const auto before = testing::ReadCornerViewRecords(before_path, &error);
    ASSERT_EQ(error, "") << "MONOCLE_CORNER_VIEWS_BEFORE";
    std::cout << "against " << before_path << ": " << testing::ComparePaired(before, pooled.views);
  }
}

}  // namespace
}  // namespace monocle
