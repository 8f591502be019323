// Reading the node's YAML configuration (config/*.yaml) into the core Config.
#pragma once

#include <string>
#include <vector>

#include "scan_context_loop/core/config.h"

namespace scan_context_loop {
namespace eval {

/// Applies a flat YAML map of Config keys. The node's own keys (nodeSettings(), settings.h) are
/// accepted and skipped. Returns false with a reason naming the key for an unreadable file, an unknown
/// key or a bad value. A deprecated name of a key sets the key and adds a line to `warnings` (when given).
bool loadConfigFile(const std::string& path, Config* config, std::string* error,
                    std::vector<std::string>* warnings = nullptr);

/// Applies "key=value"; a deprecated key name adds a line to `warnings` (when given).
bool applyOverride(const std::string& assignment, Config* config, std::string* error,
                   std::vector<std::string>* warnings = nullptr);

}  // namespace eval
}  // namespace scan_context_loop
