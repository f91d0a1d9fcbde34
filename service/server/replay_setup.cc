#include "service/server/replay_setup.h"

#include <google/protobuf/text_format.h>

#include <cctype>
#include <filesystem>

#include "idl/service_config.pb.h"
#include "service/io/calibration_file.h"

namespace monocle {
namespace {

Result<proto::CameraRole> RoleOf(const RecordedCamera& cam, const CameraCalibration& calibration) {
  if (cam.role == "corner") return proto::CORNER;
  if (cam.role == "floor") return proto::FLOOR;
  if (cam.role == "corner+floor") return proto::CORNER_AND_FLOOR;
  if (!cam.role.empty()) {
    return MakeError(ErrorCode::kInvalidArgument,
                     "camera '" + cam.id + "' has the unknown role '" + cam.role + "'");
  }
  // No /monocle/cameras sample recorded: what its calibration can serve.
  if (calibration.floor && calibration.ceiling_distance_m) return proto::CORNER_AND_FLOOR;
  return calibration.floor ? proto::FLOOR : proto::CORNER;
}

}  // namespace

Result<ServiceSetup> ReplaySetup(const std::string& mcap_path, const std::string& state_dir,
                                 ReplayPace pace) {
  auto cameras = ListRecordedCameras(mcap_path);
  if (!cameras) return cameras.error();
  if (cameras->empty()) {
    return MakeError(ErrorCode::kNotFound,
                     mcap_path +
                         " has no camera frames to replay (record with --frames every "
                         "or N; `monocle info` lists what it has)");
  }
  const std::filesystem::path dir = std::filesystem::absolute(state_dir) / "replay";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    return MakeError(ErrorCode::kIo, "cannot create " + dir.string() +
                                         " for the replay's calibrations: " + ec.message());
  }
  proto::ServiceConfig config;
  for (const auto& cam : *cameras) {
    if (cam.calibration_text.empty()) {
      return MakeError(ErrorCode::kNotFound,
                       mcap_path + ": camera '" + cam.id + "' (" + cam.ros_namespace +
                           ") has frames but no calibration in the recording (/monocle/"
                           "calibrations was not recorded)");
    }
    const std::string source = mcap_path + " (" + cam.id + "'s recorded calibration)";
    auto calibration = ParseCalibration(cam.calibration_text, source);
    if (!calibration) return calibration.error();
    auto role = RoleOf(cam, *calibration);
    if (!role) return role.error();
    // The file name is ours, not the recording's: an id is only ever a file name's stem
    // after everything but letters, digits, '-' and '_' became '_'.
    std::string stem;
    for (const char ch : cam.id)
      stem += std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' ? ch : '_';
    const auto path = (dir / (stem + ".pbtxt")).string();
    if (Status s = WriteFileAtomically(path, cam.calibration_text); !s) return s.error();
    auto* c = config.add_camera();
    c->set_id(cam.id);
    c->set_device("replay");
    c->set_role(*role);
    c->set_calibration(path);
    c->set_ros_namespace(cam.ros_namespace);
    if (cam.ceiling_distance_m) c->set_ceiling_distance_m(*cam.ceiling_distance_m);
  }
  std::string text;
  google::protobuf::TextFormat::PrintToString(config, &text);
  auto setup = ParseServiceConfig(text, mcap_path + " (replay)", state_dir);
  if (!setup) return setup.error();
  for (size_t i = 0; i < setup->cameras.size(); ++i) {
    setup->cameras[i].options.device = "replay of " + mcap_path;
    setup->cameras[i].replay = CameraSetup::Replay{mcap_path, (*cameras)[i].ros_namespace, pace};
  }
  return setup;
}

}  // namespace monocle
