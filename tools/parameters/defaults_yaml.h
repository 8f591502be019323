// A YAML file of defaults (config/default.yaml, config/pose_graph.yaml) written from settings tables, in
// the style of robot_localization's ekf_template.yaml: every key with its default and, above it, a comment
// saying what it means, its unit, what it may be and its default.
#pragma once

#include <string>
#include <vector>

#include "setting_row.h"

namespace scan_context_loop {

/// `header` (comment lines, without "# "), then a section per group in the order the groups first
/// appear in `tables` (rows of several tables in one group share its section), each row as its comment
/// and `key: default`.
std::string defaultsYaml(const std::vector<std::string>& header, const std::vector<std::vector<SettingRow>>& tables);

/// The row's default as a YAML value that reads back as the row's type: 20, 2.0, true, odom, "".
std::string yamlValue(const SettingRow& row);

/// The comment above the row's key, unwrapped: doc, details, former names, what it may be, live, default.
std::string yamlComment(const SettingRow& row);

}  // namespace scan_context_loop
