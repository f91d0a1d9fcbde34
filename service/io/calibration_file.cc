#include "service/io/calibration_file.h"

#include "service/io/bounded_file.h"
#include "service/io/text_proto.h"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>

namespace monocle {
namespace {

Error Invalid(const std::string& source, const std::string& field, const std::string& why) {
  return MakeError(ErrorCode::kInvalidArgument, source + ": field '" + field + "' " + why);
}

bool Finite(double v) { return std::isfinite(v); }

// A length in metres that must lie in (0, 1000]: the message says so, and a value that reads
// like millimetres (the papers' unit) says what it would be in metres.
std::optional<Error> CheckMetres(const std::string& source, const std::string& field, double v,
                                 const std::string& what) {
  if (v > 0 && Finite(v) && v <= 1000) return std::nullopt;
  std::ostringstream os;
  os << "must be " << what << " in metres, more than 0 and at most 1000";
  if (Finite(v) && v > 1000) os << "; " << v << " reads like millimetres: " << v / 1000 << " m";
  return Invalid(source, field, os.str());
}

// The intrinsics section into `out` (intrinsics, their covariance and model).
Status ParseIntrinsicsSection(const proto::Calibration& msg, const std::string& source,
                              CameraCalibration* out_calibration) {
  CameraCalibration& out = *out_calibration;
  const auto& in = msg.intrinsics();
  auto& k = out.intrinsics;
  if (in.width() == 0 || in.width() > 65535)
    return Invalid(source, "intrinsics.width", "must be 1..65535 pixels");
  if (in.height() == 0 || in.height() > 65535)
    return Invalid(source, "intrinsics.height", "must be 1..65535 pixels");
  k.width_px = static_cast<int>(in.width());
  k.height_px = static_cast<int>(in.height());
  if (!(in.fx() > 0) || !Finite(in.fx()))
    return Invalid(source, "intrinsics.fx", "must be a positive focal length in pixels");
  if (!(in.fy() > 0) || !Finite(in.fy()))
    return Invalid(source, "intrinsics.fy", "must be a positive focal length in pixels");
  if (!Finite(in.cx()) || in.cx() < 0 || in.cx() > k.width_px)
    return Invalid(source, "intrinsics.cx", "must lie inside the image (0..width pixels)");
  if (!Finite(in.cy()) || in.cy() < 0 || in.cy() > k.height_px)
    return Invalid(source, "intrinsics.cy", "must lie inside the image (0..height pixels)");
  k.fx = in.fx();
  k.fy = in.fy();
  k.cx = in.cx();
  k.cy = in.cy();
  const int nd = in.distortion_size();
  if (nd != 0 && nd != 4 && nd != 5 && nd != 8) {
    return Invalid(
        source, "intrinsics.distortion",
        "must have 0, 4 (k1 k2 p1 p2), 5 (+k3) or 8 (+k3..k6) values, not " + std::to_string(nd));
  }
  for (int i = 0; i < nd; ++i) {
    if (!Finite(in.distortion(i)) || std::abs(in.distortion(i)) > 1e4) {
      return Invalid(source, "intrinsics.distortion",
                     "value " + std::to_string(i + 1) + " is not a finite coefficient");
    }
    k.distortion[i] = in.distortion(i);
  }
  out.intrinsics_rms_px = in.has_rms_px() ? in.rms_px() : 0.0;
  if (in.covariance_size() != 0) {
    constexpr int n = kNumIntrinsicParams;
    if (in.covariance_size() != n * n) {
      return Invalid(source, "intrinsics.covariance",
                     "must have 81 values (9x9 of fx fy cx cy k1 k2 p1 p2 k3, row-major), not " +
                         std::to_string(in.covariance_size()));
    }
    for (int i = 0; i < n * n; ++i) {
      if (!Finite(in.covariance(i)))
        return Invalid(source, "intrinsics.covariance", "has a value that is not finite");
      out.intrinsics_covariance(i / n, i % n) = in.covariance(i);
    }
    if (!out.intrinsics_covariance.isApprox(out.intrinsics_covariance.transpose(), 1e-6) ||
        (out.intrinsics_covariance.diagonal().array() < 0).any()) {
      return Invalid(source, "intrinsics.covariance",
                     "is not a covariance (not symmetric, or a negative variance)");
    }
  }
  if (in.has_model()) {
    if (in.model() != "k1k2" && in.model() != "k1k2p1p2" && in.model() != "k1k2p1p2k3")
      return Invalid(source, "intrinsics.model", "must be k1k2, k1k2p1p2 or k1k2p1p2k3");
    out.distortion_model = in.model();
  }

  return Ok{};
}

// The floor section: the camera's height, pitch, yaw and roll with their covariances.
Result<FloorCalibration> ParseFloorSection(const proto::Calibration& msg,
                                           const std::string& source) {
  const auto& f = msg.floor();
  FloorCalibration fc;
  if (!f.has_height()) return Invalid(source, "floor.height", "is missing");
  if (auto wrong = CheckMetres(source, "floor.height", f.height(),
                               "the optical centre's height above the floor"))
    return *wrong;
  if (!f.has_pitch()) return Invalid(source, "floor.pitch", "is missing");
  if (!Finite(f.pitch()) || f.pitch() <= 0 || f.pitch() >= std::numbers::pi) {
    return Invalid(
        source, "floor.pitch",
        "must be an angle in (0, pi) radians between the floor's up normal and the optical axis");
  }
  if (!Finite(f.yaw()) || std::abs(f.yaw()) > std::numbers::pi)
    return Invalid(source, "floor.yaw", "must be an angle in [-pi, pi] radians");
  if (!Finite(f.roll()) || std::abs(f.roll()) > std::numbers::pi)
    return Invalid(source, "floor.roll", "must be an angle in [-pi, pi] radians");
  fc.pose = FloorPose{f.height(), f.pitch(), f.yaw(), f.roll()};
  if (f.covariance_size() != 0 && f.covariance_size() != 16) {
    return Invalid(
        source, "floor.covariance",
        "must have 16 values (4x4, row-major), not " + std::to_string(f.covariance_size()));
  }
  for (int i = 0; i < f.covariance_size(); ++i) {
    if (!Finite(f.covariance(i)))
      return Invalid(source, "floor.covariance", "has a value that is not finite");
    fc.covariance(i / 4, i % 4) = f.covariance(i);
  }
  for (int i = 0; i < 4; ++i) {
    if (fc.covariance(i, i) < 0)
      return Invalid(source, "floor.covariance", "has a negative variance on its diagonal");
  }
  if (f.intrinsics_cross_covariance_size() != 0) {
    constexpr int n = kNumIntrinsicParams;
    if (f.intrinsics_cross_covariance_size() != 4 * n) {
      return Invalid(source, "floor.intrinsics_cross_covariance",
                     "must have 36 values (4x9, row-major), not " +
                         std::to_string(f.intrinsics_cross_covariance_size()));
    }
    for (int i = 0; i < 4 * n; ++i) {
      if (!Finite(f.intrinsics_cross_covariance(i)))
        return Invalid(source, "floor.intrinsics_cross_covariance",
                       "has a value that is not finite");
      fc.intrinsics_cross_covariance(i / n, i % n) = f.intrinsics_cross_covariance(i);
    }
  }
  fc.rms_px = f.has_rms_px() ? f.rms_px() : 0.0;
  if (f.has_method() && f.method() != "full" && f.method() != "paper") {
    return Invalid(source, "floor.method", "must be \"full\" or \"paper\"");
  }
  fc.method =
      f.method() == "paper" ? FloorCalibrationMethod::kPaper : FloorCalibrationMethod::kFull;
  return fc;
}

// The corner section: the ceiling distance and the largest roll a pose may have.
Status ParseCornerSection(const proto::Calibration& msg, const std::string& source,
                          CameraCalibration* out_calibration) {
  CameraCalibration& out = *out_calibration;
  if (msg.has_corner() && msg.corner().has_ceiling_distance()) {
    const double z = msg.corner().ceiling_distance();
    if (auto wrong = CheckMetres(source, "corner.ceiling_distance", z,
                                 "the optical centre's distance to the ceiling"))
      return *wrong;
    out.ceiling_distance_m = z;
  }
  if (msg.has_corner() && msg.corner().has_max_swing()) {
    const double swing = msg.corner().max_swing();
    if (!Finite(swing) || !(swing > 0) || swing > std::numbers::pi)
      return Invalid(source, "corner.max_swing",
                     "must be an angle in radians, more than 0 and at most pi (3.14159)");
    out.corner_max_swing_rad = swing;
  }
  return Ok{};
}

}  // namespace

Result<CameraCalibration> ParseCalibration(const std::string& text, const std::string& source) {
  proto::Calibration msg;
  if (auto parsed = ParseTextProto(text, source, &msg); !parsed) return parsed.error();
  if (!msg.has_intrinsics()) return Invalid(source, "intrinsics", "is missing");
  CameraCalibration out;
  if (Status s = ParseIntrinsicsSection(msg, source, &out); !s) return s.error();
  if (msg.has_floor()) {
    auto floor = ParseFloorSection(msg, source);
    if (!floor) return floor.error();
    out.floor = *floor;
  }
  if (Status s = ParseCornerSection(msg, source, &out); !s) return s.error();
  return out;
}

Result<CameraCalibration> LoadCalibrationFile(const std::string& path) {
  auto text = ReadBoundedFile(path, "calibration file", kMaxTextFileBytes);
  if (!text) return text.error();
  return ParseCalibration(*text, path);
}

std::string FormatCalibration(const CameraCalibration& c) {
  proto::Calibration msg;
  auto* in = msg.mutable_intrinsics();
  const auto& k = c.intrinsics;
  in->set_width(k.width_px);
  in->set_height(k.height_px);
  in->set_fx(k.fx);
  in->set_fy(k.fy);
  in->set_cx(k.cx);
  in->set_cy(k.cy);
  int nd = 8;
  while (nd > 0 && k.distortion[nd - 1] == 0) --nd;
  nd = nd == 0 ? 0 : (nd <= 4 ? 4 : (nd == 5 ? 5 : 8));
  for (int i = 0; i < nd; ++i) in->add_distortion(k.distortion[i]);
  if (c.intrinsics_rms_px > 0) in->set_rms_px(c.intrinsics_rms_px);
  if (!c.intrinsics_covariance.isZero()) {
    for (int i = 0; i < kNumIntrinsicParams * kNumIntrinsicParams; ++i)
      in->add_covariance(c.intrinsics_covariance(i / kNumIntrinsicParams, i % kNumIntrinsicParams));
  }
  if (!c.distortion_model.empty()) in->set_model(c.distortion_model);
  if (c.floor) {
    auto* f = msg.mutable_floor();
    f->set_height(c.floor->pose.height_m);
    f->set_pitch(c.floor->pose.pitch_rad);
    f->set_yaw(c.floor->pose.yaw_rad);
    f->set_roll(c.floor->pose.roll_rad);
    if (!c.floor->covariance.isZero()) {
      for (int i = 0; i < 16; ++i) f->add_covariance(c.floor->covariance(i / 4, i % 4));
    }
    if (!c.floor->intrinsics_cross_covariance.isZero()) {
      for (int i = 0; i < 4 * kNumIntrinsicParams; ++i)
        f->add_intrinsics_cross_covariance(
            c.floor->intrinsics_cross_covariance(i / kNumIntrinsicParams, i % kNumIntrinsicParams));
    }
    if (c.floor->rms_px > 0) f->set_rms_px(c.floor->rms_px);
    f->set_method(ToString(c.floor->method));
  }
  if (c.ceiling_distance_m) msg.mutable_corner()->set_ceiling_distance(*c.ceiling_distance_m);
  if (c.corner_max_swing_rad) msg.mutable_corner()->set_max_swing(*c.corner_max_swing_rad);
  google::protobuf::TextFormat::Printer printer;
  std::string text;
  printer.PrintToString(msg, &text);
  return "# monocle camera calibration (idl/calibration.proto). Metres, radians, pixels.\n" + text;
}

Status SaveCalibrationFileAtomically(const std::string& path, const CameraCalibration& c) {
  return WriteFileAtomically(path, FormatCalibration(c));
}

}  // namespace monocle
