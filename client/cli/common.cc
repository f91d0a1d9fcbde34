#include <google/protobuf/util/json_util.h>

#include <filesystem>
#include <iostream>

#include "client/cli/commands.h"
#include "service/io/image_codec.h"
#include "service/io/image_file.h"

namespace monocle::cli {

int Fail(const std::string& message, int status) {
  std::cerr << "monocle: error: " << message << "\n";
  return status;
}

int Fail(const Error& error, int status) { return Fail(error.message, status); }

Result<cv::Mat> ReadGreyImage(const std::string& path) { return ReadGreyImageFile(path); }

Status WriteImage(const std::string& path, const cv::Mat& image) {
  return WriteImageFile(path, image);
}

std::string ToJson(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  std::string out;
  const auto status = google::protobuf::util::MessageToJsonString(message, &out, options);
  (void)status;  // cannot fail for our own messages
  return out;
}

bool WantsHelp(const std::vector<std::string>& args) {
  for (const auto& a : args) {
    if (a == "--help" || a == "-h") return true;
  }
  return false;
}

}  // namespace monocle::cli
