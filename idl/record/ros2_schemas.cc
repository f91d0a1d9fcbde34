#include "idl/record/ros2_schemas.h"

#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "monocle_msgs_definitions.h"

namespace monocle::record {
namespace {

// ROS 2 Humble's standard messages that monocle publishes or that they contain (comments
// and defaults as in ROS where they matter for decoding: constants, array sizes).
const std::map<std::string, std::string>& StandardMessages() {
  static const std::map<std::string, std::string> kMessages = {
      {"builtin_interfaces/msg/Time", "int32 sec\nuint32 nanosec\n"},
      {"std_msgs/msg/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
      {"geometry_msgs/msg/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/msg/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/msg/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
      {"geometry_msgs/msg/Pose", "Point position\nQuaternion orientation\n"},
      {"geometry_msgs/msg/PoseWithCovariance", "Pose pose\nfloat64[36] covariance\n"},
      {"geometry_msgs/msg/PoseWithCovarianceStamped",
       "std_msgs/Header header\nPoseWithCovariance pose\n"},
      {"geometry_msgs/msg/Transform", "Vector3 translation\nQuaternion rotation\n"},
      {"geometry_msgs/msg/TransformStamped",
       "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"},
      {"tf2_msgs/msg/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
      {"sensor_msgs/msg/RegionOfInterest",
       "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n"},
      {"sensor_msgs/msg/CameraInfo",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\n"
       "float64[] d\nfloat64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\n"
       "uint32 binning_y\nRegionOfInterest roi\n"},
      {"sensor_msgs/msg/Image",
       "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\n"
       "uint8 is_bigendian\nuint32 step\nuint8[] data\n"},
      {"diagnostic_msgs/msg/KeyValue", "string key\nstring value\n"},
      {"diagnostic_msgs/msg/DiagnosticStatus",
       "byte OK=0\nbyte WARN=1\nbyte ERROR=2\nbyte STALE=3\nbyte level\nstring name\n"
       "string message\nstring hardware_id\nKeyValue[] values\n"},
      {"diagnostic_msgs/msg/DiagnosticArray",
       "std_msgs/Header header\nDiagnosticStatus[] status\n"},
  };
  return kMessages;
}

std::optional<std::string> Text(const std::string& type) {
  if (auto it = StandardMessages().find(type); it != StandardMessages().end()) return it->second;
  if (auto it = kMonocleMsgsFiles.find(type); it != kMonocleMsgsFiles.end()) return it->second;
  return std::nullopt;
}

const std::set<std::string>& Primitives() {
  static const std::set<std::string> kPrimitives = {
      "bool",   "byte",  "char",   "float32", "float64", "int8",   "uint8",  "int16",
      "uint16", "int32", "uint32", "int64",   "uint64",  "string", "wstring"};
  return kPrimitives;
}

// The "pkg/msg/Type" names a .msg text uses, in order of first use; a name without a package
// is of the text's own package.
std::vector<std::string> Uses(const std::string& text, const std::string& package) {
  std::vector<std::string> out;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    std::string field_type = line.substr(start, line.find_first_of(" \t", start) - start);
    field_type = field_type.substr(0, field_type.find('['));   // arrays
    field_type = field_type.substr(0, field_type.find("<="));  // bounded strings
    if (field_type.empty() || field_type == "---" || Primitives().count(field_type)) continue;
    const size_t slash = field_type.find('/');
    const std::string full = slash == std::string::npos ? package + "/msg/" + field_type
                                                        : field_type.substr(0, slash) + "/msg/" +
                                                              field_type.substr(slash + 1);
    out.push_back(full);
  }
  return out;
}

std::string PackageOf(const std::string& type) { return type.substr(0, type.find('/')); }

// `top`'s text, then every type it uses (depth first, each once), MCAP's concatenation.
std::optional<std::string> Concatenate(const std::string& top_text, const std::string& package) {
  std::string out = top_text;
  std::set<std::string> seen;
  std::vector<std::string> pending = Uses(top_text, package);
  while (!pending.empty()) {
    const std::string type = pending.front();
    pending.erase(pending.begin());
    if (!seen.insert(type).second) continue;
    const std::optional<std::string> text = Text(type);
    if (!text) return std::nullopt;
    const size_t slash = type.rfind('/');
    out += "\n" + std::string(80, '=') + "\nMSG: " + PackageOf(type) + "/" +
           type.substr(slash + 1) + "\n" + *text;
    const std::vector<std::string> more = Uses(*text, PackageOf(type));
    pending.insert(pending.end(), more.begin(), more.end());
  }
  return out;
}

}  // namespace

std::optional<std::string> Ros2MsgDefinition(const std::string& type) {
  const std::optional<std::string> text = Text(type);
  if (!text) return std::nullopt;
  return Concatenate(*text, PackageOf(type));
}

std::optional<std::string> Ros2ServiceSampleDefinition(const std::string& service, bool request) {
  const auto it = kMonocleMsgsFiles.find(service);
  if (it == kMonocleMsgsFiles.end()) return std::nullopt;
  const std::string& srv = it->second;
  const size_t split = srv.find("\n---\n");
  if (split == std::string::npos) return std::nullopt;
  const std::string part = request ? srv.substr(0, split + 1) : srv.substr(split + 5);
  const std::string header =
      "uint64 guid  # rmw_cyclonedds's request header: the client's id\n"
      "int64 seq    # the request's number; a response echoes both\n";
  return Concatenate(header + part, PackageOf(service));
}

}  // namespace monocle::record
