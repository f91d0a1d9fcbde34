#include "service/io/field_errors.h"

#include <gtest/gtest.h>

#include "idl/service_config.pb.h"

namespace monocle {
namespace {

using google::protobuf::TextFormat;

constexpr const char* kConfig = R"(domain: 3
camera {
  id: "a"
  device: "sim-floor"
}
camera {
  id: "b"
  device: "x"
  mount {
    base_frame: "base_link"
    translation_m: [0, 0, 1]
  }
}
)";

class FieldErrorsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    TextFormat::Parser parser;
    parser.WriteLocationsTo(&tree_);
    ASSERT_TRUE(parser.ParseFromString(kConfig, &config_));
  }
  proto::ServiceConfig config_;
  TextFormat::ParseInfoTree tree_;
};

TEST_F(FieldErrorsTest, NamesTheFileTheLineAndTheFieldPath) {
  const FieldErrors errors("cfg.pbtxt", tree_, proto::ServiceConfig::descriptor());
  EXPECT_EQ(errors.At({{"domain"}}, "must be 0..232").message,
            "cfg.pbtxt: line 1: domain must be 0..232");
  EXPECT_EQ(errors.At({{"camera", 1}, {"device"}}, "is unknown").message,
            "cfg.pbtxt: line 8: camera[1].device is unknown");
  EXPECT_EQ(errors.At({{"camera", 1}, {"mount"}, {"translation_m", 2}}, "is too high").message,
            "cfg.pbtxt: line 11: camera[1].mount.translation_m[2] is too high");
}

// A missing field takes the line of the nearest parent that is there.
TEST_F(FieldErrorsTest, AMissingFieldTakesItsParentsLine) {
  const FieldErrors errors("cfg.pbtxt", tree_, proto::ServiceConfig::descriptor());
  EXPECT_EQ(errors.At({{"camera", 0}, {"role"}}, "is missing").message,
            "cfg.pbtxt: line 2: camera[0].role is missing");
  EXPECT_EQ(errors.At({{"status_period_s"}}, "is missing").message,
            "cfg.pbtxt: status_period_s is missing");
}

// An error may name one field and point at the line of another it came from.
TEST_F(FieldErrorsTest, TheLineMayBeAnotherFields) {
  const FieldErrors errors("cfg.pbtxt", tree_, proto::ServiceConfig::descriptor());
  EXPECT_EQ(
      errors.At({{"camera", 1}, {"mount.rotation_xyzw"}}, "is missing", {{"camera", 1}, {"mount"}})
          .message,
      "cfg.pbtxt: line 9: camera[1].mount.rotation_xyzw is missing");
}

}  // namespace
}  // namespace monocle
