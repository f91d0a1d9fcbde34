// Errors in a text-protobuf file that name the file, the line and the field: "cfg.pbtxt:
// line 7: camera[1].role must be ...". One for every file users write (configuration, room
// map, mount).
#pragma once

#include <google/protobuf/descriptor.h>
#include <google/protobuf/text_format.h>

#include <initializer_list>
#include <string>

#include "service/common/result.h"

namespace monocle {

// One step of a field path: a field of the message, and the index for repeated ones.
struct PathStep {
  const char* field;
  int index = -1;
};

// "source: line N: room[0].corner[1].position why", the line of the deepest step the parser
// recorded (a missing field takes its parent's line).
class FieldErrors {
 public:
  FieldErrors(std::string source, const google::protobuf::TextFormat::ParseInfoTree& tree,
              const google::protobuf::Descriptor* root)
      : source_(std::move(source)), tree_(tree), root_(root) {}

  Error At(std::initializer_list<PathStep> path, const std::string& why) const;
  // Names `path` but gives the line of `line_of` where the parser recorded it (a field the
  // value came from, when `path` itself is missing or derived).
  Error At(std::initializer_list<PathStep> path, const std::string& why,
           std::initializer_list<PathStep> line_of) const;

 private:
  // The deepest recorded line along `path` (-1: none), and the path's name.
  int Line(std::initializer_list<PathStep> path, std::string* name) const;

  std::string source_;
  const google::protobuf::TextFormat::ParseInfoTree& tree_;
  const google::protobuf::Descriptor* root_;
};

}  // namespace monocle
