// The ros2msg schemas of recordings: every type a definition uses is defined in it exactly
// once (what Foxglove's and rosbag2's parsers need), in the MCAP registry's delimiter format.
#include "idl/record/ros2_schemas.h"

#include <gtest/gtest.h>

#include <set>
#include <sstream>

namespace monocle::record {
namespace {

// Splits a concatenated definition into (name, text) sections; the first is unnamed.
std::vector<std::pair<std::string, std::string>> Sections(const std::string& def) {
  std::vector<std::pair<std::string, std::string>> out{{"", ""}};
  std::istringstream in(def);
  std::string line;
  bool expect_name = false;
  while (std::getline(in, line)) {
    if (line == std::string(80, '=')) {
      expect_name = true;
      continue;
    }
    if (expect_name) {
      EXPECT_EQ(line.rfind("MSG: ", 0), 0u) << line;
      out.emplace_back(line.substr(5), "");
      expect_name = false;
      continue;
    }
    out.back().second += line + "\n";
  }
  return out;
}

// Field types of a section that are not primitives, qualified with `package`.
std::set<std::string> ComplexTypes(const std::string& text, const std::string& package) {
  static const std::set<std::string> kPrimitive = {"bool",  "byte",   "float64", "float32",
                                                   "int32", "uint32", "int64",   "uint64",
                                                   "uint8", "int8",   "string",  "uint16"};
  std::set<std::string> out;
  std::istringstream in(text);
  std::string type;
  std::string rest;
  while (in >> type) {
    std::getline(in, rest);
    if (type[0] == '#') continue;
    type = type.substr(0, type.find('['));
    if (kPrimitive.count(type)) continue;
    out.insert(type.find('/') == std::string::npos ? package + "/" + type : type);
  }
  return out;
}

void ExpectComplete(const std::string& top, const std::string& def) {
  const auto sections = Sections(def);
  std::set<std::string> defined;
  for (size_t i = 1; i < sections.size(); ++i) {
    EXPECT_TRUE(defined.insert(sections[i].first).second) << sections[i].first << " twice";
  }
  for (size_t i = 0; i < sections.size(); ++i) {
    const std::string package = i == 0 ? top.substr(0, top.find('/'))
                                       : sections[i].first.substr(0, sections[i].first.find('/'));
    for (const std::string& used : ComplexTypes(sections[i].second, package)) {
      EXPECT_TRUE(defined.count(used)) << top << ": " << used << " is used but not defined";
    }
  }
}

TEST(Ros2Schemas, EveryRecordedTypeIsCompleteAndSelfContained) {
  for (const char* type : {"geometry_msgs/msg/PoseWithCovarianceStamped", "sensor_msgs/msg/Image",
                           "sensor_msgs/msg/CameraInfo", "tf2_msgs/msg/TFMessage",
                           "diagnostic_msgs/msg/DiagnosticArray", "monocle_msgs/msg/CornerPose",
                           "monocle_msgs/msg/CameraStatus", "monocle_msgs/msg/Calibration"}) {
    const auto def = Ros2MsgDefinition(type);
    ASSERT_TRUE(def.has_value()) << type;
    ExpectComplete(type, *def);
  }
  const auto pose = *Ros2MsgDefinition("geometry_msgs/msg/PoseWithCovarianceStamped");
  EXPECT_EQ(pose.rfind("std_msgs/Header header\n", 0), 0u) << "the type's own text comes first";
  EXPECT_NE(pose.find("MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"),
            std::string::npos);
  EXPECT_FALSE(Ros2MsgDefinition("geometry_msgs/msg/Nothing").has_value());
}

TEST(Ros2Schemas, ServiceSamplesCarryRmwCycloneddsRequestHeader) {
  for (const char* srv : {"monocle_msgs/srv/MeasurePoints", "monocle_msgs/srv/GetPose",
                          "monocle_msgs/srv/CalibrateFloor"}) {
    for (bool request : {true, false}) {
      const auto def = Ros2ServiceSampleDefinition(srv, request);
      ASSERT_TRUE(def.has_value()) << srv;
      EXPECT_EQ(def->rfind("uint64 guid", 0), 0u) << *def;
      EXPECT_EQ(def->find("---"), std::string::npos) << "one side only";
      ExpectComplete(srv, *def);
    }
  }
  const auto reply = *Ros2ServiceSampleDefinition("monocle_msgs/srv/GetPose", false);
  EXPECT_NE(reply.find("MSG: monocle_msgs/CornerPose"), std::string::npos) << reply;
  EXPECT_NE(
      Ros2ServiceSampleDefinition("monocle_msgs/srv/MeasurePoints", true)->find("float64[] u"),
      std::string::npos);
}

}  // namespace
}  // namespace monocle::record
