#include "scan_context_loop/eval/config_file.h"

#include <algorithm>

#include <yaml-cpp/yaml.h>

namespace scan_context_loop {
namespace eval {

const std::vector<std::string>& rosOnlyKeys() {
  static const std::vector<std::string> keys = {
      "pose_source",          "fixed_frame",          "tf_timeout",         "sensor_frame",       "approximate_sync",
      "sync_queue_size",      "cloud_in_world_frame", "keyframe_min_distance", "keyframe_min_angle",
      "voxel_leaf",           "queue_size",           "publish_markers",    "marker_frame",
      "lio_sam_output",       "unsynchronised_warning", "diagnostics_period", "covariance_translation",
      "covariance_rotation"};
  return keys;
}

bool loadConfigFile(const std::string& path, Config* config, std::vector<std::string>* warnings, std::string* error) {
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
    const auto& known = configKeys();
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      const auto& ros = rosOnlyKeys();
      if (std::find(ros.begin(), ros.end(), key) == ros.end()) {
        warnings->push_back(path + ": unknown key '" + key + "' ignored");
      }
      continue;
    }
    if (!item.second.IsScalar()) {
      *error = path + ": " + key + " must be a single value";
      return false;
    }
    if (!setConfigValue(&updated, key, item.second.as<std::string>(), error)) {
      *error = path + ": " + *error;
      return false;
    }
  }
  *config = updated;
  return true;
}

bool applyOverride(const std::string& assignment, Config* config, std::string* error) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos) {
    *error = "expected key=value, got '" + assignment + "'";
    return false;
  }
  return setConfigValue(config, assignment.substr(0, eq), assignment.substr(eq + 1), error);
}

}  // namespace eval
}  // namespace scan_context_loop
