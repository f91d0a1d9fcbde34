// One line of JSON for a protobuf message, exactly as protobuf's MessageToJsonString prints
// it with always_print_primitive_fields and preserve_proto_field_names (the tests compare
// the two byte for byte), but written directly from the message by reflection:
// MessageToJsonString serializes the message and parses it again through a type resolver,
// and with its number formatting that was 6 % of `monocle corner locate --json`'s time per
// frame. Messages outside what is written here (maps, well-known types, strings that are not
// UTF-8) are handed to MessageToJsonString itself.
#pragma once

#include <google/protobuf/message.h>

#include <string>

namespace monocle::cli {

std::string ProtoToJson(const google::protobuf::Message& message);

}  // namespace monocle::cli
