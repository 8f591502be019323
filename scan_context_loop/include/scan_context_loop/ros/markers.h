// RViz markers for the keyframes and the loops found.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

namespace scan_context_loop {

struct LoopEdge {
  std::size_t query, match;
  double distance;
};

/// Keyframe positions (spheres), the trajectory (a line strip), loop edges (lines from green at
/// distance 0 to red at the threshold), a label per loop ("query -> match, distance"), and candidates
/// that verification rejected as thin grey lines.
visualization_msgs::MarkerArray makeLoopMarkers(const std::vector<Eigen::Vector3d>& positions,
                                                const std::vector<LoopEdge>& loops,
                                                const std::vector<LoopEdge>& rejected, const std::string& frame,
                                                const ros::Time& stamp, double threshold);

}  // namespace scan_context_loop
