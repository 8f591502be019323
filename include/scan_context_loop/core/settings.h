// Every configuration key, declared once: its name, the member it sets, its type, its range and a
// one-line doc. Parsing (setConfigValue), validation (Config::validate), the YAML reader of the
// evaluator, the node's ROS parameter reader and the check of config/default.yaml all read these tables.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/node_options.h"

namespace scan_context_loop {

enum class SettingType { kInt, kDouble, kBool, kChoice, kString };

/// One key of a settings table over the struct T (Config or NodeOptions).
template <typename T>
struct Setting {
  std::string key;
  SettingType type = SettingType::kDouble;
  std::string doc;                   ///< one line
  std::vector<std::string> choices;  ///< kChoice: the accepted names
  /// The value in `target` as text ("20", "0.25", "true", "occupancy").
  std::function<std::string(const T& target)> get;
  /// Parses `text` into `target`; false (target unchanged) when it is not a value of this type.
  std::function<bool(T* target, const std::string& text)> set;
  /// "" when the value in `target` is allowed, else the rule it breaks ("must be in [1, 1000]").
  std::function<std::string(const T& target)> check;
  /// Safe to change while running: read afresh for every keyframe and never baked into stored data
  /// (KeyframePipeline::reconfigure, the node's dynamic_reconfigure server).
  bool live = false;
};

/// The core's keys (config/*.yaml, the node's private parameters, `scripts/evaluate --set`).
const std::vector<Setting<Config>>& configSettings();
/// The node's own keys (ROS input, threading, publishing): read by the node, accepted and ignored by
/// the evaluator.
const std::vector<Setting<NodeOptions>>& nodeSettings();

/// The row of `key`, or nullptr.
template <typename T>
const Setting<T>* findSetting(const std::vector<Setting<T>>& table, const std::string& key) {
  for (const auto& s : table) {
    if (s.key == key) return &s;
  }
  return nullptr;
}

/// "key = value: rule" for every value of the table that breaks its rule.
template <typename T>
std::vector<std::string> checkSettings(const std::vector<Setting<T>>& table, const T& target) {
  std::vector<std::string> problems;
  for (const auto& s : table) {
    const std::string rule = s.check(target);
    if (!rule.empty()) problems.push_back(s.key + " = " + s.get(target) + ": " + rule);
  }
  return problems;
}

/// The keys that may not change while running (not Setting::live) whose values differ between `a` and `b`.
template <typename T>
std::vector<std::string> fixedSettingsChanged(const std::vector<Setting<T>>& table, const T& a, const T& b) {
  std::vector<std::string> changed;
  for (const auto& s : table) {
    if (!s.live && s.get(a) != s.get(b)) changed.push_back(s.key);
  }
  return changed;
}

/// A name for the type, for messages ("an integer", "a number", "true or false", ...).
std::string settingTypeName(SettingType type, const std::vector<std::string>& choices);

}  // namespace scan_context_loop
