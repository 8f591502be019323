// The node's parameters: every core Config key plus the ROS options, read once and validated.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/core/node_options.h"

namespace scan_context_loop {

using RosOptions = NodeOptions;


/// Reads every key of the settings tables (settings.h) from the private node handle, each with the
/// struct's default. Returns the problems found, empty when all is well: a private parameter that is
/// no key (a misspelling), a value of the wrong type (`verify: 1`, `exclude_recent_frames: 0.4`), a
/// value out of its range.
std::vector<std::string> readParameters(const ros::NodeHandle& pnh, Config* config, RosOptions* options);

/// The private parameters (keys under pnh's namespace) that `known` does not accept: misspellings, or
/// settings of another version.
std::vector<std::string> unknownPrivateParameters(const ros::NodeHandle& pnh,
                                                  const std::function<bool(const std::string&)>& known);

}  // namespace scan_context_loop
