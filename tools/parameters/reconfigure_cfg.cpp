#include "reconfigure_cfg.h"

#include <algorithm>
#include <sstream>

namespace scan_context_loop {

namespace {

std::string pythonString(const std::string& text) {
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

/// A number of the row's type as Python reads it.
std::string pythonNumber(SettingType type, double v) {
  return type == SettingType::kInt ? std::to_string(static_cast<long long>(v)) : floatText(v);
}

const char* parameterType(SettingType type) {
  switch (type) {
    case SettingType::kInt:
      return "int_t";
    case SettingType::kDouble:
      return "double_t";
    case SettingType::kBool:
      return "bool_t";
    case SettingType::kChoice:
    case SettingType::kString:
      return "str_t";
  }
  return "";
}

/// `group.add(...)` for one row: name, type, level 0, description, default and the range's bounds.
std::string addLine(const SettingRow& row) {
  std::ostringstream out;
  out << row.group.name << ".add(" << pythonString(row.key) << ", " << parameterType(row.type) << ", 0, "
      << pythonString(row.doc + row.range.note) << ", ";
  if (row.number) {
    out << pythonNumber(row.type, row.default_number);
    if (row.range.boundedBelow()) out << ", " << pythonNumber(row.type, row.range.low);
    if (row.range.boundedAbove()) {
      out << (row.range.boundedBelow() ? ", " : ", max=") << pythonNumber(row.type, row.range.high);
    }
  } else if (row.type == SettingType::kBool) {
    out << (row.default_text == "true" ? "True" : "False");
  } else {
    out << pythonString(row.default_text);
  }
  out << ")\n";
  return out.str();
}

}  // namespace

std::string reconfigureCfg(const std::vector<std::string>& header, const std::vector<std::vector<SettingRow>>& tables,
                           const ReconfigureNames& names) {
  std::ostringstream out;
  out << "#!/usr/bin/env python3\n";
  for (const auto& line : header) out << "# " << line << "\n";
  out << "from dynamic_reconfigure.parameter_generator_catkin import ParameterGenerator, bool_t, double_t, int_t, "
         "str_t\n\ngen = ParameterGenerator()\n";
  std::vector<std::string> groups;
  for (const auto& table : tables) {
    for (const auto& row : table) {
      if (row.live && std::find(groups.begin(), groups.end(), row.group.name) == groups.end()) {
        groups.push_back(row.group.name);
      }
    }
  }
  for (const auto& group : groups) {
    out << "\n" << group << " = gen.add_group(" << pythonString(group) << ")\n";
    for (const auto& table : tables) {
      for (const auto& row : table) {
        if (row.live && row.group.name == group) out << addLine(row);
      }
    }
  }
  out << "\nexit(gen.generate(" << pythonString(names.package) << ", " << pythonString(names.node) << ", "
      << pythonString(names.name) << "))\n";
  return out.str();
}

}  // namespace scan_context_loop
