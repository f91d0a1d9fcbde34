// Text-format protobuf parsing that rejects unknown fields and says where the first error is.
#pragma once

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/message.h>
#include <google/protobuf/text_format.h>

#include <string>

#include "service/common/result.h"

namespace monocle {

// Parses `text` into `msg`. On failure the message names `source`, the line and the column
// (counted from 1), e.g. "cfg.pbtxt: line 3, column 5: Message type ... has no field ...".
// `locations`, if given, receives where each field was written (for later field errors).
inline Status ParseTextProto(const std::string& text, const std::string& source,
                             google::protobuf::Message* msg,
                             google::protobuf::TextFormat::ParseInfoTree* locations = nullptr) {
  class CollectFirstError : public google::protobuf::io::ErrorCollector {
   public:
    void AddError(int line, google::protobuf::io::ColumnNumber column,
                  const std::string& message) override {
      if (text.empty()) {  // the parser counts from 0
        text = "line " + std::to_string(line + 1) + ", column " + std::to_string(column + 1) +
               ": " + message;
      }
    }
    void AddWarning(int, google::protobuf::io::ColumnNumber, const std::string&) override {}
    std::string text;
  };
  google::protobuf::TextFormat::Parser parser;
  CollectFirstError errors;
  parser.RecordErrorsTo(&errors);
  if (locations != nullptr) parser.WriteLocationsTo(locations);
  if (!parser.ParseFromString(text, msg)) {
    return MakeError(ErrorCode::kInvalidArgument, source + ": " + errors.text);
  }
  return Ok{};
}

}  // namespace monocle
