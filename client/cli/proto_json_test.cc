// ProtoToJson against protobuf's own MessageToJsonString, byte for byte, on messages of
// every type monocle prints or stores, filled at random: unset and set optional fields,
// empty and full repeated ones, doubles from tiny to huge, NaN and infinities, the largest
// 64-bit integers, and strings with every character protobuf escapes.
#include "client/cli/proto_json.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <limits>
#include <memory>
#include <random>
#include <string>

#include "idl/calibration.pb.h"
#include "idl/cli_output.pb.h"
#include "idl/room_map.pb.h"
#include "idl/service_config.pb.h"

namespace monocle::cli {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

std::string Theirs(const Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  std::string out;
  EXPECT_TRUE(google::protobuf::util::MessageToJsonString(message, &out, options).ok());
  return out;
}

void AppendUtf8(uint32_t code, std::string* out) {
  if (code < 0x80) {
    out->push_back(static_cast<char>(code));
  } else if (code < 0x800) {
    out->push_back(static_cast<char>(0xC0 | code >> 6));
    out->push_back(static_cast<char>(0x80 | (code & 0x3F)));
  } else if (code < 0x10000) {
    out->push_back(static_cast<char>(0xE0 | code >> 12));
    out->push_back(static_cast<char>(0x80 | (code >> 6 & 0x3F)));
    out->push_back(static_cast<char>(0x80 | (code & 0x3F)));
  } else {
    out->push_back(static_cast<char>(0xF0 | code >> 18));
    out->push_back(static_cast<char>(0x80 | (code >> 12 & 0x3F)));
    out->push_back(static_cast<char>(0x80 | (code >> 6 & 0x3F)));
    out->push_back(static_cast<char>(0x80 | (code & 0x3F)));
  }
}

class Filler {
 public:
  explicit Filler(uint64_t seed) : rng_(seed) {}

  double Double() {
    switch (Pick(8)) {
      case 0:
        return 0.0;
      case 1:
        return -0.0;
      case 2:
        return std::numeric_limits<double>::quiet_NaN();
      case 3:
        return Pick(2) ? std::numeric_limits<double>::infinity()
                       : -std::numeric_limits<double>::infinity();
      case 4:
        return std::ldexp(Uniform(), static_cast<int>(Pick(2100)) - 1050);  // any size
      case 5:
        return static_cast<double>(Pick(100000)) / 1000;  // short decimals: %.15g
      case 6:
        return std::numeric_limits<double>::denorm_min() * static_cast<double>(Pick(1000));
      default:
        return (Uniform() - 0.5) * std::pow(10.0, static_cast<double>(Pick(12)) - 6);
    }
  }

  std::string Text() {
    // Around every code point protobuf escapes beyond ASCII.
    static constexpr uint32_t kNear[] = {
        0x9F,    0xA0,    0xAD,    0x5FF,   0x603,   0x604,   0x6DD,   0x70F,  0x17B4,
        0x17B5,  0x200A,  0x200B,  0x200F,  0x2027,  0x2028,  0x202E,  0x202F, 0x2060,
        0x2064,  0x206A,  0x206F,  0xFEFF,  0xFFF8,  0xFFF9,  0xFFFB,  0xFFFC, 0x1D172,
        0x1D173, 0x1D17A, 0x1D17B, 0xE0001, 0xE001F, 0xE0020, 0xE007F, 0xE0080};
    std::string s;
    const int length = static_cast<int>(Pick(12));
    for (int i = 0; i < length; ++i) {
      switch (Pick(5)) {
        case 0:
          AppendUtf8(static_cast<uint32_t>(Pick(0x80)), &s);
          break;  // ASCII, controls
        case 1:
          AppendUtf8(kNear[Pick(std::size(kNear))], &s);
          break;
        case 2:
          AppendUtf8(0x80 + static_cast<uint32_t>(Pick(0x780)), &s);
          break;
        case 3: {
          uint32_t code = static_cast<uint32_t>(Pick(0x10FFFF));
          if (code >= 0xD800 && code <= 0xDFFF) code = 0xFFFD;
          AppendUtf8(code, &s);
          break;
        }
        default:
          s += "a/_.-"[Pick(5)];
      }
    }
    return s;
  }

  void Fill(Message* message, int depth) {
    const Descriptor* descriptor = message->GetDescriptor();
    const auto* r = message->GetReflection();
    for (int i = 0; i < descriptor->field_count(); ++i) {
      const FieldDescriptor* field = descriptor->field(i);
      if (Pick(3) == 0) continue;  // left unset
      const int count = field->is_repeated() ? static_cast<int>(Pick(4)) : 1;
      for (int k = 0; k < count; ++k) {
        switch (field->cpp_type()) {
          case FieldDescriptor::CPPTYPE_INT32: {
            const int32_t v = static_cast<int32_t>(rng_());
            field->is_repeated() ? r->AddInt32(message, field, v) : r->SetInt32(message, field, v);
            break;
          }
          case FieldDescriptor::CPPTYPE_UINT32: {
            const uint32_t v = Pick(2) ? static_cast<uint32_t>(rng_()) : 4294967295u;
            field->is_repeated() ? r->AddUInt32(message, field, v)
                                 : r->SetUInt32(message, field, v);
            break;
          }
          case FieldDescriptor::CPPTYPE_INT64: {
            const int64_t v = Pick(2) ? static_cast<int64_t>(rng_()) : INT64_MIN;
            field->is_repeated() ? r->AddInt64(message, field, v) : r->SetInt64(message, field, v);
            break;
          }
          case FieldDescriptor::CPPTYPE_UINT64: {
            const uint64_t v = Pick(2) ? rng_() : UINT64_MAX;
            field->is_repeated() ? r->AddUInt64(message, field, v)
                                 : r->SetUInt64(message, field, v);
            break;
          }
          case FieldDescriptor::CPPTYPE_DOUBLE: {
            const double v = Double();
            field->is_repeated() ? r->AddDouble(message, field, v)
                                 : r->SetDouble(message, field, v);
            break;
          }
          case FieldDescriptor::CPPTYPE_FLOAT: {
            const float v = static_cast<float>(Double());
            field->is_repeated() ? r->AddFloat(message, field, v) : r->SetFloat(message, field, v);
            break;
          }
          case FieldDescriptor::CPPTYPE_BOOL: {
            const bool v = Pick(2) == 1;
            field->is_repeated() ? r->AddBool(message, field, v) : r->SetBool(message, field, v);
            break;
          }
          case FieldDescriptor::CPPTYPE_ENUM: {
            const auto* e = field->enum_type()->value(
                static_cast<int>(Pick(field->enum_type()->value_count())));
            field->is_repeated() ? r->AddEnum(message, field, e) : r->SetEnum(message, field, e);
            break;
          }
          case FieldDescriptor::CPPTYPE_STRING: {
            const std::string v = Text();
            field->is_repeated() ? r->AddString(message, field, v)
                                 : r->SetString(message, field, v);
            break;
          }
          case FieldDescriptor::CPPTYPE_MESSAGE:
            if (depth < 3)
              Fill(field->is_repeated() ? r->AddMessage(message, field)
                                        : r->MutableMessage(message, field),
                   depth + 1);
            break;
        }
      }
    }
  }

 private:
  uint64_t Pick(uint64_t n) { return rng_() % n; }
  double Uniform() { return std::uniform_real_distribution<double>(0, 1)(rng_); }
  std::mt19937_64 rng_;
};

TEST(ProtoJsonTest, PrintsEveryMessageTypeAsProtobufDoes) {
  // Every message type in the files monocle prints or stores.
  std::vector<const Descriptor*> types;
  for (const auto* file :
       {proto::CornerOutput::descriptor()->file(), proto::Calibration::descriptor()->file(),
        proto::RoomMap::descriptor()->file(), proto::ServiceConfig::descriptor()->file()}) {
    for (int i = 0; i < file->message_type_count(); ++i) types.push_back(file->message_type(i));
  }
  ASSERT_GT(types.size(), 20u);
  auto* factory = google::protobuf::MessageFactory::generated_factory();
  Filler filler(20261125);
  int compared = 0;
  for (const Descriptor* type : types) {
    for (int round = 0; round < 300; ++round) {
      std::unique_ptr<Message> message(factory->GetPrototype(type)->New());
      if (round > 0) filler.Fill(message.get(), 0);  // round 0: every field unset
      ASSERT_EQ(ProtoToJson(*message), Theirs(*message))
          << type->full_name() << " round " << round << "\n"
          << message->DebugString();
      ++compared;
    }
  }
  EXPECT_EQ(compared, 300 * static_cast<int>(types.size()));
}

// A string that is not UTF-8 (a file name can be anything) goes to protobuf's printer, which
// drops what it cannot encode; the output is still protobuf's.
TEST(ProtoJsonTest, TextThatIsNotUtf8IsPrintedByProtobuf) {
  proto::CornerOutput out;
  out.set_image("frame\xff\xc3.pgm");
  out.set_x(1.5);
  const std::string json = ProtoToJson(out);
  EXPECT_EQ(json, Theirs(out));
  EXPECT_NE(json.find("\"x\":1.5"), std::string::npos) << json;
}

}  // namespace
}  // namespace monocle::cli
