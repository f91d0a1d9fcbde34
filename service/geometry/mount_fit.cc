#include "service/geometry/mount_fit.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "service/geometry/mount_level.h"

namespace monocle {
namespace {

// Poses whose tip, against the fit, is beyond chi-square with 2 degrees of freedom at 0.999
// (3.7 sigma) are left out, one at a time, worst first: mount_level's gate.
constexpr double kMaxTipMahalanobis2 = 13.8;
constexpr size_t kMinPoses = 5;

// The mount with its camera turned about the base's x and y axes.
RigidTransform Corrected(const RigidTransform& mount, const Eigen::Vector2d& correction_rad) {
  RigidTransform out = mount;
  out.rotation = (Eigen::AngleAxisd(correction_rad.x(), Eigen::Vector3d::UnitX()) *
                  Eigen::AngleAxisd(correction_rad.y(), Eigen::Vector3d::UnitY()) * mount.rotation)
                     .normalized();
  return out;
}

// One pose's tip under a mount, its derivative by the correction, and the tip's covariance
// from the pose's own.
struct TipTerms {
  Eigen::Vector2d tip;
  Eigen::Matrix2d by_correction;
  Eigen::Matrix2d pose_covariance;
};

TipTerms TermsOf(const MountFitPose& p, const RigidTransform& mount,
                 const Eigen::Vector2d& correction_rad) {
  constexpr double kStepRad = 1e-6;
  const RigidTransform at = Corrected(mount, correction_rad);
  TipTerms t;
  t.tip = BaseTipInCornerFrame(p.pose, at);
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2d step = Eigen::Vector2d::Unit(i) * kStepRad;
    t.by_correction.col(i) =
        (BaseTipInCornerFrame(p.pose, Corrected(mount, correction_rad + step)) -
         BaseTipInCornerFrame(p.pose, Corrected(mount, correction_rad - step))) /
        (2 * kStepRad);
  }
  const Eigen::Matrix<double, 2, 5> h = BaseTipJacobian(p.pose, at);
  t.pose_covariance = h * p.covariance * h.transpose();
  return t;
}

struct Solution {
  Eigen::Vector2d correction_rad = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  double floor_sigma_rad = 0;
  std::vector<double> mahalanobis2;  // per used pose, against the fit
};

// Sum over poses of r^T (C_i + floor^2 I)^-1 r at the correction's linearisation.
double Chi2(const std::vector<TipTerms>& terms, double floor_sigma_rad) {
  double chi2 = 0;
  for (const TipTerms& t : terms) {
    const Eigen::Matrix2d c =
        t.pose_covariance + floor_sigma_rad * floor_sigma_rad * Eigen::Matrix2d::Identity();
    chi2 += t.tip.dot(c.ldlt().solve(t.tip));
  }
  return chi2;
}

// Gauss-Newton on the correction, each round with the floor's 1 sigma that makes the
// residuals' chi-square equal its degrees of freedom (zero if the poses' own covariances
// already explain them): the floor is what the poses' scatter leaves over.
Solution Solve(const std::vector<MountFitPose>& poses, const std::vector<size_t>& used,
               const RigidTransform& mount) {
  Solution s;
  const double dof = 2.0 * static_cast<double>(used.size()) - 2;
  for (int round = 0; round < 6; ++round) {
    std::vector<TipTerms> terms;
    for (size_t i : used) terms.push_back(TermsOf(poses[i], mount, s.correction_rad));
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
    for (const TipTerms& t : terms) {
      const Eigen::Matrix2d weight =
          (t.pose_covariance + s.floor_sigma_rad * s.floor_sigma_rad * Eigen::Matrix2d::Identity())
              .inverse();
      normal += t.by_correction.transpose() * weight * t.by_correction;
      gradient += t.by_correction.transpose() * weight * t.tip;
    }
    const Eigen::Vector2d step = -normal.ldlt().solve(gradient);
    s.correction_rad += step;
    s.covariance = normal.inverse();
    // Residuals after the step, linearly.
    for (TipTerms& t : terms) t.tip += t.by_correction * step;
    double lo = 0, hi = 5 * std::numbers::pi / 180;
    if (Chi2(terms, 0) <= dof) {
      s.floor_sigma_rad = 0;
    } else {
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (Chi2(terms, mid) > dof ? lo : hi) = mid;
      }
      s.floor_sigma_rad = hi;
    }
    s.mahalanobis2.clear();
    for (const TipTerms& t : terms) {
      const Eigen::Matrix2d c =
          t.pose_covariance + s.floor_sigma_rad * s.floor_sigma_rad * Eigen::Matrix2d::Identity();
      s.mahalanobis2.push_back(t.tip.dot(c.ldlt().solve(t.tip)));
    }
    if (step.norm() < 1e-10) break;
  }
  return s;
}

}  // namespace

Result<MountLevelFit> FitMountLevel(const std::vector<MountFitPose>& poses,
                                    const RigidTransform& mount) {
  if (poses.size() < kMinPoses) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "fitting the mount's level needs at least " + std::to_string(kMinPoses) +
                         " corner poses (got " + std::to_string(poses.size()) + ")");
  }
  MountLevelFit out;
  for (size_t i = 0; i < poses.size(); ++i) out.used.push_back(i);
  Solution s = Solve(poses, out.used, mount);
  // Leave out the worst pose while it is beyond the gate, keeping at least three quarters.
  while (out.used.size() > std::max(kMinPoses, (3 * poses.size() + 3) / 4)) {
    const auto worst = std::max_element(s.mahalanobis2.begin(), s.mahalanobis2.end());
    if (*worst <= kMaxTipMahalanobis2) break;
    const size_t at = static_cast<size_t>(worst - s.mahalanobis2.begin());
    out.left_out.push_back(out.used[at]);
    out.left_out_sigmas.push_back(std::sqrt(*worst));
    out.used.erase(out.used.begin() + static_cast<std::ptrdiff_t>(at));
    s = Solve(poses, out.used, mount);
  }
  out.correction_rad = s.correction_rad;
  out.covariance = s.covariance;
  out.floor_sigma_rad = s.floor_sigma_rad;
  out.mount = Corrected(mount, s.correction_rad);
  return out;
}

}  // namespace monocle
