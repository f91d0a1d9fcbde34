#include "camera/render/reference_camera.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <mutex>
#include <opencv2/calib3d.hpp>

namespace monocle::reference {
namespace {

// Converged far past the renderers' needs (1e-4 px); OpenCV's default stops after 5 rounds.
// OpenCV measures the criterion's error in pixels, where doubles resolve ~1e-13 px: at 1e-14
// only an exact zero met it and the rest ran all 200 rounds, doubling a realistic view's
// render time. 1e-10 px is met in a few rounds at these lenses' distortion.
const cv::TermCriteria kUndistortCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200,
                                          1e-10);

}  // namespace

cv::Matx33d CameraMatrix(const CameraIntrinsics& k) {
  return {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
}

cv::Mat DistortionCoefficients(const CameraIntrinsics& k) {
  cv::Mat d(1, 8, CV_64F);
  for (int i = 0; i < 8; ++i) d.at<double>(0, i) = k.distortion[i];
  return d;
}

std::vector<cv::Point2d> UndistortPixels(const CameraIntrinsics& k,
                                         const std::vector<cv::Point2d>& pixels) {
  std::vector<cv::Point2d> out;
  if (pixels.empty()) return out;
  cv::undistortPoints(pixels, out, CameraMatrix(k), DistortionCoefficients(k), cv::noArray(),
                      cv::noArray(), kUndistortCriteria);
  return out;
}

namespace {

using GridKey = std::array<double, 14>;  // size, fx fy cx cy, eight distortion terms
struct GridEntry {
  GridKey key;
  cv::Mat grid;
};
std::mutex grid_mutex;
std::deque<GridEntry> grid_cache;
int grid_scopes = 0;

}  // namespace

PixelGridCacheScope::PixelGridCacheScope() {
  std::lock_guard<std::mutex> lock(grid_mutex);
  ++grid_scopes;
}

PixelGridCacheScope::~PixelGridCacheScope() {
  std::lock_guard<std::mutex> lock(grid_mutex);
  if (--grid_scopes == 0) grid_cache.clear();
}

cv::Mat UndistortedPixelGrid(const CameraIntrinsics& k) {
  // cv::undistortPoints over a million pixels takes ~2 s; a test set renders hundreds of
  // views through one camera, so the last few grids are kept (read-only, shared).
  using Key = GridKey;
  auto& mutex = grid_mutex;
  auto& cache = grid_cache;
  Key key{
      static_cast<double>(k.width_px), static_cast<double>(k.height_px), k.fx, k.fy, k.cx, k.cy};
  std::copy(k.distortion.begin(), k.distortion.end(), key.begin() + 6);
  {
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& e : cache)
      if (e.key == key) return e.grid;
  }
  std::vector<cv::Point2d> pixels;
  pixels.reserve(static_cast<size_t>(k.width_px) * k.height_px);
  for (int v = 0; v < k.height_px; ++v)
    for (int u = 0; u < k.width_px; ++u) pixels.emplace_back(u, v);
  const auto normalized = UndistortPixels(k, pixels);
  cv::Mat grid = cv::Mat(normalized, true).reshape(2, k.height_px);
  std::lock_guard<std::mutex> lock(mutex);
  cache.push_back({key, grid});
  if (cache.size() > 4) cache.pop_front();
  return grid;
}

Eigen::Matrix3d RotationCameraFromCorner(const CornerPose& pose) {
  // Eq. (1) as printed: row vectors times R_z(psi) R_x(Theta) F_z.
  const double cp = std::cos(pose.pan_rad), sp = std::sin(pose.pan_rad);
  const double ct = std::cos(pose.tilt_rad), st = std::sin(pose.tilt_rad);
  Eigen::Matrix4d rz, rx, fz;
  rz << cp, -sp, 0, 0, sp, cp, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  rx << 1, 0, 0, 0, 0, ct, -st, 0, 0, st, ct, 0, 0, 0, 0, 1;
  fz = Eigen::Vector4d(1, 1, -1, 1).asDiagonal();
  const Eigen::Matrix4d tr = rz * rx * fz;
  // (u, v, w) = (x, y, z) * tr: as columns, uvw = tr^T * xyz.
  const Eigen::Matrix3d uvw_from_corner = tr.topLeftCorner<3, 3>().transpose();
  // Section 2.2: (u_p, v_p) = (u_i, v_i) S, S = [cos -sin; sin cos], so as columns
  // (u_i, v_i) = S (u_p, v_p) (S is orthogonal).
  const double cd = std::cos(pose.swing_rad), sd = std::sin(pose.swing_rad);
  Eigen::Matrix3d image_from_unswung = Eigen::Matrix3d::Identity();
  image_from_unswung.topLeftCorner<2, 2>() << cd, -sd, sd, cd;
  // OpenCV's x runs to the image's right, the paper's u to its left (corner_pose.h).
  const Eigen::Matrix3d opencv_from_paper = Eigen::Vector3d(-1, 1, 1).asDiagonal();
  return opencv_from_paper * image_from_unswung * uvw_from_corner;
}

Eigen::Matrix3d RotationCameraFromRobot(const FloorPose& pose) {
  // The camera's axes in the robot frame. Optical axis: pitch from straight up (+Z_w) towards
  // ahead (+Y_w), so 90 degrees looks level and more looks down. Before roll the image's x
  // axis is the robot's X_w (right); roll turns x and y about the optical axis.
  const double s = std::sin(pose.pitch_rad), c = std::cos(pose.pitch_rad);
  const Eigen::Vector3d z_c(0, s, c);
  const Eigen::Vector3d x0 = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d y0 = z_c.cross(x0);
  const double sr = std::sin(pose.roll_rad), cr = std::cos(pose.roll_rad);
  Eigen::Matrix3d r;
  r.row(0) = (cr * x0 - sr * y0).transpose();
  r.row(1) = (sr * x0 + cr * y0).transpose();
  r.row(2) = z_c.transpose();
  return r;
}

std::vector<cv::Point2d> ProjectPoints(const CameraIntrinsics& k, const Eigen::Matrix3d& r,
                                       const Eigen::Vector3d& t,
                                       const std::vector<Eigen::Vector3d>& points) {
  cv::Matx33d rm;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rm(i, j) = r(i, j);
  cv::Vec3d rvec;
  cv::Rodrigues(rm, rvec);
  std::vector<cv::Point3d> object;
  for (const auto& p : points) object.emplace_back(p.x(), p.y(), p.z());
  std::vector<cv::Point2d> out;
  if (object.empty()) return out;
  cv::projectPoints(object, rvec, cv::Vec3d(t.x(), t.y(), t.z()), CameraMatrix(k),
                    DistortionCoefficients(k), out);
  return out;
}

}  // namespace monocle::reference
