// monocle corner fit-mount: the mount's level fitted from images of the ceiling corner taken
// while the robot stood on the floor (service/geometry/mount_fit.h).
#include <google/protobuf/text_format.h>

#include <unistd.h>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <sstream>

#include "client/cli/command_line.h"
#include "client/cli/commands.h"
#include "client/cli/corner_setup.h"
#include "idl/cli_output.pb.h"
#include "idl/service_config.pb.h"
#include "service/geometry/mount_fit.h"
#include "service/io/bounded_file.h"
#include "service/io/calibration_file.h"
#include "service/io/room_map_file.h"
#include "service/io/text_proto.h"
#include "service/vision/corner_locator.h"

namespace monocle::cli {
namespace {

constexpr double kDegPerRad = 180 / std::numbers::pi;

constexpr char kAbout[] =
    R"(Fits the tilt and roll of the camera's mount on the robot base from ceiling-corner images
taken while the robot stood on the floor, at several places and headings. The mount's level
(corner locate --mount, monocled's level_sigma_deg) helps a pose only as far as the mount's
rotation is right, and most at a tenth of a degree; a mount read off a drawing is rarely
better than half a degree. Each image's pose says where the base's up axis points under the
given mount; a mount error turns with the robot's heading and the floor's slope does not,
so poses facing several ways, at corners on different walls, separate the two (client/cli/GUIDE.md,
"Fitting the mount's level").)";

constexpr char kFooter[] =
    R"(Prints the correction (degrees about the base's x axis, ahead, and y axis, left), its 1σ,
and how level the floor was (1σ per axis beyond the poses' own: the least level_sigma_deg to
configure). Images without a corner, poses suspect for their edges, and poses that tip the
base more than 3.7σ from the fit are left out and named. The mount's yaw (the camera's
heading on the robot) is not the level's and is kept as given. Needs at least 5 poses; 20 or
more, at corners on different walls, are better.)";

struct FitMountArgs {
  std::vector<std::string> images;
  std::string calibration_path, mount_path;
  std::optional<std::string> out_path;
  CornerArgs corner;  // its ceiling distance
  bool json = false;
};

void DeclareFitMount(CommandLine& line, FitMountArgs* a) {
  line.Footer(kFooter);
  line.Positionals("IMAGE", &a->images, "an image of a ceiling corner, the robot on the floor");
  line.Text("--calibration", &a->calibration_path, "CAL.pbtxt",
            "the camera's intrinsics (and corner { ceiling_distance })");
  line.Require("--calibration");
  line.Text("--mount", &a->mount_path, "MOUNT.pbtxt",
            "the mount as it is configured (a CameraMount); its rotation is corrected, its "
            "translation and base_frame are kept");
  line.Require("--mount");
  DeclareCeilingDistance(line, &a->corner, "default: the calibration file's");
  line.Text("--out", &a->out_path, "NEW_MOUNT.pbtxt", "write the fitted mount there (atomically)");
  line.Flag("--json", &a->json, "one JSON object (MountFitOutput in idl/cli_output.proto)");
}

std::string Fixed(double value, int decimals) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << value;
  return s.str();
}

// The mount file's text with its rotation replaced (its other fields as they were).
Result<std::string> FittedMountText(const std::string& path, const RigidTransform& fitted,
                                    size_t poses) {
  auto text = ReadBoundedFile(path, "camera mount", kMaxTextFileBytes);
  if (!text) return text.error();
  proto::CameraMount msg;
  if (auto parsed = ParseTextProto(*text, path, &msg); !parsed) return parsed.error();
  msg.clear_rotation_xyzw();
  const Eigen::Quaterniond& q = fitted.rotation;
  for (double v : {q.x(), q.y(), q.z(), q.w()}) msg.add_rotation_xyzw(v);
  google::protobuf::TextFormat::Printer printer;
  printer.SetUseShortRepeatedPrimitives(true);
  std::string body;
  printer.PrintToString(msg, &body);
  return "# Fitted by monocle corner fit-mount from " + std::to_string(poses) + " poses (was " +
         path + ").\n" + body;
}

}  // namespace

int FitMountCommand(const std::vector<std::string>& argv) {
  FitMountArgs a;
  CommandLine line("corner fit-mount", kAbout);
  DeclareFitMount(line, &a);
  if (const auto exit_now = line.Parse(argv)) return *exit_now;
  const auto calibration = LoadCalibrationFile(a.calibration_path);
  if (!calibration) return Fail(calibration.error(), kExitFailure);
  const auto mount = LoadCameraMountFile(a.mount_path, RoomMap{});
  if (!mount) return Fail(mount.error(), kExitFailure);
  const auto zc = CeilingDistanceM(a.corner, calibration->ceiling_distance_m, a.calibration_path);
  if (!zc) return Fail(zc.error(), kExitUsage);
  CornerQualityOptions quality;
  quality.max_swing_rad = calibration->corner_max_swing_rad.value_or(quality.max_swing_rad);

  proto::MountFitOutput out;
  std::vector<MountFitPose> poses;
  std::vector<int> image_of_pose;  // index into out.images
  const bool tty = ::isatty(STDERR_FILENO) == 1;
  const auto& images = a.images;
  for (size_t i = 0; i < images.size(); ++i) {
    if (tty) std::cerr << "\rlocating " << i + 1 << "/" << images.size() << std::flush;
    auto* entry = out.add_images();
    entry->set_image(images[i]);
    const auto grey = ReadGreyImage(images[i]);
    if (!grey) {
      entry->set_left_out(grey.error().message);
      continue;
    }
    const auto located = LocateCorner(*grey, calibration->intrinsics, *zc, {}, quality);
    if (!located) {
      entry->set_left_out(located.error().message);
    } else if (located->suspect && !located->suspect_only_imprecise) {
      entry->set_left_out("suspect: " + located->suspect_reason);
    } else {
      poses.push_back({located->pose, located->covariance});
      image_of_pose.push_back(out.images_size() - 1);
    }
  }
  if (tty) std::cerr << "\r" << std::string(30, ' ') << "\r";
  out.set_poses(static_cast<uint32_t>(poses.size()));
  const auto fit = FitMountLevel(poses, *mount);
  if (!fit) {
    std::string why = fit.error().message + ": " + std::to_string(images.size()) + " images gave " +
                      std::to_string(poses.size()) + " usable poses";
    for (const auto& e : out.images())
      if (!e.left_out().empty()) why += "\n  " + e.image() + ": " + e.left_out();
    return Fail(why, kExitFailure);
  }
  for (size_t k = 0; k < fit->left_out.size(); ++k) {
    out.mutable_images(image_of_pose[fit->left_out[k]])
        ->set_left_out("tips the base " + Fixed(fit->left_out_sigmas[k], 1) +
                       " sigma from the fit (a wrong Y, or the robot not standing level)");
  }
  out.set_used(static_cast<uint32_t>(fit->used.size()));
  out.set_correction_x_deg(fit->correction_rad.x() * kDegPerRad);
  out.set_correction_y_deg(fit->correction_rad.y() * kDegPerRad);
  out.set_sigma_x_deg(std::sqrt(fit->covariance(0, 0)) * kDegPerRad);
  out.set_sigma_y_deg(std::sqrt(fit->covariance(1, 1)) * kDegPerRad);
  out.set_floor_sigma_deg(fit->floor_sigma_rad * kDegPerRad);
  const Eigen::Quaterniond& q = fit->mount.rotation;
  for (double v : {q.x(), q.y(), q.z(), q.w()}) out.add_rotation_xyzw(v);
  if (const auto& path = a.out_path) {
    const auto text = FittedMountText(a.mount_path, fit->mount, fit->used.size());
    if (!text) return Fail(text.error(), kExitFailure);
    if (auto written = WriteFileAtomically(*path, *text); !written)
      return Fail(written.error(), kExitFailure);
    out.set_written(*path);
  }

  if (a.json) {
    std::cout << ToJson(out) << std::endl;
  } else {
    std::cout << "mount fitted from " << out.used() << " of " << images.size() << " images\n";
    for (const auto& e : out.images())
      if (!e.left_out().empty())
        std::cout << "  left out " << e.image() << ": " << e.left_out() << "\n";
    std::cout << "  correction: " << Fixed(out.correction_x_deg(), 3)
              << " deg about the base's x axis"
              << " (1σ " << Fixed(out.sigma_x_deg(), 3) << "), " << Fixed(out.correction_y_deg(), 3)
              << " deg about its y axis (1σ " << Fixed(out.sigma_y_deg(), 3) << ")\n"
              << "  the robot stood level to " << Fixed(out.floor_sigma_deg(), 3)
              << " deg (1σ per axis beyond the poses' own): level_sigma_deg "
              << Fixed(std::max(out.floor_sigma_deg(), 0.05), 2) << " or more\n"
              << "  rotation_xyzw: [" << Fixed(q.x(), 9) << ", " << Fixed(q.y(), 9) << ", "
              << Fixed(q.z(), 9) << ", " << Fixed(q.w(), 9) << "]\n";
    if (!out.written().empty()) std::cout << "wrote " << out.written() << "\n";
  }
  return kExitOk;
}

}  // namespace monocle::cli
