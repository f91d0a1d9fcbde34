#include "service/geometry/corner_pose.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "service/geometry/levenberg_marquardt.h"

namespace monocle {
namespace {

constexpr double kPi = std::numbers::pi;
// A candidate whose worst line misfit (angle in rad plus corner offset in normalized units)
// is below this explains the rays; 0.01 is ~16 px at f = 1600: generous, refinement follows.
constexpr double kExplainsRays = 0.01;

double WrapPi(double a) {
  a = std::fmod(a + kPi, 2 * kPi);
  if (a <= 0) a += 2 * kPi;
  return a - kPi;
}

Eigen::Vector2d Rotate(double angle, const Eigen::Vector2d& p) {
  const double s = std::sin(angle), c = std::cos(angle);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}

// Paper image coordinates from OpenCV normalized (x right, y down): u = -x, v = y. The
// paper's camera frame (U, V, W) is left-handed and, for a camera tilted up, V points down
// in the room; this is the mapping under which swing 0 is an upright camera.
Eigen::Vector2d ToPaper(const Eigen::Vector2d& n) { return {-n.x(), n.y()}; }

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// How far a pose is from explaining the rays, and whether it is physically possible.
void Score(const std::array<ObservedRay, 3>& rays, CornerCandidate* cand) {
  const Eigen::Matrix3d r = RotationCameraFromCorner(cand->pose);
  const Eigen::Vector3d c = CameraPosition(cand->pose);
  cand->valid = cand->pose.x_m > 0 && cand->pose.y_m > 0 && cand->pose.z_m > 0;
  cand->residual = 0;
  for (int k = 0; k < 3; ++k) {
    const auto img = ImageOfAxis(r, c, cand->axis_of_ray[k]);
    if (!img) {
      cand->valid = false;
      cand->residual = std::numeric_limits<double>::infinity();
      return;
    }
    if (img->direction.dot(rays[k].direction) <= 0) cand->valid = false;
    const double angle = std::abs(Cross(img->direction, rays[k].direction));
    const double offset = std::abs(Cross(img->corner - rays[k].corner, rays[k].direction));
    cand->residual = std::max(cand->residual, angle + offset);
  }
}

}  // namespace

// Projection into OpenCV normalized coordinates; empty behind the camera.
std::optional<Eigen::Vector2d> ProjectNormalized(const Eigen::Matrix3d& r, const Eigen::Vector3d& c,
                                                 const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = r * (p - c);
  if (q.z() <= 1e-12) return std::nullopt;
  return q.head<2>() / q.z();
}

std::optional<AxisImage> ImageOfAxis(const Eigen::Matrix3d& r, const Eigen::Vector3d& c, int axis) {
  const auto corner = ProjectNormalized(r, c, Eigen::Vector3d::Zero());
  if (!corner) return std::nullopt;
  // A step small against the camera distance keeps the point in front whenever the
  // corner is; the direction is exact in the limit and the projection is smooth.
  const double step = 1e-4 * std::max(c.norm(), 1e-3);
  const auto along = ProjectNormalized(r, c, step * Eigen::Vector3d::Unit(axis));
  if (!along) return std::nullopt;
  const Eigen::Vector2d d = *along - *corner;
  if (d.norm() < 1e-15) return std::nullopt;  // the axis points at the camera
  return AxisImage{*corner, d.normalized()};
}

std::ostream& operator<<(std::ostream& os, const CornerPose& p) {
  return os << "CornerPose{x=" << p.x_m << " y=" << p.y_m << " z=" << p.z_m
            << " m, pan=" << p.pan_rad << " tilt=" << p.tilt_rad << " swing=" << p.swing_rad
            << " rad}";
}

Eigen::Matrix3d RotationCameraFromCorner(const CornerPose& pose) {
  const double sp = std::sin(pose.pan_rad), cp = std::cos(pose.pan_rad);
  const double st = std::sin(pose.tilt_rad), ct = std::cos(pose.tilt_rad);
  const double ss = std::sin(pose.swing_rad), cs = std::cos(pose.swing_rad);
  // Rows: the paper's U, V, W axes in the corner frame (transpose of T_r's rotation).
  Eigen::Matrix3d uvw_from_corner;
  uvw_from_corner << cp, sp, 0, -sp * ct, cp * ct, st, -sp * st, cp * st, -ct;
  Eigen::Matrix3d swing;  // (u_i, v_i) = R(delta) (u_p, v_p)
  swing << cs, -ss, 0, ss, cs, 0, 0, 0, 1;
  // OpenCV's camera frame (x right, y down, z forward) is (-U, V, W): see ToPaper.
  return Eigen::Vector3d(-1, 1, 1).asDiagonal() * swing * uvw_from_corner;
}

Eigen::Vector3d CameraPosition(const CornerPose& pose) { return {pose.x_m, pose.y_m, pose.z_m}; }

Eigen::Vector3d CornerToCamera(const CornerPose& pose, const Eigen::Vector3d& p_corner) {
  return RotationCameraFromCorner(pose) * (p_corner - CameraPosition(pose));
}

CornerPose MovedBy(CornerPose pose, const Eigen::Matrix<double, 5, 1>& change) {
  pose.x_m += change[0];
  pose.y_m += change[1];
  pose.pan_rad += change[2];
  pose.tilt_rad += change[3];
  pose.swing_rad += change[4];
  return pose;
}

CornerPose Canonical(const CornerPose& pose) {
  CornerPose out = pose;
  double tilt = WrapPi(pose.tilt_rad);
  if (tilt < 0) {
    // (psi, Theta, delta) and (psi + pi, -Theta, delta - pi) are the same rotation.
    tilt = -tilt;
    out.pan_rad += kPi;
    out.swing_rad -= kPi;
  }
  out.tilt_rad = tilt;
  out.pan_rad = WrapPi(out.pan_rad);
  out.swing_rad = WrapPi(out.swing_rad);
  return out;
}

CornerPose PoseFromRotation(const Eigen::Matrix3d& camera_from_corner,
                            const Eigen::Vector3d& position) {
  // Undo RotationCameraFromCorner: R_uvw = diag(-1, 1, 1) R = R_w(delta) * U(psi, Theta),
  // whose third row is U's: (-sin psi sin Theta, cos psi sin Theta, -cos Theta), and whose
  // third column is R_w(delta) (0, sin Theta, -cos Theta).
  const Eigen::Matrix3d r = Eigen::Vector3d(-1, 1, 1).asDiagonal() * camera_from_corner;
  const double tilt = std::acos(std::clamp(-r(2, 2), -1.0, 1.0));
  const double pan = std::atan2(-r(2, 0), r(2, 1));
  const double swing = std::atan2(-r(0, 2), r(1, 2));
  return Canonical(CornerPose{position.x(), position.y(), position.z(), pan, tilt, swing});
}

std::array<PaperLine, 3> PaperLineCoefficients(const CornerPose& p) {
  const double xc = p.x_m, yc = p.y_m, zc = p.z_m;
  const double sp = std::sin(p.pan_rad), cp = std::cos(p.pan_rad);
  const double st = std::sin(p.tilt_rad), ct = std::cos(p.tilt_rad);
  const double sd = std::sin(p.swing_rad), cd = std::cos(p.swing_rad);
  std::array<PaperLine, 3> out;
  {  // (5), (6)
    const double m = yc * st - zc * cp * ct;
    const double den = -zc * sp * cd - m * sd;
    out[0] = {(-zc * sp * sd + m * cd) / den, (-yc * ct - zc * cp * st) / den};
  }
  {  // (7), (8)
    const double m = -xc * st - zc * sp * ct;
    const double den = zc * cp * cd - m * sd;
    out[1] = {(zc * cp * sd + m * cd) / den, (xc * ct - zc * sp * st) / den};
  }
  {  // (9), (10)
    const double m = xc * sp - yc * cp, n = xc * cp + yc * sp;
    const double den = m * cd - n * ct * sd;
    out[2] = {(m * sd + n * ct * cd) / den, (n * st) / den};
  }
  return out;
}

namespace {

// The closed form in one (possibly virtually rotated) camera: `rays` are as that camera sees
// them; every candidate is turned back into the real camera by `real_from_virtual` and
// scored against `real_rays`.
void SolveInFrame(const std::array<ObservedRay, 3>& rays, double zc,
                  const Eigen::Matrix3d& real_from_virtual,
                  const std::array<ObservedRay, 3>& real_rays, std::vector<CornerCandidate>* out) {
  // Virtual swing gamma: turn the image so that every line is far from horizontal, where
  // the paper's u + b v + c = 0 form breaks down. Three directions leave a gap of at least
  // 60 degrees, so the worst line stays >= 30 degrees from horizontal.
  std::array<double, 3> angles;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d d = ToPaper(rays[k].direction);
    angles[k] = std::atan2(d.y(), d.x());
  }
  double gamma = 0, best = -1;
  for (int step = 0; step < 180; ++step) {
    const double g = step * kPi / 180;
    double worst = 1;
    for (double a : angles) worst = std::min(worst, std::abs(std::sin(a - g)));
    if (worst > best) {
      best = worst;
      gamma = g;
    }
  }
  // Lines in the turned paper coordinates: u' = R(-gamma) u.
  std::array<PaperLine, 3> line;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d p = Rotate(-gamma, ToPaper(rays[k].corner));
    const Eigen::Vector2d d = Rotate(-gamma, ToPaper(rays[k].direction));
    const Eigen::Vector2d n(-d.y(), d.x());  // normal; n.x() != 0 by the choice of gamma
    line[k] = {n.y() / n.x(), -n.dot(p) / n.x()};
  }

  std::array<int, 3> perm{0, 1, 2};  // perm[axis] = ray index
  do {
    const double b1 = line[perm[0]].b, c1 = line[perm[0]].c;
    const double b2 = line[perm[1]].b, c2 = line[perm[1]].c;
    const double b3 = line[perm[2]].b, c3 = line[perm[2]].c;
    // Eq. (15) with f = 1. B_delta's c1 term is -c1 c3 (b2 + b3), not +: derived by
    // substituting (14) into (13); the printed sign fails the round trip.
    const double a_d = c3 * c3 * b1 * b2 + c3 * c3 * c1 * c2 + c1 * c3 + c2 * c3 + (1 + b1 * b2);
    const double b_d =
        c3 * c3 * (b1 + b2) - c1 * c3 * (b2 + b3) - c2 * c3 * (b3 + b1) - 2 * b3 * (1 + b1 * b2);
    const double c_d = c3 * c3 + c3 * c3 * c1 * c2 + c1 * c3 * b2 * b3 + c2 * c3 * b1 * b3 +
                       (1 + b1 * b2) * b3 * b3;
    std::vector<double> tan_deltas;
    double root_separation = 0;  // relative; small near a double root, where roots lose digits
    const double scale = std::max({std::abs(a_d), std::abs(b_d), std::abs(c_d)});
    if (std::abs(a_d) < 1e-12 * scale) {
      if (std::abs(b_d) > 0) tan_deltas.push_back(-c_d / b_d);
    } else {
      double disc = b_d * b_d - 4 * a_d * c_d;
      // Exact data sits on a double root at times; tolerate rounding below zero.
      if (disc < 0 && disc > -1e-10 * b_d * b_d) disc = 0;
      if (disc >= 0) {
        const double sq = std::sqrt(disc);
        // Numerically stable pair of roots.
        const double q = -0.5 * (b_d + std::copysign(sq, b_d));
        if (q != 0) {
          tan_deltas.push_back(q / a_d);
          tan_deltas.push_back(c_d / q);
          root_separation = std::abs(tan_deltas[0] - tan_deltas[1]) /
                            (1 + std::abs(tan_deltas[0]) + std::abs(tan_deltas[1]));
        } else {
          tan_deltas.push_back(0);
        }
      }
    }
    for (double tan_delta : tan_deltas) {
      for (double delta : {std::atan(tan_delta), std::atan(tan_delta) + kPi}) {
        const double sd = std::sin(delta), cd = std::cos(delta);
        // Eq. (14).
        const double theta0 = std::atan2(c3, b3 * cd - sd);
        for (double theta : {theta0, theta0 + kPi}) {
          const double st = std::sin(theta), ct = std::cos(theta);
          if (std::abs(st) < 1e-9) continue;
          // Eq. (11).
          const double psi0 = std::atan2(b1 * sd + cd, b1 * ct * cd - ct * sd + c1 * st);
          for (double psi : {psi0, psi0 + kPi}) {
            const double sp = std::sin(psi), cp = std::cos(psi);
            // Eq. (5) for Y_c and eq. (7) for X_c.
            const double den1 = cd + b1 * sd, den2 = cd + b2 * sd;
            if (std::abs(den1) < 1e-12 || std::abs(den2) < 1e-12) continue;
            const double p = zc * sp * (sd - b1 * cd) / den1;
            const double q = zc * cp * (b2 * cd - sd) / den2;
            const CornerPose virtual_pose{
                -(q + zc * sp * ct) / st, (p + zc * cp * ct) / st, zc, psi, theta, delta + gamma};
            CornerCandidate cand;
            cand.pose = PoseFromRotation(real_from_virtual * RotationCameraFromCorner(virtual_pose),
                                         CameraPosition(virtual_pose));
            cand.conditioning = std::min(root_separation, std::abs(st));
            for (int axis = 0; axis < 3; ++axis) cand.axis_of_ray[perm[axis]] = axis;
            Score(real_rays, &cand);
            out->push_back(cand);
          }
        }
      }
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
}

// Rays as seen by a camera turned by `virtual_from_real` about its centre.
std::optional<std::array<ObservedRay, 3>> RotateRays(const std::array<ObservedRay, 3>& rays,
                                                     const Eigen::Matrix3d& virtual_from_real) {
  std::array<ObservedRay, 3> out;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = virtual_from_real * rays[k].corner.homogeneous();
    const Eigen::Vector3d b =
        virtual_from_real * (rays[k].corner + 1e-3 * rays[k].direction).homogeneous();
    if (a.z() <= 1e-9 || b.z() <= 1e-9) return std::nullopt;
    out[k].corner = a.head<2>() / a.z();
    out[k].direction = (b.head<2>() / b.z() - out[k].corner).normalized();
  }
  return out;
}

}  // namespace

namespace {

// Virtual rotations of the camera about its centre (virtual_from_real) that move the
// corner's image off-centre, each in a direction halfway between two of the lines.
std::vector<Eigen::Matrix3d> Placements(const std::array<ObservedRay, 3>& rays) {
  Eigen::Vector2d corner = Eigen::Vector2d::Zero();
  for (const auto& r : rays) corner += r.corner / 3;
  std::array<double, 3> folded;
  for (int k = 0; k < 3; ++k) {
    folded[k] = std::fmod(std::atan2(rays[k].direction.y(), rays[k].direction.x()) + 2 * kPi, kPi);
  }
  std::sort(folded.begin(), folded.end());
  std::vector<Eigen::Matrix3d> out;
  for (int k = 0; k < 3; ++k) {
    const double next = k + 1 < 3 ? folded[k + 1] : folded[0] + kPi;
    const double mid = 0.5 * (folded[k] + next);
    for (double phi : {mid, mid + kPi}) {
      constexpr double kOffset = 0.4;  // normalized units, ~22 degrees off the axis
      const Eigen::Vector3d from = corner.homogeneous().normalized();
      const Eigen::Vector3d to =
          Eigen::Vector3d(kOffset * std::cos(phi), kOffset * std::sin(phi), 1).normalized();
      out.push_back(Eigen::Quaterniond::FromTwoVectors(from, to).toRotationMatrix());
    }
  }
  return out;
}

// Candidates of one placement.
void SolvePlacement(const std::array<ObservedRay, 3>& rays, double zc,
                    const Eigen::Matrix3d& virtual_from_real, int placement,
                    std::vector<CornerCandidate>* out) {
  const auto turned = RotateRays(rays, virtual_from_real);
  if (!turned) return;
  const size_t first = out->size();
  SolveInFrame(*turned, zc, virtual_from_real.transpose(), rays, out);
  for (size_t i = first; i < out->size(); ++i) (*out)[i].placement = placement;
}

// The orthogonal trihedron is symmetric under the cyclic relabelling X -> Y -> Z: each of
// the three cyclic labellings explains the rays exactly, with a different scale. The image
// cannot tell them apart; the mount can. A camera that sees a ceiling corner looks up
// (tilt < 90 degrees) and stands upright (small swing). Among the candidates that explain
// the rays, take one looking up, then the least swing. Measured over 20000 random views in
// the range tilt 10-85, swing +-30 degrees: every other such candidate looking up has
// |swing| > 60 degrees, a margin of 30 (corner_pose_test checks > 50).
const CornerCandidate* Choose(const std::vector<CornerCandidate>& candidates) {
  double best_residual = std::numeric_limits<double>::infinity();
  for (const auto& c : candidates) {
    if (c.valid) best_residual = std::min(best_residual, c.residual);
  }
  const double accept = std::max(kExplainsRays, 3 * best_residual);
  auto key = [](const CornerCandidate& k) {
    return std::make_pair(k.pose.tilt_rad >= kPi / 2, std::abs(k.pose.swing_rad));
  };
  const CornerCandidate* chosen = nullptr;
  for (const auto& c : candidates) {
    if (!c.valid || c.residual > accept) continue;
    if (chosen == nullptr || key(c) < key(*chosen)) chosen = &c;
  }
  return chosen;
}

}  // namespace

std::vector<CornerCandidate> SolveCornerCandidates(const std::array<ObservedRay, 3>& rays,
                                                   double zc) {
  // The paper's closed form is ill-conditioned when a corner line passes near the principal
  // point: eq. (14) becomes 0/0 and eq. (15) approaches a double root, losing half the
  // digits. That happens whenever the camera aims at the corner. A virtual rotation of the
  // camera about its centre moves the corner's image off-centre, in a direction that keeps
  // every line away from the principal point, without changing the camera's position; the
  // solution is turned back afterwards.
  std::vector<CornerCandidate> out;
  const auto placements = Placements(rays);
  for (size_t p = 0; p < placements.size(); ++p) {
    SolvePlacement(rays, zc, placements[p], static_cast<int>(p), &out);
  }
  return out;
}

Result<CornerCandidate> SolveCornerClosedForm(const std::array<ObservedRay, 3>& rays, double zc) {
  if (!(zc > 0))
    return MakeError(ErrorCode::kInvalidArgument, "the ceiling distance must be positive");
  // Placements in turn; the first whose choice is well conditioned is kept (the
  // conditioning bounds the digits lost), otherwise the best conditioned of all.
  constexpr double kWellConditioned = 0.05;
  std::optional<CornerCandidate> best;
  const auto placements = Placements(rays);
  for (size_t p = 0; p < placements.size(); ++p) {
    std::vector<CornerCandidate> candidates;
    SolvePlacement(rays, zc, placements[p], static_cast<int>(p), &candidates);
    const CornerCandidate* chosen = Choose(candidates);
    if (chosen == nullptr) continue;
    if (!best || chosen->conditioning > best->conditioning) best = *chosen;
    if (best->conditioning > kWellConditioned) break;
  }
  if (!best) {
    return MakeError(
        ErrorCode::kDegenerate,
        "the three lines cannot be the edges of a ceiling corner seen from inside the room");
  }
  return *best;
}

}  // namespace monocle
