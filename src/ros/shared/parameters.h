// The nodes' parameters, read once through their settings tables and validated: the loop_closure node's
// (every core Config key plus the ROS options) here, the pose_graph node's in pose_graph_parameters.h.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/node_options.h"
#include "scan_context_loop/core/settings.h"

namespace scan_context_loop {

/// Reads every key of the settings tables (settings.h) from the private node handle, each with the
/// struct's default. Returns the problems found, empty when all is well: a private parameter that is
/// no key (a misspelling), a value of the wrong type (`verify: 1`, `exclude_recent_frames: 0.4`), a
/// value out of its range. A deprecated key name (Setting::deprecated_keys) sets its key and adds a line
/// to `warnings` (when given).
std::vector<std::string> readParameters(const ros::NodeHandle& pnh, Config* config, NodeOptions* options,
                                        std::vector<std::string>* warnings = nullptr);

/// The parameter's value as the text the settings table parses; `ok` false when its type does not fit:
/// an integer for an int, a number for a double (an integer too), a boolean for a bool, a string for a
/// string or a choice.
std::string parameterText(XmlRpc::XmlRpcValue& value, SettingType type, bool* ok);

/// Reads every row of `table` present under the private node handle into `target` (the rest keep their
/// value), by its key or, with a line in `warnings` (when given), by one of its deprecated_keys (the key
/// wins when both are set). A value of the wrong type adds a line to `problems`. No range checks.
template <typename T>
void readTable(const ros::NodeHandle& pnh, const std::vector<Setting<T>>& table, T* target,
               std::vector<std::string>* problems, std::vector<std::string>* warnings = nullptr) {
  for (const auto& s : table) {
    std::vector<std::string> names = {s.key};
    names.insert(names.end(), s.deprecated_keys.begin(), s.deprecated_keys.end());
    bool taken = false;
    for (const auto& name : names) {
      XmlRpc::XmlRpcValue value;
      if (!pnh.getParam(name, value)) continue;  // the default stays
      if (name != s.key && warnings) warnings->push_back(deprecatedKeyWarning(name, s.key));
      if (taken) continue;
      taken = true;
      bool ok = false;
      const std::string text = parameterText(value, s.type, &ok);
      if (!ok || !s.set(target, text)) {
        problems->push_back(name + ": expected " + settingTypeName(s.type, s.choices) + ", got " + value.toXml());
      }
    }
  }
}

/// The keys a table accepts (its deprecated names too) and its current keys, to suggest one.
struct KnownKeys {
  std::function<bool(const std::string&)> accepts;
  std::vector<std::string> keys;
};

/// A table's KnownKeys, for reportUnknownParameters.
template <typename T>
KnownKeys knownKeyOf(const std::vector<Setting<T>>& table) {
  KnownKeys known{[&table](const std::string& key) { return findSetting(table, key) != nullptr; }, {}};
  for (const auto& s : table) known.keys.push_back(s.key);
  return known;
}

/// Adds "key: unknown parameter (...)" to `problems` for every private parameter that none of `tables`
/// knows, with the fix: the nearest key when one is a likely misspelling (unknownKeyHint), otherwise
/// where the keys are listed (`where`).
void reportUnknownParameters(const ros::NodeHandle& pnh, const std::vector<KnownKeys>& tables,
                             const std::string& where, std::vector<std::string>* problems);

/// What to do about unknown key `key`: "did you mean K?" for the key of `keys` a few edits away (at most
/// 2, or a quarter of its length), a note for the global parameters users put inside a node tag
/// (use_sim_time), or "" when nothing is near.
std::string unknownKeyHint(const std::string& key, const std::vector<std::string>& keys);

/// The private parameters (keys under pnh's namespace) that `known` does not accept: misspellings, or
/// settings of another version.
std::vector<std::string> unknownPrivateParameters(const ros::NodeHandle& pnh,
                                                  const std::function<bool(const std::string&)>& known);

}  // namespace scan_context_loop
