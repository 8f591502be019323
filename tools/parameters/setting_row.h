// One row of any settings table with its default, without the table's struct: what the generated files
// (doc/parameters.md, config/*.yaml, cfg/LoopClosure.cfg) say about a key, and how they print values.
#pragma once

#include <string>
#include <vector>

#include "scan_context_loop/core/settings.h"

namespace scan_context_loop {

struct SettingRow {
  std::string key;
  SettingType type = SettingType::kDouble;
  std::string doc, details;
  SettingGroup group;
  std::vector<std::string> choices, deprecated_keys;
  std::string default_text;     ///< Setting::get of the struct's default
  double default_number = 0.0;  ///< kInt, kDouble: the default as a number
  bool number = false;          ///< kInt, kDouble: `range` applies
  SettingRange range;
  std::string extra_rule;
  bool live = false;
};

/// The rows of a table with the defaults of a default-constructed T.
template <typename T>
std::vector<SettingRow> settingRows(const std::vector<Setting<T>>& table) {
  const T defaults;
  std::vector<SettingRow> rows;
  for (const auto& s : table) {
    SettingRow r;
    r.key = s.key;
    r.type = s.type;
    r.doc = s.doc;
    r.details = s.details;
    r.group = s.group;
    r.choices = s.choices;
    r.deprecated_keys = s.deprecated_keys;
    r.default_text = s.get(defaults);
    r.number = static_cast<bool>(s.number);
    if (r.number) r.default_number = s.number(defaults);
    r.range = s.range;
    r.extra_rule = s.extra_rule;
    r.live = s.live;
    rows.push_back(r);
  }
  return rows;
}

/// "int", "double", "bool", "choice", "string".
const char* typeName(SettingType type);

/// What a value may be, in a few words: "[0, 1]", ">= 0 (0 disables)", the choices (each through
/// `quote`), "not empty"; "" for a bool or a string without a rule.
std::string allowedText(const SettingRow& row, std::string (*quote)(const std::string&));

/// A number as YAML 1.1 (rosparam's PyYAML) and Python read it back as a float: "2.0", "0.015",
/// "1.0e-06" (a float without a point would be an int, "1e-06" a string in YAML 1.1).
std::string floatText(double v);

/// `text` broken into lines of at most `width` characters (words longer than that stay whole).
std::vector<std::string> wrapped(const std::string& text, std::size_t width);

/// `text` with a full stop at the end, and its first letter upper case when it begins with a plain word.
std::string sentence(const std::string& text);

}  // namespace scan_context_loop
