// The pose_graph node's parameters, read once through its settings tables (graph/pose_graph_settings.h)
// and validated.
#pragma once

#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "scan_context_loop/graph/keyframe_map.h"
#include "scan_context_loop/graph/pose_graph.h"
#include "scan_context_loop/graph/pose_graph_settings.h"

namespace scan_context_loop {

/// Reads every key (each with the structs' default) from the private node handle. Returns the problems
/// found, empty when all is well: a private parameter that is no key, a value of the wrong type, a
/// value out of range. A deprecated key name adds a line to `warnings` (when given).
std::vector<std::string> readPoseGraphParameters(const ros::NodeHandle& pnh, PoseGraphConfig* graph,
                                                 KeyframeMapConfig* map, PoseGraphOptions* options,
                                                 std::vector<std::string>* warnings = nullptr);

}  // namespace scan_context_loop
