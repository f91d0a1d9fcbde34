#include "service/geometry/floor_guidance.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <utility>

namespace monocle {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

std::string Format(const char* format, auto... values) {
  char text[2048];
  std::snprintf(text, sizeof text, format, values...);
  return text;
}

// Metres, as a person reads them: millimetres below 10 cm.
std::string Metres(double m) {
  return std::abs(m) < 0.1 ? Format("%.1f mm", m * 1e3) : Format("%.3f m", m);
}

// Covariance (x, y) of the floor point straight ahead at `distance_m` under `noise`;
// nullopt where the point cannot be seen (above the horizon).
std::optional<Eigen::Matrix2d> CovarianceAhead(const CameraIntrinsics& k, const FloorPose& pose,
                                               const MeasurementNoise& noise, double distance_m) {
  const auto px = ProjectRobotPoint(k, pose, Eigen::Vector3d(0, distance_m, 0));
  if (!px) return std::nullopt;
  const auto m = MeasureFloorPoint(k, pose, noise, *px);
  if (!m) return std::nullopt;
  return m->covariance.topLeftCorner<2, 2>();
}

// The 1 sigma along the point's least certain horizontal direction.
std::optional<double> SigmaAhead(const CameraIntrinsics& k, const FloorPose& pose,
                                 const MeasurementNoise& noise, double distance_m) {
  const auto c = CovarianceAhead(k, pose, noise, distance_m);
  if (!c) return std::nullopt;
  return std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(*c).eigenvalues()[1]);
}

bool InImage(const CameraIntrinsics& k, const FloorPose& pose, double distance_m) {
  const auto px = ProjectRobotPoint(k, pose, Eigen::Vector3d(0, distance_m, 0));
  return px && px->x() >= 0 && px->y() >= 0 && px->x() < k.width_px && px->y() < k.height_px;
}

struct Shares {
  MeasurementNoise total, calibration, intrinsics, pixel;
};

Shares SharesOf(const FloorCalibration& floor, const IntrinsicsCovariance& k_covariance,
                double pixel_sigma_px) {
  Shares s;
  s.total = MeasurementNoiseOf(floor, k_covariance, pixel_sigma_px);
  s.calibration = MeasurementNoiseOf(floor, k_covariance, 0);
  // The intrinsics' share: what they add to the pose (the corners' part is independent of
  // them), themselves, and the correlation between the two.
  s.intrinsics = s.calibration;
  s.intrinsics.pose_covariance = floor.covariance - floor.corner_covariance;
  s.pixel.pixel_sigma_px = pixel_sigma_px;
  return s;
}

FloorAccuracyAt AccuracyAt(const CameraIntrinsics& k, const FloorPose& pose, const Shares& s,
                           double distance_m) {
  FloorAccuracyAt a;
  a.distance_m = distance_m;
  a.in_image = InImage(k, pose, distance_m);
  const auto total = CovarianceAhead(k, pose, s.total, distance_m);
  if (!total) {
    a.sigma_m = a.calibration_sigma_m = a.intrinsics_sigma_m = a.pixel_sigma_m = INFINITY;
    return a;
  }
  // Every share along the total's least certain direction, so that they add in quadrature.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(*total);
  const Eigen::Vector2d axis = eigen.eigenvectors().col(1);
  auto along = [&](const MeasurementNoise& noise) {
    const auto c = CovarianceAhead(k, pose, noise, distance_m);
    return c ? std::sqrt(std::max(0.0, axis.dot(*c * axis))) : INFINITY;
  };
  a.sigma_m = std::sqrt(eigen.eigenvalues()[1]);
  a.calibration_sigma_m = along(s.calibration);
  a.intrinsics_sigma_m = along(s.intrinsics);
  a.pixel_sigma_m = along(s.pixel);
  return a;
}

// The farthest distance ahead, within the image, out to which `noise` keeps a floor point
// within sigma_m; 0 if not even the nearest point in view is.
double MetOutTo(const CameraIntrinsics& k, const FloorPose& pose, const MeasurementNoise& noise,
                double sigma_m) {
  constexpr double kStepM = 0.05, kFarthestM = 50;
  double d = kStepM;
  while (d <= kFarthestM && !InImage(k, pose, d)) d += kStepM;
  double met = 0;
  for (; d <= kFarthestM && InImage(k, pose, d); d += kStepM) {
    const auto s = SigmaAhead(k, pose, noise, d);
    if (!s || *s > sigma_m) break;
    met = d;
  }
  return met;
}

BoardPlacement PlacementOf(const CameraIntrinsics& k, const FloorCalibration& floor,
                           const BoardObservation& board) {
  BoardPlacement p;
  const Eigen::Vector2d centre_board(0.5 * (board.cols - 1) * board.square_m,
                                     0.5 * (board.rows - 1) * board.square_m);
  const Eigen::Vector3d centre =
      BoardToRobot(floor.pose.yaw_rad, floor.board_origin_robot_m, centre_board);
  const double ground = centre.head<2>().norm();
  p.distance_m = std::hypot(ground, floor.pose.height_m);
  p.sight_angle_deg = std::atan2(floor.pose.height_m, ground) * kDeg;
  double y_min = INFINITY, y_max = -INFINITY;
  for (int j = 0; j < board.rows; ++j) {
    for (int i = 0; i < board.cols; ++i) {
      const double y =
          BoardToRobot(floor.pose.yaw_rad, floor.board_origin_robot_m, board.BoardPoint(i, j)).y();
      y_min = std::min(y_min, y);
      y_max = std::max(y_max, y);
    }
  }
  p.depth_span_m = y_max - y_min;
  // The outline through the four outer corners (shoelace).
  const Eigen::Vector2d outline[4] = {board.Pixel(0, 0), board.Pixel(board.cols - 1, 0),
                                      board.Pixel(board.cols - 1, board.rows - 1),
                                      board.Pixel(0, board.rows - 1)};
  double twice_area = 0;
  for (int c = 0; c < 4; ++c) {
    const auto& a = outline[c];
    const auto& b = outline[(c + 1) % 4];
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  p.image_fraction = 0.5 * std::abs(twice_area) / (double(k.width_px) * k.height_px);
  return p;
}

// The best place straight ahead, with the calibration's yaw and wholly inside the image, for
// a board (cols x rows, `square_m`): the one whose predicted calibration gives the smallest
// 1 sigma by `sigma_of`. Nothing if the board fits nowhere.
std::optional<BoardSuggestion> BestPlacement(
    const CameraIntrinsics& k, const IntrinsicsCovariance& k_covariance,
    const FloorCalibration& floor, int cols, int rows, double square_m, double corner_sigma_px,
    const std::function<double(const FloorCalibration&)>& sigma_of) {
  const double margin_px = 0.03 * std::min(k.width_px, k.height_px);
  const Eigen::Vector2d centre_board(0.5 * (cols - 1) * square_m, 0.5 * (rows - 1) * square_m);
  const Eigen::Vector2d centre_offset =
      BoardToRobot(floor.pose.yaw_rad, Eigen::Vector2d::Zero(), centre_board).head<2>();
  std::optional<BoardSuggestion> best;
  for (double d = 0.1; d <= 20; d += 0.1) {
    const Eigen::Vector2d origin = Eigen::Vector2d(0, d) - centre_offset;
    const auto board = ProjectBoard(k, floor.pose, origin, cols, rows, square_m);
    if (!board) continue;
    const bool inside = std::all_of(board->pixels.begin(), board->pixels.end(), [&](auto& px) {
      return px.x() >= margin_px && px.y() >= margin_px && px.x() <= k.width_px - margin_px &&
             px.y() <= k.height_px - margin_px;
    });
    if (!inside) continue;
    const auto predicted = PredictFloorCalibration(k, floor.pose, origin, cols, rows, square_m,
                                                   corner_sigma_px, k_covariance);
    if (!predicted) continue;
    const double sigma = sigma_of(*predicted);
    if (!best || sigma < best->predicted_sigma_m) best = BoardSuggestion{d, square_m, sigma};
  }
  return best;
}

// Why the paper's linear solve (eq. 13) gave a result that is no use, next to the full
// method's fit of the same corners.
std::string PaperIllConditionedReason(const FloorCalibration& paper, const FloorCalibration& full,
                                      const BoardPlacement& placement) {
  std::string roll;
  if (std::abs(full.pose.roll_rad) * kDeg > 0.5) {
    roll = Format(" It also assumes the camera has no roll; the full method finds %.1f deg.",
                  full.pose.roll_rad * kDeg);
  }
  return Format(
      "the paper's linear solve (eq. 13) is ill-conditioned for this board: its result places "
      "the corners %.2f px (RMS) from where they were found, where the full method fits them "
      "to %.2f px. Eq. (13) reads height and pitch only from how the corners along each column "
      "crowd together with distance, and its least squares has the measured coordinates on "
      "both sides, so even small corner noise biases it (towards a smaller height), the more "
      "the less this board's %.2f m of depth at %.2f m foreshortens (condition number "
      "%.1e).%s The full method on the same corners gives height %.4f m +- %s, pitch %.2f "
      "+- %.2f deg: use --method full (the default).",
      paper.rms_px, full.rms_px, placement.depth_span_m, placement.distance_m,
      paper.condition_number, roll.c_str(), full.pose.height_m, Metres(full.Sigma()[0]).c_str(),
      full.pose.pitch_rad * kDeg, full.Sigma()[1] * kDeg);
}

bool Uninformative(const FloorCalibration& c) {
  const auto sigma = c.Sigma();
  return !(sigma[0] <= 0.25 * c.pose.height_m) || !(sigma[1] <= 0.1);
}

// Whether the calibration is of no use (the paper's method where the full one explains the
// corners far better, or either with an uninformative spread): g->ill_conditioned and why.
// Also where the board really lay, from the full method, when the paper's was asked for.
void JudgeConditioning(const CameraIntrinsics& k, const IntrinsicsCovariance& k_covariance,
                       const FloorCalibration& floor, const BoardObservation& board,
                       FloorGuidance* guidance) {
  FloorGuidance& g = *guidance;
  if (floor.method == FloorCalibrationMethod::kPaper) {
    // The paper's result is no use when the full method explains the same corners far
    // better (its bias shows as a poor fit), or when its own spread says nothing.
    const auto full = CalibrateFloor(k, board, FloorCalibrationMethod::kFull, k_covariance);
    if (full) g.board = PlacementOf(k, *full, board);  // where the board really lay
    if (full && (Uninformative(floor) || floor.rms_px > 3 * full->rms_px + 0.1)) {
      g.ill_conditioned = true;
      g.ill_conditioned_reason = PaperIllConditionedReason(floor, *full, g.board);
    }
  } else if (Uninformative(floor)) {
    const auto sigma = floor.Sigma();
    g.ill_conditioned = true;
    g.ill_conditioned_reason = Format(
        "the board constrains the camera's pose too weakly to be used (1 sigma height %s, "
        "pitch %.1f deg): it is %.2f m away and covers %.1f %% of the image; lay it nearer.",
        Metres(sigma[0]).c_str(), sigma[1] * kDeg, g.board.distance_m,
        100 * g.board.image_fraction);
  }
}

}  // namespace

FloorGuidance AdviseFloorCalibration(const CameraIntrinsics& k,
                                     const IntrinsicsCovariance& k_covariance,
                                     const FloorCalibration& floor, const BoardObservation& board,
                                     double pixel_sigma_px,
                                     const std::optional<FloorAccuracyTarget>& target) {
  FloorGuidance g;
  g.board = PlacementOf(k, floor, board);
  g.target = target;
  const double corner_sigma_px = floor.rms_px / std::sqrt(2.0);
  JudgeConditioning(k, k_covariance, floor, board, &g);
  if (g.ill_conditioned) {
    g.target_met = !target.has_value();
    return g;
  }
  const Shares shares = SharesOf(floor, k_covariance, pixel_sigma_px);
  std::vector<double> distances = {1, 2, 4};
  if (target &&
      std::find(distances.begin(), distances.end(), target->distance_m) == distances.end())
    distances.push_back(target->distance_m);
  std::sort(distances.begin(), distances.end());
  for (double d : distances) g.accuracy.push_back(AccuracyAt(k, floor.pose, shares, d));
  if (!target) return g;

  const FloorAccuracyAt at = AccuracyAt(k, floor.pose, shares, target->distance_m);
  g.target_met = at.sigma_m <= target->sigma_m;
  g.target_met_out_to_m = MetOutTo(k, floor.pose, shares.total, target->sigma_m);
  if (g.target_met) return g;

  const double d = target->distance_m;
  if (at.pixel_sigma_m >= target->sigma_m) {
    g.advice.push_back(Format(
        "At %.1f m the query pixel's own noise (%.2f px) alone gives 1 sigma %s: no board can "
        "meet %s there. %s, or use a longer lens.",
        d, pixel_sigma_px, Metres(at.pixel_sigma_m).c_str(), Metres(target->sigma_m).c_str(),
        g.target_met_out_to_m > 0
            ? Format("Measure nearer (it is met out to %.2f m)", g.target_met_out_to_m).c_str()
            : "It is met nowhere in the image"));
    return g;
  }
  if (std::hypot(at.pixel_sigma_m, at.intrinsics_sigma_m) >= target->sigma_m) {
    g.advice.push_back(
        Format("The intrinsics' uncertainty alone gives 1 sigma %s at %.1f m: calibrate the "
               "intrinsics again with more views reaching into the image's corners (monocle "
               "intrinsics calibrate), then the floor.",
               Metres(at.intrinsics_sigma_m).c_str(), d));
  }
  auto predicted_at = [&](const FloorCalibration& c) {
    return SigmaAhead(k, c.pose, MeasurementNoiseOf(c, k_covariance, pixel_sigma_px), d)
        .value_or(INFINITY);
  };
  auto verdict = [&](double s) {
    return s <= target->sigma_m ? "meets the target" : "still short";
  };
  // Only a change the same first-order model predicts to help by a fifth or more is advised:
  // a far board calibrates best for points far away, so "nearer" is not always better.
  constexpr double kWorthIt = 0.8;
  const double ground_now = std::sqrt(std::max(
      0.0, g.board.distance_m * g.board.distance_m - floor.pose.height_m * floor.pose.height_m));
  bool said_why = false;
  const auto same = BestPlacement(k, k_covariance, floor, board.cols, board.rows, board.square_m,
                                  corner_sigma_px, predicted_at);
  if (same && same->predicted_sigma_m < kWorthIt * at.sigma_m) {
    g.suggestions.push_back(*same);
    const bool nearer = same->ground_distance_m < ground_now;
    const std::string why =
        nearer ? (g.board.sight_angle_deg < 20
                      ? Format("too far and seen too obliquely (the line of sight meets the "
                               "floor at %.0f deg)",
                               g.board.sight_angle_deg)
                      : std::string("too far"))
               : Format("too near for points %.1f m ahead", d);
    g.advice.push_back(
        Format("The board is %s: its centre lies %.2f m ahead. Laid %.2f m ahead the same board "
               "would give 1 sigma %s at %.1f m (%s).",
               why.c_str(), ground_now, same->ground_distance_m,
               Metres(same->predicted_sigma_m).c_str(), d, verdict(same->predicted_sigma_m)));
    said_why = true;
  }
  const double best_same = same ? std::min(same->predicted_sigma_m, at.sigma_m) : at.sigma_m;
  const auto larger = BestPlacement(k, k_covariance, floor, board.cols, board.rows,
                                    2 * board.square_m, corner_sigma_px, predicted_at);
  if (g.board.image_fraction < 0.15 && larger && larger->predicted_sigma_m < kWorthIt * best_same) {
    g.suggestions.push_back(*larger);
    g.advice.push_back(
        Format("The board is too small in the image: it covers %.1f %% of it. A board with %.0f mm "
               "squares laid %.2f m ahead would give 1 sigma %s (%s).",
               100 * g.board.image_fraction, 2e3 * board.square_m, larger->ground_distance_m,
               Metres(larger->predicted_sigma_m).c_str(), verdict(larger->predicted_sigma_m)));
    said_why = true;
  }
  if (!said_why) {
    g.advice.push_back(Format(
        "The board's corners (%.2f px of noise) limit this calibration to 1 sigma %s at %.1f m: "
        "a board with more or larger squares, a sharper image, or measure nearer.",
        corner_sigma_px, Metres(at.calibration_sigma_m).c_str(), d));
  }
  return g;
}

std::optional<std::string> FloorHeightUnitSlip(double height_m, double square_m,
                                               const UnitSlipWords& words) {
  constexpr double kLowestM = 0.05, kHighestM = 10;
  if (height_m >= kLowestM && height_m <= kHighestM) return std::nullopt;
  std::ostringstream os;
  os << std::setprecision(4) << "a camera " << height_m
     << " m above the floor is no robot's (expected " << kLowestM << "-" << kHighestM
     << " m): " << words.square << " is in metres, and the height scales with it.";
  // Read as centimetres or millimetres, would the square give a robot's height?
  for (const auto& [factor, unit] : {std::pair{0.01, "cm"}, std::pair{0.001, "mm"}}) {
    const double height = height_m * factor;
    if (height < kLowestM || height > kHighestM) continue;
    os << " If the square is " << square_m << " " << unit << ", give " << words.square << " "
       << square_m * factor << " (height " << height << " m).";
  }
  os << " " << words.force << " keeps this result.";
  return os.str();
}

}  // namespace monocle
