#include "shared/parameters.h"

#include <cmath>
#include <sstream>

#include <ros/names.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "scan_context_loop/core/settings.h"
#include "scan_context_loop/core/team_matcher.h"

namespace scan_context_loop {

std::string parameterText(XmlRpc::XmlRpcValue& value, SettingType type, bool* ok) {
  *ok = true;
  std::ostringstream out;
  out.precision(17);
  switch (type) {
    case SettingType::kInt:
      if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) return std::to_string(static_cast<int>(value));
      break;
    case SettingType::kDouble:
      if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
        out << static_cast<double>(value);
        return out.str();
      }
      if (value.getType() == XmlRpc::XmlRpcValue::TypeInt) return std::to_string(static_cast<int>(value));
      break;
    case SettingType::kBool:
      if (value.getType() == XmlRpc::XmlRpcValue::TypeBoolean) return static_cast<bool>(value) ? "true" : "false";
      break;
    case SettingType::kString:
    case SettingType::kChoice:
      if (value.getType() == XmlRpc::XmlRpcValue::TypeString) return static_cast<std::string>(value);
      break;
  }
  *ok = false;
  return "";
}

std::vector<std::string> readParameters(const ros::NodeHandle& pnh, Config* c, NodeOptions* o,
                                        std::vector<std::string>* warnings) {
  std::vector<std::string> problems;
  readTable(pnh, configSettings(), c, &problems, warnings);
  readTable(pnh, nodeSettings(), o, &problems, warnings);
  reportUnknownParameters(pnh, {knownKeyOf(configSettings()), knownKeyOf(nodeSettings())}, "config/default.yaml",
                          &problems);

  for (const auto& p : c->validate()) problems.push_back(p);
  for (const auto& p : checkSettings(nodeSettings(), *o)) problems.push_back(p);
  const auto check = [&](bool ok, const std::string& text) {
    if (!ok) problems.push_back(text);
  };
  check(!o->fixed_frame.empty() || o->pose_source != PoseSource::kTf, "fixed_frame must be set when pose_source is tf");
  check(o->mode != NodeMode::kRelocalize || c->verification.enabled, "mode relocalize needs verify: true");
  check(o->robot_id.empty() || validRobotId(o->robot_id), std::string("robot_id must be ") + kRobotIdRule);
  check(o->robot_id.empty() || o->mode == NodeMode::kDetect, "robot_id (a team) needs mode detect");
  std::string why;
  check(ros::names::validate(o->team_namespace, why) && !o->team_namespace.empty(),
        "team_namespace must be a valid ROS name: " + why);
  check(!(o->pose_source == PoseSource::kTf && c->cloud_in_world_frame && o->sensor_frame.empty()),
        "sensor_frame must name the sensor's tf frame when pose_source is tf and cloud_in_world_frame is true");
  return problems;
}

void reportUnknownParameters(const ros::NodeHandle& pnh,
                             const std::vector<std::function<bool(const std::string&)>>& tables,
                             const std::string& where, std::vector<std::string>* problems) {
  const auto known = [&](const std::string& key) {
    for (const auto& table : tables) {
      if (table(key)) return true;
    }
    return false;
  };
  for (const auto& key : unknownPrivateParameters(pnh, known)) {
    problems->push_back(key + ": unknown parameter (see " + where + " for the keys)");
  }
}

std::vector<std::string> unknownPrivateParameters(const ros::NodeHandle& pnh,
                                                  const std::function<bool(const std::string&)>& known) {
  std::vector<std::string> unknown, names;
  const std::string prefix = pnh.getNamespace() + "/";
  if (!pnh.getParamNames(names)) return unknown;
  for (const std::string& name : names) {
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string key = name.substr(prefix.size());
    if (!known(key)) unknown.push_back(key);
  }
  return unknown;
}

}  // namespace scan_context_loop
