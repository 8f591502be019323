// Reading the node's YAML configuration (config/*.yaml) into the core Config.
#pragma once

#include <string>
#include <vector>

#include "scan_context_loop/config.h"

namespace scan_context_loop {
namespace eval {

/// Keys of config/*.yaml that configure the ROS node only; the evaluator accepts and ignores them.
const std::vector<std::string>& rosOnlyKeys();

/// Applies a flat YAML map of Config keys. ROS-only keys are skipped; any other unknown key is
/// reported in `warnings`. Returns false with a reason for an unreadable file or a bad value.
bool loadConfigFile(const std::string& path, Config* config, std::vector<std::string>* warnings, std::string* error);

/// Applies "key=value".
bool applyOverride(const std::string& assignment, Config* config, std::string* error);

}  // namespace eval
}  // namespace scan_context_loop
