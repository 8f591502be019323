#include "shared/parameters.h"

#include <algorithm>
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

namespace {

/// The number of single-character insertions, deletions and substitutions between `a` and `b`.
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string unknownKeyHint(const std::string& key, const std::vector<std::string>& keys) {
  if (key == "use_sim_time") {
    return "use_sim_time is a global parameter (/use_sim_time), not a node's: set it outside the node tag, "
           "e.g. <param name=\"use_sim_time\" value=\"true\"/> at the top of the launch file";
  }
  const std::string* best = nullptr;
  std::size_t best_distance = std::max<std::size_t>(2, key.size() / 4) + 1;
  for (const std::string& k : keys) {
    const std::size_t d = editDistance(key, k);
    if (d < best_distance) {
      best_distance = d;
      best = &k;
    }
  }
  return best ? "did you mean " + *best + "?" : "";
}

void reportUnknownParameters(const ros::NodeHandle& pnh, const std::vector<KnownKeys>& tables,
                             const std::string& where, std::vector<std::string>* problems) {
  std::vector<std::string> keys;
  for (const auto& table : tables) keys.insert(keys.end(), table.keys.begin(), table.keys.end());
  const auto known = [&](const std::string& key) {
    for (const auto& table : tables) {
      if (table.accepts(key)) return true;
    }
    return false;
  };
  for (const auto& key : unknownPrivateParameters(pnh, known)) {
    const std::string hint = unknownKeyHint(key, keys);
    problems->push_back(key + ": unknown parameter (" + (hint.empty() ? "" : hint + "; ") + "see " + where +
                        " for the keys)");
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
