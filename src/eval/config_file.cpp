#include "scan_context_loop/eval/config_file.h"

#include <yaml-cpp/yaml.h>

#include "scan_context_loop/core/settings.h"

namespace scan_context_loop {
namespace eval {

bool loadConfigFile(const std::string& path, Config* config, std::string* error, std::vector<std::string>* warnings) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const std::exception& e) {
    *error = "cannot read " + path + ": " + e.what();
    return false;
  }
  if (root.IsNull()) return true;
  if (!root.IsMap()) {
    *error = path + ": expected a map of key: value";
    return false;
  }
  Config updated = *config;
  for (const auto& item : root) {
    const std::string key = item.first.as<std::string>();
    std::string warning;
    if (findSetting(configSettings(), key) == nullptr) {
      if (findSetting(nodeSettings(), key) != nullptr) continue;  // the node's own: accepted, not used here
      *error = path + ": unknown key '" + key + "' (see config/default.yaml for the keys)";
      return false;
    }
    if (!item.second.IsScalar()) {
      *error = path + ": " + key + " must be a single value";
      return false;
    }
    if (!setConfigValue(&updated, key, item.second.as<std::string>(), error, &warning)) {
      *error = path + ": " + *error;
      return false;
    }
    if (!warning.empty() && warnings) warnings->push_back(path + ": " + warning);
  }
  *config = updated;
  return true;
}

bool applyOverride(const std::string& assignment, Config* config, std::string* error,
                   std::vector<std::string>* warnings) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos) {
    *error = "expected key=value, got '" + assignment + "'";
    return false;
  }
  std::string warning;
  if (!setConfigValue(config, assignment.substr(0, eq), assignment.substr(eq + 1), error, &warning)) return false;
  if (!warning.empty() && warnings) warnings->push_back(warning);
  return true;
}

}  // namespace eval
}  // namespace scan_context_loop
