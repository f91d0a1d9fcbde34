#include "client/cli/proto_json.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>
#include <system_error>
#include <vector>

namespace monocle::cli {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

// Whether this writer prints `descriptor`'s messages as protobuf does: no maps, no
// well-known types (Timestamp, Any, wrappers... print in their own forms), no groups, no
// bytes (base64).
bool Supported(const Descriptor* descriptor, int depth = 0) {
  if (depth > 32 || descriptor->file()->package() == "google.protobuf") return false;
  for (int i = 0; i < descriptor->field_count(); ++i) {
    const FieldDescriptor* field = descriptor->field(i);
    if (field->is_map() || field->type() == FieldDescriptor::TYPE_GROUP ||
        field->type() == FieldDescriptor::TYPE_BYTES)
      return false;
    if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE &&
        field->message_type() != descriptor && !Supported(field->message_type(), depth + 1))
      return false;
  }
  return true;
}

// protobuf's SimpleDtoa / SimpleFtoa: the shortest of %.15g (%.6g for a float) that reads
// back as the same value, else %.17g (%.9g). std::to_chars with a precision formats as
// printf does, in a fraction of its time.
template <typename T>
void AppendNumber(T value, std::string* out) {
  constexpr int kShort = std::numeric_limits<T>::digits10;     // 15 or 6
  constexpr int kLong = std::numeric_limits<T>::max_digits10;  // 17 or 9
  char buffer[64];
  auto printed =
      std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, kShort);
  T parsed{};
  const auto read = std::from_chars(buffer, printed.ptr, parsed);
  if (read.ec != std::errc() || parsed != value)
    printed =
        std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, kLong);
  out->append(buffer, printed.ptr);
}

template <typename T>
void AppendFloating(T value, std::string* out) {
  if (std::isnan(value)) {
    out->append("\"NaN\"");
  } else if (std::isinf(value)) {
    out->append(value > 0 ? "\"Infinity\"" : "\"-Infinity\"");
  } else {
    AppendNumber(value, out);
  }
}

// The code point of the UTF-8 sequence at text[*at] (moving past it), or -1 where the text
// is not UTF-8 (ill-formed, overlong, a surrogate or beyond U+10FFFF).
int32_t NextCodePoint(std::string_view text, size_t* at) {
  const auto byte = [&](size_t i) { return static_cast<uint8_t>(text[i]); };
  const uint8_t lead = byte(*at);
  int length = 0;
  int32_t code = 0, minimum = 0;
  if (lead < 0x80) {
    ++*at;
    return lead;
  } else if ((lead & 0xE0) == 0xC0) {
    length = 2, code = lead & 0x1F, minimum = 0x80;
  } else if ((lead & 0xF0) == 0xE0) {
    length = 3, code = lead & 0x0F, minimum = 0x800;
  } else if ((lead & 0xF8) == 0xF0) {
    length = 4, code = lead & 0x07, minimum = 0x10000;
  } else {
    return -1;
  }
  if (text.size() - *at < static_cast<size_t>(length)) return -1;
  for (int i = 1; i < length; ++i) {
    if ((byte(*at + i) & 0xC0) != 0x80) return -1;
    code = code << 6 | (byte(*at + i) & 0x3F);
  }
  if (code < minimum || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return -1;
  *at += length;
  return code;
}

bool IsUtf8(std::string_view text) {
  for (size_t at = 0; at < text.size();)
    if (NextCodePoint(text, &at) < 0) return false;
  return true;
}

// Whether protobuf writes the code point as \uXXXX: the C0 and C1 controls, DEL, '<' and '>'
// (for HTML), and the invisible format characters it escapes against JavaScript trouble
// (soft hyphen, zero-width and direction marks, the line and paragraph separators, ...).
bool EscapedAsHex(int32_t code) {
  if (code < 0xA0) return code < 0x20 || code == '<' || code == '>' || code >= 0x7F;
  switch (code) {
    case 0x00AD:
    case 0x06DD:
    case 0x070F:
    case 0x17B4:
    case 0x17B5:
    case 0xFEFF:
    case 0xFFF9:
    case 0xFFFA:
    case 0xFFFB:
    case 0xE0001:
      return true;
    default:
      return (code >= 0x0600 && code <= 0x0603) || (code >= 0x200B && code <= 0x200F) ||
             (code >= 0x2028 && code <= 0x202E) || (code >= 0x2060 && code <= 0x2064) ||
             (code >= 0x206A && code <= 0x206F) || (code >= 0x1D173 && code <= 0x1D17A) ||
             (code >= 0xE0020 && code <= 0xE007F);
  }
}

// A JSON string as protobuf escapes it: '"' and '\' and the short forms \b \t \n \f \r,
// EscapedAsHex code points as \uXXXX in lower-case hex (beyond U+FFFF as a surrogate pair),
// everything else as it is.
void AppendString(std::string_view text, std::string* out) {
  static constexpr char kHex[] = "0123456789abcdef";
  auto append_hex = [&](int32_t unit) {
    out->append("\\u");
    for (int shift = 12; shift >= 0; shift -= 4) out->push_back(kHex[(unit >> shift) & 0xF]);
  };
  out->push_back('"');
  for (size_t at = 0; at < text.size();) {
    const size_t start = at;
    const int32_t code = NextCodePoint(text, &at);
    switch (code) {
      case '"':
        out->append("\\\"");
        continue;
      case '\\':
        out->append("\\\\");
        continue;
      case '\b':
        out->append("\\b");
        continue;
      case '\t':
        out->append("\\t");
        continue;
      case '\n':
        out->append("\\n");
        continue;
      case '\f':
        out->append("\\f");
        continue;
      case '\r':
        out->append("\\r");
        continue;
      default:
        break;
    }
    if (!EscapedAsHex(code)) {
      out->append(text.substr(start, at - start));
    } else if (code < 0x10000) {
      append_hex(code);
    } else {
      append_hex(0xD800 + ((code - 0x10000) >> 10));
      append_hex(0xDC00 + ((code - 0x10000) & 0x3FF));
    }
  }
  out->push_back('"');
}

// Whether every string in `message` (and the messages in it) is UTF-8.
bool StringsAreUtf8(const Message& message) {
  const Descriptor* descriptor = message.GetDescriptor();
  const Reflection* reflection = message.GetReflection();
  std::string scratch;
  for (int i = 0; i < descriptor->field_count(); ++i) {
    const FieldDescriptor* field = descriptor->field(i);
    if (field->cpp_type() == FieldDescriptor::CPPTYPE_STRING) {
      if (field->is_repeated()) {
        for (int k = 0; k < reflection->FieldSize(message, field); ++k)
          if (!IsUtf8(reflection->GetRepeatedStringReference(message, field, k, &scratch)))
            return false;
      } else if (!IsUtf8(reflection->GetStringReference(message, field, &scratch))) {
        return false;
      }
    } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      if (field->is_repeated()) {
        for (int k = 0; k < reflection->FieldSize(message, field); ++k)
          if (!StringsAreUtf8(reflection->GetRepeatedMessage(message, field, k))) return false;
      } else if (reflection->HasField(message, field) &&
                 !StringsAreUtf8(reflection->GetMessage(message, field))) {
        return false;
      }
    }
  }
  return true;
}

void AppendMessage(const Message& message, std::string* out);

// One value of `field`: element `index` of a repeated field, or the singular value (-1).
void AppendValue(const Message& message, const FieldDescriptor* field, int index,
                 std::string* out) {
  const Reflection* r = message.GetReflection();
  const bool repeated = index >= 0;
  switch (field->cpp_type()) {
    case FieldDescriptor::CPPTYPE_INT32:
      out->append(std::to_string(repeated ? r->GetRepeatedInt32(message, field, index)
                                          : r->GetInt32(message, field)));
      return;
    case FieldDescriptor::CPPTYPE_UINT32:
      out->append(std::to_string(repeated ? r->GetRepeatedUInt32(message, field, index)
                                          : r->GetUInt32(message, field)));
      return;
    case FieldDescriptor::CPPTYPE_INT64:  // 64-bit integers are strings in protobuf's JSON
      out->append("\"" +
                  std::to_string(repeated ? r->GetRepeatedInt64(message, field, index)
                                          : r->GetInt64(message, field)) +
                  "\"");
      return;
    case FieldDescriptor::CPPTYPE_UINT64:
      out->append("\"" +
                  std::to_string(repeated ? r->GetRepeatedUInt64(message, field, index)
                                          : r->GetUInt64(message, field)) +
                  "\"");
      return;
    case FieldDescriptor::CPPTYPE_DOUBLE:
      AppendFloating(
          repeated ? r->GetRepeatedDouble(message, field, index) : r->GetDouble(message, field),
          out);
      return;
    case FieldDescriptor::CPPTYPE_FLOAT:
      AppendFloating(
          repeated ? r->GetRepeatedFloat(message, field, index) : r->GetFloat(message, field), out);
      return;
    case FieldDescriptor::CPPTYPE_BOOL:
      out->append(
          (repeated ? r->GetRepeatedBool(message, field, index) : r->GetBool(message, field))
              ? "true"
              : "false");
      return;
    case FieldDescriptor::CPPTYPE_ENUM: {
      const int number = repeated ? r->GetRepeatedEnumValue(message, field, index)
                                  : r->GetEnumValue(message, field);
      const auto* value = field->enum_type()->FindValueByNumber(number);
      if (value != nullptr) {
        AppendString(value->name(), out);
      } else {
        out->append(std::to_string(number));
      }
      return;
    }
    case FieldDescriptor::CPPTYPE_STRING: {  // UTF-8 text (Supported: no bytes)
      std::string scratch;
      AppendString(repeated ? r->GetRepeatedStringReference(message, field, index, &scratch)
                            : r->GetStringReference(message, field, &scratch),
                   out);
      return;
    }
    case FieldDescriptor::CPPTYPE_MESSAGE:
      AppendMessage(
          repeated ? r->GetRepeatedMessage(message, field, index) : r->GetMessage(message, field),
          out);
      return;
  }
}

void AppendMessage(const Message& message, std::string* out) {
  const Descriptor* descriptor = message.GetDescriptor();
  const Reflection* reflection = message.GetReflection();
  out->push_back('{');
  bool first = true;
  auto append_field = [&](const FieldDescriptor* field) {
    // Fields that track presence (messages, proto3 `optional`, oneof members) only when set;
    // the others always, defaults too (always_print_primitive_fields).
    if (!field->is_repeated() && field->has_presence() && !reflection->HasField(message, field))
      return;
    if (!first) out->push_back(',');
    first = false;
    AppendString(field->name(), out);
    out->push_back(':');
    if (!field->is_repeated()) {
      AppendValue(message, field, -1, out);
      return;
    }
    out->push_back('[');
    const int size = reflection->FieldSize(message, field);
    for (int k = 0; k < size; ++k) {
      if (k > 0) out->push_back(',');
      AppendValue(message, field, k, out);
    }
    out->push_back(']');
  };
  // protobuf's order: every field where it is declared, except the scalars in a oneof (a
  // proto3 `optional` scalar is in a oneof of its own), which follow the others in the order
  // of their numbers (its default-value writer fills in the others, then appends these as
  // they arrive from the serialized message).
  std::vector<const FieldDescriptor*> oneof_scalars;
  for (int i = 0; i < descriptor->field_count(); ++i) {
    const FieldDescriptor* field = descriptor->field(i);
    if (field->containing_oneof() != nullptr &&
        field->cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE) {
      oneof_scalars.push_back(field);
    } else {
      append_field(field);
    }
  }
  std::sort(
      oneof_scalars.begin(), oneof_scalars.end(),
      [](const FieldDescriptor* a, const FieldDescriptor* b) { return a->number() < b->number(); });
  for (const FieldDescriptor* field : oneof_scalars) append_field(field);
  out->push_back('}');
}

}  // namespace

std::string ProtoToJson(const Message& message) {
  if (!Supported(message.GetDescriptor()) || !StringsAreUtf8(message)) {
    google::protobuf::util::JsonPrintOptions options;
    options.always_print_primitive_fields = true;
    options.preserve_proto_field_names = true;
    std::string out;
    const auto status = google::protobuf::util::MessageToJsonString(message, &out, options);
    (void)status;  // cannot fail for our own messages
    return out;
  }
  std::string out;
  out.reserve(1024);
  AppendMessage(message, &out);
  return out;
}

}  // namespace monocle::cli
