// Keeps the ROS interface package idl/ros/monocle_msgs/ (what a ROS 2 user builds) in step
// with idl/ros/monocle_msgs.idl (what monocled and the client library compile): the same
// messages and services, the same fields in the same order with the same wire types, and one
// ROS constant per IDL enumerator. No type information travels between ROS 2 and Cyclone DDS,
// so a field out of step would silently garble every sample.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
const fs::path kRosDir = fs::path(MONOCLE_SOURCE_DIR) / "idl" / "ros";

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Field {
  std::string type, name;  // in ROS spelling: float64[25], std_msgs/Header, uint32, ...
  bool operator==(const Field&) const = default;
};

struct Interface {
  std::vector<Field> fields;
  std::map<std::string, std::string> constants;  // NAME -> "uint32 value"
};

struct IdlTypes {
  std::map<std::string, std::vector<std::string>> enums;        // enum name -> enumerators
  std::map<std::string, std::vector<Field>> structs;            // e.g. "msg/CornerPose_"
  std::map<std::string, std::vector<std::string>> enum_fields;  // struct -> enum types used
};

std::string StripComments(const std::string& text, const std::string& marker) {
  std::stringstream in(text), out;
  for (std::string line; std::getline(in, line);) out << line.substr(0, line.find(marker)) << "\n";
  return out.str();
}

// An IDL type as ROS writes it; enum types become uint32 (their XCDR1 encoding).
std::string RosType(std::string idl, const IdlTypes& types, std::vector<std::string>* enums_used) {
  static const std::map<std::string, std::string> kPrimitive = {
      {"double", "float64"},  {"float", "float32"},        {"unsigned long long", "uint64"},
      {"long long", "int64"}, {"unsigned long", "uint32"}, {"long", "int32"},
      {"boolean", "bool"},    {"string", "string"},        {"octet", "uint8"}};
  if (auto it = kPrimitive.find(idl); it != kPrimitive.end()) return it->second;
  const std::smatch m = [&] {
    std::smatch match;
    std::regex_match(idl, match, std::regex(R"((\w+)::(msg|srv)::dds_::(\w+?)_?)"));
    return match;
  }();
  if (m.empty()) return "?" + idl;
  const std::string pkg = m[1], name = m[3];
  if (pkg == "monocle_msgs" && types.enums.count(name) != 0) {
    enums_used->push_back(name);
    return "uint32";
  }
  return pkg == "monocle_msgs" ? name : pkg + "/" + name;
}

IdlTypes ParseIdl(const std::string& raw) {
  IdlTypes out;
  const std::string text = StripComments(raw, "//");
  const std::regex enum_re(R"(enum\s+(\w+)\s*\{([^}]*)\})");
  for (std::sregex_iterator it(text.begin(), text.end(), enum_re), end; it != end; ++it) {
    std::vector<std::string> names;
    const std::string body = (*it)[2];
    const std::regex word(R"(\w+)");
    for (std::sregex_iterator w(body.begin(), body.end(), word); w != end; ++w)
      names.push_back(w->str());
    out.enums[(*it)[1]] = names;
  }
  const size_t srv_start = text.find("module srv");
  const std::regex struct_re(R"(struct\s+(\w+)\s*\{([^}]*)\})");
  const std::regex member_re(R"(^\s*(sequence<\s*([^>]+?)\s*>|[\w: ]+?)\s+(\w+)(\[(\d+)\])?\s*;)");
  for (std::sregex_iterator it(text.begin(), text.end(), struct_re), end; it != end; ++it) {
    const bool srv = static_cast<size_t>(it->position()) > srv_start;
    const std::string key = std::string(srv ? "srv/" : "msg/") + (*it)[1].str();
    std::vector<Field> fields;
    std::vector<std::string> enums_used;
    std::stringstream body((*it)[2]);
    for (std::string line; std::getline(body, line);) {
      std::smatch m;
      if (!std::regex_search(line, m, member_re)) continue;
      std::string type =
          m[2].matched ? RosType(m[2], out, &enums_used) + "[]" : RosType(m[1], out, &enums_used);
      if (m[5].matched) type += "[" + m[5].str() + "]";
      fields.push_back({type, m[3]});
    }
    out.structs[key] = fields;
    out.enum_fields[key] = enums_used;
  }
  return out;
}

// One .msg, or one half of a .srv.
Interface ParseRos(const std::string& raw) {
  Interface out;
  const std::regex constant_re(R"(^\s*(\w+)\s+(\w+)\s*=\s*(\S+)\s*$)");
  const std::regex field_re(R"(^\s*([\w/]+(\[\d*\])?)\s+(\w+)\s*$)");
  std::stringstream in(StripComments(raw, "#"));
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (std::regex_match(line, m, constant_re)) {
      out.constants[m[2]] = m[1].str() + " " + m[3].str();
    } else if (std::regex_match(line, m, field_re)) {
      out.fields.push_back({m[1], m[3]});
    }
  }
  return out;
}

// Every difference between an IDL struct and its ROS counterpart, in words.
std::vector<std::string> Compare(const std::string& what, const std::vector<Field>& idl,
                                 const std::vector<std::string>& enums_used, const Interface& ros,
                                 const IdlTypes& types) {
  std::vector<std::string> diffs;
  for (size_t i = 0; i < std::max(idl.size(), ros.fields.size()); ++i) {
    const std::string a = i < idl.size() ? idl[i].type + " " + idl[i].name : "(nothing)";
    const std::string b =
        i < ros.fields.size() ? ros.fields[i].type + " " + ros.fields[i].name : "(nothing)";
    if (a != b) diffs.push_back(what + " field " + std::to_string(i) + ": IDL " + a + ", ROS " + b);
  }
  for (const auto& e : enums_used) {
    const auto& names = types.enums.at(e);
    for (size_t v = 0; v < names.size(); ++v) {
      const auto it = ros.constants.find(names[v]);
      const std::string want = "uint32 " + std::to_string(v);
      if (it == ros.constants.end() || it->second != want)
        diffs.push_back(what + ": needs the constant " + names[v] + "=" + std::to_string(v) +
                        " (uint32) for enum " + e);
    }
  }
  return diffs;
}

// The leading rmw_cyclonedds request header, which .srv files do not show.
std::vector<Field> WithoutHeader(const std::string& what, std::vector<Field> fields,
                                 std::vector<std::string>* diffs) {
  const std::vector<Field> header = {{"uint64", "guid"}, {"int64", "seq"}};
  if (fields.size() < 2 || !std::equal(header.begin(), header.end(), fields.begin())) {
    diffs->push_back(what + ": must begin with uint64 guid; int64 seq (rmw_cyclonedds)");
    return fields;
  }
  return {fields.begin() + 2, fields.end()};
}

std::vector<std::string> CheckPackage(const std::string& idl_text, const fs::path& package) {
  const IdlTypes types = ParseIdl(idl_text);
  std::vector<std::string> diffs;
  const std::string cmake = ReadFile(package / "CMakeLists.txt");
  size_t interfaces = 0;
  for (const auto& [key, fields] : types.structs) {
    const bool srv = key.rfind("srv/", 0) == 0;
    std::string name = key.substr(4);
    name.pop_back();  // the trailing '_'
    if (!srv) {
      const fs::path file = package / "msg" / (name + ".msg");
      if (!fs::exists(file)) {
        diffs.push_back("no " + file.string() + " for IDL " + key);
        continue;
      }
      ++interfaces;
      if (cmake.find("\"msg/" + name + ".msg\"") == std::string::npos)
        diffs.push_back("msg/" + name + ".msg is not in CMakeLists.txt");
      auto d = Compare(name + ".msg", fields, types.enum_fields.at(key), ParseRos(ReadFile(file)),
                       types);
      diffs.insert(diffs.end(), d.begin(), d.end());
      continue;
    }
    const bool request = name.size() > 8 && name.substr(name.size() - 8) == "_Request";
    const std::string svc = name.substr(0, name.rfind('_'));
    const fs::path file = package / "srv" / (svc + ".srv");
    if (!fs::exists(file)) {
      diffs.push_back("no " + file.string() + " for IDL " + key);
      continue;
    }
    const std::string text = ReadFile(file);
    const size_t split = text.find("\n---");
    if (split == std::string::npos) {
      diffs.push_back(file.string() + " has no --- between request and response");
      continue;
    }
    if (request) {
      ++interfaces;
      if (cmake.find("\"srv/" + svc + ".srv\"") == std::string::npos)
        diffs.push_back("srv/" + svc + ".srv is not in CMakeLists.txt");
    }
    const std::string half = request ? text.substr(0, split) : text.substr(split + 4);
    const std::string what = svc + ".srv " + (request ? "request" : "response");
    auto d = Compare(what, WithoutHeader(what, fields, &diffs), types.enum_fields.at(key),
                     ParseRos(half), types);
    diffs.insert(diffs.end(), d.begin(), d.end());
  }
  // Files of the package without an IDL counterpart.
  size_t files = 0;
  for (const char* dir : {"msg", "srv"}) {
    for (const auto& f : fs::directory_iterator(package / dir)) files += f.is_regular_file();
  }
  if (files != interfaces)
    diffs.push_back(std::to_string(files) + " files in msg/ and srv/, " +
                    std::to_string(interfaces) + " interfaces in the IDL");
  return diffs;
}

TEST(MonocleMsgsInStep, PackageDescribesTheIdl) {
  const auto diffs = CheckPackage(ReadFile(kRosDir / "monocle_msgs.idl"), kRosDir / "monocle_msgs");
  for (const auto& d : diffs) ADD_FAILURE() << d;
  // The checker saw what it checks: 5 messages and 3 services with their fields.
  const IdlTypes types = ParseIdl(ReadFile(kRosDir / "monocle_msgs.idl"));
  EXPECT_EQ(types.structs.size(), 11u);
  EXPECT_EQ(types.structs.at("msg/CornerPose_").size(), 34u);
  EXPECT_EQ(types.enums.at("MapStatus").size(), 5u);
  EXPECT_EQ(types.structs.at("srv/MeasurePoints_Response_").size(), 15u);
  EXPECT_EQ(types.enums.at("CameraState").size(), 4u);
}

TEST(MonocleMsgsInStep, CatchesAFieldOutOfStep) {
  std::string idl = ReadFile(kRosDir / "monocle_msgs.idl");
  // Swap two fields of the same type: names out of order.
  const std::string pan = "  double pan;", tilt = "  double tilt;";
  const size_t a = idl.find(pan), b = idl.find(tilt);
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  idl.replace(b, tilt.size(), pan);
  idl.replace(a, pan.size(), tilt);
  auto diffs = CheckPackage(idl, kRosDir / "monocle_msgs");
  ASSERT_FALSE(diffs.empty());
  EXPECT_NE(diffs[0].find("CornerPose.msg field 7"), std::string::npos) << diffs[0];

  // A wider type: 8 bytes on the wire instead of 4.
  idl = ReadFile(kRosDir / "monocle_msgs.idl");
  const std::string corners = "  unsigned long corners;";
  idl.replace(idl.find(corners), corners.size(), "  unsigned long long corners;");
  diffs = CheckPackage(idl, kRosDir / "monocle_msgs");
  ASSERT_EQ(diffs.size(), 1u);
  EXPECT_NE(diffs[0].find("uint64 corners"), std::string::npos) << diffs[0];

  // A new enumerator without its ROS constant.
  idl = ReadFile(kRosDir / "monocle_msgs.idl");
  const std::string states = "CAMERA_FAILED }";
  idl.replace(idl.find(states), states.size(), "CAMERA_FAILED, CAMERA_UNPLUGGED }");
  diffs = CheckPackage(idl, kRosDir / "monocle_msgs");
  ASSERT_EQ(diffs.size(), 1u);
  EXPECT_NE(diffs[0].find("CAMERA_UNPLUGGED=4"), std::string::npos) << diffs[0];
}

TEST(MonocleMsgsInStep, ServiceSamplesBeginWithTheRequestHeader) {
  std::string idl = ReadFile(kRosDir / "monocle_msgs.idl");
  const std::string seq = "  long long seq;\n  monocle_msgs::msg::dds_::PoseWhich which;";
  const size_t at = idl.find(seq);
  ASSERT_NE(at, std::string::npos);
  idl.replace(at, seq.size(), "  monocle_msgs::msg::dds_::PoseWhich which;");
  const auto diffs = CheckPackage(idl, kRosDir / "monocle_msgs");
  ASSERT_FALSE(diffs.empty());
  EXPECT_NE(diffs[0].find("GetPose.srv request: must begin with"), std::string::npos) << diffs[0];
}

}  // namespace
