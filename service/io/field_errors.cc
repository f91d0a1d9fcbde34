#include "service/io/field_errors.h"

#include <algorithm>

namespace monocle {

int FieldErrors::Line(std::initializer_list<PathStep> path, std::string* name) const {
  const google::protobuf::TextFormat::ParseInfoTree* tree = &tree_;
  const google::protobuf::Descriptor* message = root_;
  int line = -1;
  for (const PathStep& step : path) {
    *name += (name->empty() ? "" : ".") + std::string(step.field) +
             (step.index >= 0 ? "[" + std::to_string(step.index) + "]" : "");
    const auto* field = message != nullptr ? message->FindFieldByName(step.field) : nullptr;
    if (tree == nullptr || field == nullptr) continue;
    const int index = field->is_repeated() ? std::max(step.index, 0) : -1;
    auto at = tree->GetLocation(field, index);
    // A list ("edge_heading_deg: [0, 90]") is recorded at its first value only.
    if (at.line < 0 && index > 0) at = tree->GetLocation(field, 0);
    if (at.line >= 0) line = at.line;
    tree = field->message_type() != nullptr ? tree->GetTreeForNested(field, index) : nullptr;
    message = field->message_type();
  }
  return line;
}

Error FieldErrors::At(std::initializer_list<PathStep> path, const std::string& why) const {
  std::string name;
  const int line = Line(path, &name);
  return MakeError(
      ErrorCode::kInvalidArgument,
      source_ + (line >= 0 ? ": line " + std::to_string(line + 1) : "") + ": " + name + " " + why);
}

Error FieldErrors::At(std::initializer_list<PathStep> path, const std::string& why,
                      std::initializer_list<PathStep> line_of) const {
  std::string name, unused;
  Line(path, &name);
  const int line = Line(line_of, &unused);
  return MakeError(
      ErrorCode::kInvalidArgument,
      source_ + (line >= 0 ? ": line " + std::to_string(line + 1) : "") + ": " + name + " " + why);
}

}  // namespace monocle
