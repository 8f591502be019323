#include "defaults_yaml.h"

#include <algorithm>
#include <regex>
#include <sstream>

namespace scan_context_loop {

namespace {

constexpr std::size_t kWidth = 100;  // the repository's comment width

/// A plain scalar when it cannot read as another type (YAML 1.1, as rosparam's PyYAML reads it: "off",
/// "yes" and "null" are no strings there), else double-quoted.
std::string yamlString(const std::string& text) {
  static const std::regex plain("[A-Za-z_/$][A-Za-z0-9_/$.<>-]*");
  static const std::regex special("y|n|yes|no|true|false|on|off|null", std::regex::icase);
  if (std::regex_match(text, plain) && !std::regex_match(text, special)) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

std::string backquoted(const std::string& text) { return "`" + text + "`"; }

void section(std::ostringstream& out, const std::string& title) {
  std::string line = "# ---- " + title + " ";
  out << "\n" << line << std::string(line.size() < kWidth ? kWidth - line.size() : 4, '-') << "\n";
}

}  // namespace

std::string yamlValue(const SettingRow& row) {
  switch (row.type) {
    case SettingType::kDouble:
      return floatText(row.default_number);
    case SettingType::kInt:
    case SettingType::kBool:
      return row.default_text;
    case SettingType::kChoice:
    case SettingType::kString:
      return yamlString(row.default_text);
  }
  return row.default_text;
}

std::string yamlComment(const SettingRow& row) {
  std::string text = sentence(row.doc);
  if (!row.details.empty()) text += " " + row.details;
  for (const auto& old_key : row.deprecated_keys) {
    text += " Formerly " + backquoted(old_key) + ", still read with a warning.";
  }
  const std::string allowed = allowedText(row, yamlString);
  if (allowed == "any") {
    text += " Any finite number.";
  } else if (!allowed.empty()) {
    text += " Allowed: " + allowed + ".";
  }
  if (row.live) text += " Live: may change while running.";
  return text + " Default: " + yamlValue(row) + ".";
}

std::string defaultsYaml(const std::vector<std::string>& header, const std::vector<std::vector<SettingRow>>& tables) {
  std::ostringstream out;
  for (const auto& line : header) out << "# " << line << "\n";
  std::vector<std::string> groups;
  for (const auto& table : tables) {
    for (const auto& row : table) {
      if (std::find(groups.begin(), groups.end(), row.group.name) == groups.end()) groups.push_back(row.group.name);
    }
  }
  for (const auto& group : groups) {
    bool first = true;
    for (const auto& table : tables) {
      for (const auto& row : table) {
        if (row.group.name != group) continue;
        if (first) section(out, row.group.title);
        first = false;
        for (const auto& line : wrapped(yamlComment(row), kWidth - 2)) out << "# " << line << "\n";
        out << row.key << ": " << yamlValue(row) << "\n";
      }
    }
  }
  return out.str();
}

}  // namespace scan_context_loop
