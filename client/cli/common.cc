#include <filesystem>
#include <iostream>

#include "client/cli/commands.h"
#include "client/cli/proto_json.h"
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

std::string ToJson(const google::protobuf::Message& message) { return ProtoToJson(message); }

}  // namespace monocle::cli
