// Camera pose from the three edges of a ceiling corner (Chou & Tsai 1986).
// Pure geometry: Eigen only, no I/O.
//
// Corner frame G (the paper's global system): origin at the corner, X and Y along the two
// ceiling edges, Z along the vertical wall edge pointing DOWN from the ceiling, so the
// room is x > 0, y > 0, z > 0 and the camera sits at (x, y, z) with z = the camera-to-ceiling
// distance. Right-handed.
//
// Orientation, exactly as eq. (1) and section 2.2: pan psi about Z, tilt Theta about the
// rotated X, then the Z reversal F_z, then swing delta rotating the image plane. Tilt 0 looks
// straight up at the ceiling, tilt pi/2 looks level.
//
// Image coordinates of the paper (u, v), focal length 1: u = -x_n and v = y_n for OpenCV's
// normalized coordinates (x_n right, y_n down) after undistortion, i.e. u runs to the
// image's left and v down. The paper's (U, V, W) camera frame is left-handed and its V axis
// points down in the room when the camera tilts up, so this is the mapping under which
// swing 0 is an upright camera (the vertical edge runs down the image). Lines are
// u + b v + c = 0.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <ostream>
#include <vector>

#include "service/common/result.h"

namespace monocle {

struct CornerPose {
  double x_m = 0, y_m = 0, z_m = 0;  // camera position in the corner frame; z = ceiling distance
  double pan_rad = 0;                // psi
  double tilt_rad = 0;               // Theta, in [0, pi)
  double swing_rad = 0;              // delta
};

std::ostream& operator<<(std::ostream& os, const CornerPose& p);

// Rotation taking corner-frame vectors into OpenCV's camera frame (x right, y down,
// z forward): p_camera = R * (p_corner - position).
Eigen::Matrix3d RotationCameraFromCorner(const CornerPose& pose);
Eigen::Vector3d CameraPosition(const CornerPose& pose);
Eigen::Vector3d CornerToCamera(const CornerPose& pose, const Eigen::Vector3d& p_corner);

// Canonical angles: tilt in [0, pi), pan and swing in (-pi, pi].
CornerPose Canonical(const CornerPose& pose);

// The pose moved by `change` of (x, y, pan, tilt, swing), metres and radians: the order of a
// corner pose's 5x5 covariance. Angles are not wrapped.
CornerPose MovedBy(CornerPose pose, const Eigen::Matrix<double, 5, 1>& change);

// A line u + b v + c = 0 in the paper's image coordinates (focal length 1).
struct PaperLine {
  double b = 0, c = 0;
};

// Eqs. (5)-(10): the coefficients of the images of the X, Y and Z axes, f = 1.
std::array<PaperLine, 3> PaperLineCoefficients(const CornerPose& pose);

// An observed image ray from the corner along one edge, in OpenCV normalized (undistorted)
// coordinates: it starts at the corner and runs along `direction` (unit).
struct ObservedRay {
  Eigen::Vector2d corner = Eigen::Vector2d::Zero();
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();
};

// The pose whose camera has this rotation (as RotationCameraFromCorner) and position.
CornerPose PoseFromRotation(const Eigen::Matrix3d& camera_from_corner,
                            const Eigen::Vector3d& position);

// One finished candidate of the closed form, with how well it explains the observation.
struct CornerCandidate {
  CornerPose pose;
  std::array<int, 3> axis_of_ray{};  // ray k is the image of axis axis_of_ray[k] (0 X, 1 Y, 2 Z)
  double residual = 0;               // max line misfit, normalized image units
  bool valid = false;                // corner in front, inside the room, rays point the right way
  double conditioning = 0;           // min(relative root separation of eq. 16, sin Theta)
  int placement = 0;                 // which virtual rotation produced it
};

// Section 2.3 with every branch kept: both roots of eq. (16) (with the corrected B_delta),
// the pi-branches of delta, Theta and psi, and all six labellings of the rays as X, Y, Z.
// Solved in six virtually rotated cameras (same centre) that keep every line away from the
// principal point, each with a virtual swing so no line is horizontal (b finite).
std::vector<CornerCandidate> SolveCornerCandidates(const std::array<ObservedRay, 3>& rays,
                                                   double ceiling_distance_m);

// The valid candidate that best reprojects the rays, or an error saying why none does.
Result<CornerCandidate> SolveCornerClosedForm(const std::array<ObservedRay, 3>& rays,
                                              double ceiling_distance_m);

// Projection into OpenCV normalized coordinates of a corner-frame point `p`, seen by a camera
// at `c` with rotation `r` (camera from corner); empty behind the camera.
std::optional<Eigen::Vector2d> ProjectNormalized(const Eigen::Matrix3d& r, const Eigen::Vector3d& c,
                                                 const Eigen::Vector3d& p);

// Image of one axis near the corner: the projected corner and the unit direction in which
// the axis leaves it (OpenCV normalized coordinates).
struct AxisImage {
  Eigen::Vector2d corner, direction;
};
std::optional<AxisImage> ImageOfAxis(const Eigen::Matrix3d& r, const Eigen::Vector3d& c, int axis);

}  // namespace monocle
