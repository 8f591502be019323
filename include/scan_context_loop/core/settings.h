// Every configuration key, declared once: its name, the member it sets, its type, its range, its group,
// a one-line doc and a longer explanation. Parsing (setConfigValue), validation (Config::validate), the
// YAML reader of the evaluator and the nodes' ROS parameter reader read these tables, and the files a
// user reads are written from them (tools/parameters: doc/parameters.md, config/default.yaml,
// config/pose_graph.yaml and cfg/LoopClosure.cfg), so a new setting is one row. The pose_graph node's
// tables use the same Setting<T> (graph/pose_graph_settings.h).
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/node_options.h"

namespace scan_context_loop {

enum class SettingType { kInt, kDouble, kBool, kChoice, kString };

/// The interval a number row allows; `open_low` / `open_high` exclude the bound. Not finite values are
/// never allowed. The default is unbounded (any finite number).
struct SettingRange {
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  bool open_low = false, open_high = false;
  std::string note;  ///< appended to the rule, e.g. " (0 disables)"

  bool boundedBelow() const { return low != -std::numeric_limits<double>::infinity(); }
  bool boundedAbove() const { return high != std::numeric_limits<double>::infinity(); }
  bool contains(double v) const;
  /// The rule as text: "must be finite", "must be finite and >= 0 (0 disables)", "must be in (0, 2]".
  std::string rule() const;
  /// The interval alone: "any", ">= 0", "(0, 2]".
  std::string interval() const;
};

/// A run of related rows of a table. `name` (a Python identifier) is the dynamic_reconfigure group of its
/// live rows (cfg/LoopClosure.cfg); `title` heads its section of the YAML file of defaults. Rows of
/// several tables with the same group name share one section.
struct SettingGroup {
  std::string name;
  std::string title;
};

/// One key of a settings table over the struct T (Config, NodeOptions, the pose_graph node's structs).
template <typename T>
struct Setting {
  std::string key;
  SettingType type = SettingType::kDouble;
  std::string doc;  ///< one line
  /// What a user should know beyond `doc` (whole sentences, no line breaks; may be empty): the comment
  /// above the key in the YAML file of defaults says it after the doc.
  std::string details;
  SettingGroup group;
  std::vector<std::string> choices;  ///< kChoice: the accepted names
  /// Earlier names of the key: still read (ROS parameters, YAML, --set), each with a warning.
  std::vector<std::string> deprecated_keys;
  /// The value in `target` as text ("20", "0.25", "true", "occupancy").
  std::function<std::string(const T& target)> get;
  /// Parses `text` into `target`; false (target unchanged) when it is not a value of this type.
  std::function<bool(T* target, const std::string& text)> set;
  /// kInt, kDouble: the value as a number, checked against `range`.
  std::function<double(const T& target)> number;
  SettingRange range;
  /// A rule beyond the range (none when empty): "" when the value is allowed, else the rule it breaks.
  std::function<std::string(const T& target)> extra_check;
  /// That rule in a few words for the documentation ("not empty").
  std::string extra_rule;
  /// Safe to change while running: read afresh for every keyframe and never baked into stored data
  /// (KeyframePipeline::reconfigure, the node's dynamic_reconfigure server).
  bool live = false;

  /// "" when the value in `target` is allowed, else the rule it breaks ("must be in [1, 1000]").
  std::string check(const T& target) const {
    if (number && !range.contains(number(target))) return range.rule();
    return extra_check ? extra_check(target) : std::string();
  }
};

/// The core's keys (config/*.yaml, the node's private parameters, `scripts/evaluate --set`).
const std::vector<Setting<Config>>& configSettings();
/// The node's own keys (ROS input, threading, publishing): read by the node, accepted and ignored by
/// the evaluator.
const std::vector<Setting<NodeOptions>>& nodeSettings();

/// "old is deprecated, use new": the warning for reading a row by one of its deprecated_keys.
std::string deprecatedKeyWarning(const std::string& old_key, const std::string& key);

/// The row of `key`, or of a row that lists `key` among its deprecated_keys, or nullptr. For an old
/// name `deprecation` (when given) receives deprecatedKeyWarning; otherwise it is cleared.
template <typename T>
const Setting<T>* findSetting(const std::vector<Setting<T>>& table, const std::string& key,
                              std::string* deprecation = nullptr) {
  if (deprecation) deprecation->clear();
  for (const auto& s : table) {
    if (s.key == key) return &s;
  }
  for (const auto& s : table) {
    for (const auto& old_key : s.deprecated_keys) {
      if (old_key != key) continue;
      if (deprecation) *deprecation = deprecatedKeyWarning(old_key, s.key);
      return &s;
    }
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
