// Sub-commands of the `monocle` tool. Each returns the process exit status:
// 0 success, 1 a measurement or input failed (reported on stderr or in the JSON),
// 2 the command line itself is wrong.
#pragma once

#include <google/protobuf/message.h>

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "service/common/result.h"

namespace monocle::cli {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

int FloorCommand(const std::vector<std::string>& args);
int CornerCommand(const std::vector<std::string>& args);
// corner fit-mount (mount_fit_command.cc).
int FitMountCommand(const std::vector<std::string>& args);
// cameras, snapshot, simcam
int CameraCommand(const std::string& command, const std::vector<std::string>& args);
// simcam (simcam_command.cc).
int SimcamCommand(const std::vector<std::string>& args);
int IntrinsicsCommand(const std::vector<std::string>& args);
int IntrinsicsImportCommand(const std::vector<std::string>& args);
int IntrinsicsExportCommand(const std::vector<std::string>& args);
int RenderCommand(const std::vector<std::string>& args);
int RenderBoards(const std::vector<std::string>& args);  // render boards
int RenderRoom(const std::vector<std::string>& args);    // render room
// The running service's cameras (over DDS).
int StatusCommand(const std::vector<std::string>& args);
// MCAP recordings: record (over DDS), info.
int RecordCommand(const std::vector<std::string>& args);
int InfoCommand(const std::vector<std::string>& args);
// A recording's frames through the corner pipeline again (replay_command.cc).
int ReplayCommand(const std::vector<std::string>& args);
// The live frame with the service's measurement drawn on it (view_command.cc).
int ViewCommand(const std::vector<std::string>& args);
// Room maps: check, draw (map_commands.cc).
int MapCommand(const std::vector<std::string>& args);
// DDS Security keystores (security init).
int SecurityCommand(const std::vector<std::string>& args);

// Prints "monocle: error: <message>" on stderr and returns `status`.
int Fail(const std::string& message, int status);
int Fail(const Error& error, int status);

// Reads an image as 8-bit grey, with a clear error if the file is missing or unreadable.
Result<cv::Mat> ReadGreyImage(const std::string& path);

// Writes an image in the format its extension names, with a clear error.
Status WriteImage(const std::string& path, const cv::Mat& image);

// One-line JSON of a protobuf message, keys as in the .proto.
std::string ToJson(const google::protobuf::Message& message);

}  // namespace monocle::cli
