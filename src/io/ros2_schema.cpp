// Message definitions of the laser-log types and the check of the schema a bag declares.
#include <cctype>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

#include "glassmap/core/error.hpp"
#include "glassmap/io/ros2_cdr.hpp"

namespace glassmap::ros2 {
namespace {

struct Field {
  std::string type, name, default_value;
};
using Definition = std::vector<Field>;

/// The fields of every type the laser-log messages use, by "pkg/Type" (ROS 2 interface definitions).
const std::map<std::string, Definition>& definitions() {
  static const std::map<std::string, Definition> defs = [] {
    std::map<std::string, Definition> d;
    d["builtin_interfaces/Time"] = {{"int32", "sec", ""}, {"uint32", "nanosec", ""}};
    d["std_msgs/Header"] = {{"builtin_interfaces/Time", "stamp", ""}, {"string", "frame_id", ""}};
    const Definition scan_head = {{"std_msgs/Header", "header", ""}, {"float32", "angle_min", ""},
                                  {"float32", "angle_max", ""},      {"float32", "angle_increment", ""},
                                  {"float32", "time_increment", ""}, {"float32", "scan_time", ""},
                                  {"float32", "range_min", ""},      {"float32", "range_max", ""}};
    Definition scan = scan_head, multi = scan_head;
    scan.push_back({"float32[]", "ranges", ""});
    scan.push_back({"float32[]", "intensities", ""});
    multi.push_back({"sensor_msgs/LaserEcho[]", "ranges", ""});
    multi.push_back({"sensor_msgs/LaserEcho[]", "intensities", ""});
    d["sensor_msgs/LaserScan"] = scan;
    d["sensor_msgs/MultiEchoLaserScan"] = multi;
    d["sensor_msgs/LaserEcho"] = {{"float32[]", "echoes", ""}};
    d["geometry_msgs/Point"] = {{"float64", "x", ""}, {"float64", "y", ""}, {"float64", "z", ""}};
    d["geometry_msgs/Vector3"] = d["geometry_msgs/Point"];
    d["geometry_msgs/Quaternion"] = {
        {"float64", "x", "0"}, {"float64", "y", "0"}, {"float64", "z", "0"}, {"float64", "w", "1"}};
    d["geometry_msgs/Pose"] = {{"geometry_msgs/Point", "position", ""},
                               {"geometry_msgs/Quaternion", "orientation", ""}};
    d["geometry_msgs/PoseWithCovariance"] = {{"geometry_msgs/Pose", "pose", ""}, {"float64[36]", "covariance", ""}};
    d["geometry_msgs/Twist"] = {{"geometry_msgs/Vector3", "linear", ""}, {"geometry_msgs/Vector3", "angular", ""}};
    d["geometry_msgs/TwistWithCovariance"] = {{"geometry_msgs/Twist", "twist", ""}, {"float64[36]", "covariance", ""}};
    d["nav_msgs/Odometry"] = {{"std_msgs/Header", "header", ""},
                              {"string", "child_frame_id", ""},
                              {"geometry_msgs/PoseWithCovariance", "pose", ""},
                              {"geometry_msgs/TwistWithCovariance", "twist", ""}};
    d["geometry_msgs/Transform"] = {{"geometry_msgs/Vector3", "translation", ""},
                                    {"geometry_msgs/Quaternion", "rotation", ""}};
    d["geometry_msgs/TransformStamped"] = {{"std_msgs/Header", "header", ""},
                                           {"string", "child_frame_id", ""},
                                           {"geometry_msgs/Transform", "transform", ""}};
    d["tf2_msgs/TFMessage"] = {{"geometry_msgs/TransformStamped[]", "transforms", ""}};
    return d;
  }();
  return defs;
}

const std::set<std::string_view> kPrimitives = {"bool",   "byte",  "char",   "float32", "float64",
                                                "int8",   "uint8", "int16",  "uint16",  "int32",
                                                "uint32", "int64", "uint64", "string",  "wstring"};

/// "sensor_msgs/msg/LaserScan" -> "sensor_msgs/LaserScan".
std::string shortName(std::string type) {
  const auto p = type.find("/msg/");
  if (p != std::string::npos) type.erase(p, 4);
  return type;
}

/// The element type of a field type ("pkg/T[]" -> "pkg/T").
std::string elementType(const std::string& t) { return t.substr(0, t.find('[')); }

/// Normalises a field type of `package`: "/msg/" dropped, package added to relative names.
std::string normalizeType(const std::string& raw, const std::string& package) {
  std::string t = shortName(raw);
  const std::string elem = elementType(t);
  if (elem.find('/') == std::string::npos && !kPrimitives.contains(elem) && !elem.starts_with("string<")) {
    if (elem == "Header") return "std_msgs/" + t;  // the one relative name the ROS 1 rule still uses
    return package + "/" + t;
  }
  return t;
}

void addDependencies(const std::string& type, std::vector<std::string>& order) {
  for (const Field& f : definitions().at(type)) {
    const std::string e = elementType(f.type);
    if (kPrimitives.contains(e)) continue;
    bool seen = false;
    for (const auto& o : order) seen = seen || o == e;
    if (seen) continue;
    order.push_back(e);
    addDependencies(e, order);
  }
}

std::string fieldsText(const Definition& def) {
  std::string s;
  for (const Field& f : def) s += f.type + " " + f.name + (f.default_value.empty() ? "" : " " + f.default_value) + "\n";
  return s;
}

/// Sections of a ros2msg text: the main definition (name "") and each "MSG: pkg/Type" block.
std::vector<std::pair<std::string, std::vector<Field>>> parseSections(const std::string& text) {
  std::vector<std::pair<std::string, std::vector<Field>>> sections(1);
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream ls(line);
    std::string a, b, c;
    ls >> a >> b >> c;
    if (a.empty()) continue;
    if (a.starts_with("===")) {
      sections.emplace_back();
      continue;
    }
    if (a == "MSG:") {
      sections.back().first = shortName(b);
      continue;
    }
    if (b.find('=') != std::string::npos || c.starts_with("=")) continue;  // a constant
    sections.back().second.push_back({a, b, ""});
  }
  return sections;
}

/// Compares parsed fields with a known definition; returns "" when compatible, else what differs.
std::string compare(const std::vector<Field>& got, const std::string& type) {
  const Definition& want = definitions().at(type);
  const std::string package = type.substr(0, type.find('/'));
  for (std::size_t i = 0; i < want.size(); ++i) {
    if (i >= got.size()) return type + " lacks field '" + want[i].type + " " + want[i].name + "'";
    const std::string t = normalizeType(got[i].type, package);
    if (got[i].name != want[i].name || t != want[i].type)
      return type + " field " + std::to_string(i + 1) + " is '" + got[i].type + " " + got[i].name + "', expected '" +
             want[i].type + " " + want[i].name + "'";
  }
  if (got.size() > want.size()) return type + " has an extra field '" + got[want.size()].name + "'";
  return {};
}

bool hasWord(const std::string& text, const std::string& word) {
  for (std::size_t p = text.find(word); p != std::string::npos; p = text.find(word, p + 1)) {
    const bool left = p == 0 || !(std::isalnum(static_cast<unsigned char>(text[p - 1])) || text[p - 1] == '_');
    const std::size_t e = p + word.size();
    const bool right = e == text.size() || !(std::isalnum(static_cast<unsigned char>(text[e])) || text[e] == '_');
    if (left && right) return true;
  }
  return false;
}

}  // namespace

std::string messageDefinition(const std::string& type) {
  const std::string name = shortName(type);
  const auto it = definitions().find(name);
  if (it == definitions().end()) throw Error("no message definition known for type " + type);
  std::string text = fieldsText(it->second);
  std::vector<std::string> deps;
  addDependencies(name, deps);
  for (const std::string& d : deps)
    text += std::string(80, '=') + "\nMSG: " + d + "\n" + fieldsText(definitions().at(d));
  return text;
}

void checkTopicSchema(const std::string& topic, const std::string& type, const std::string& serialization,
                      const std::string& schema_encoding, const std::string& schema_text) {
  const std::string name = shortName(type);
  static const std::set<std::string> kTopLevel = {"sensor_msgs/LaserScan", "sensor_msgs/MultiEchoLaserScan",
                                                  "nav_msgs/Odometry", "tf2_msgs/TFMessage"};
  if (!kTopLevel.contains(name))
    throw Error("topic " + topic + " has type '" + type +
                "', which glassmap cannot read (sensor_msgs/msg/LaserScan, sensor_msgs/msg/MultiEchoLaserScan, "
                "nav_msgs/msg/Odometry, tf2_msgs/msg/TFMessage)");
  if (serialization != "cdr")
    throw Error("topic " + topic + " (" + type + ") is serialized as '" + serialization +
                "'; glassmap reads only 'cdr'");
  if (schema_text.empty()) return;
  if (schema_encoding == "ros2idl") {
    for (const Field& f : definitions().at(name))
      if (!hasWord(schema_text, f.name))
        throw Error("topic " + topic + ": the bag's IDL schema of " + type + " has no field '" + f.name +
                    "': not the definition glassmap reads");
    return;
  }
  if (!schema_encoding.empty() && schema_encoding != "ros2msg") return;  // nothing we can parse
  for (const auto& [section, fields] : parseSections(schema_text)) {
    const std::string what = section.empty() ? name : section;
    if (!definitions().contains(what)) continue;  // a nested type glassmap does not decode
    const std::string diff = compare(fields, what);
    if (!diff.empty())
      throw Error("topic " + topic + ": the bag's schema of " + type +
                  " is incompatible with the one glassmap reads: " + diff);
  }
}

}  // namespace glassmap::ros2
