// RViz markers for the keyframes and the loops found.
#pragma once

#include <cstdint>
#include <functional>
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

/// Keyframes and rejected candidates are drawn in chunks of this many (one marker id per chunk), loops
/// one marker id each, so an update carries what changed, not the whole map.
constexpr std::size_t kMarkerChunk = 100;

/// How much of each list the markers already show.
struct MarkerState {
  std::size_t keyframes = 0, loops = 0, rejected = 0;
};

/// The keyframes the markers draw: how many, and each one's position and session (by keyframe number).
struct MarkerKeyframes {
  std::size_t count = 0;
  std::function<Eigen::Vector3d(std::size_t)> position;
  std::function<std::uint32_t(std::size_t)> session;
};

/// Keyframe positions (spheres, coloured by `sessions`: the session of each keyframe, or empty for one
/// session), the trajectory (line segments between consecutive keyframes of one session), loop edges (lines from green
/// at distance 0 to red at the threshold) with both ends marked, a label per loop ("query -> match, distance"), and
/// candidates that verification rejected as thin grey lines. With `published`, only what changed since it (the last
/// keyframe and rejected chunks, the new loops) is made, and `published` is advanced; without it (or from a zero state)
/// everything. Markers keep their ids (namespace, id) across updates, so RViz replaces a chunk and keeps the rest.
visualization_msgs::MarkerArray makeLoopMarkers(const std::vector<Eigen::Vector3d>& positions,
                                                const std::vector<std::uint32_t>& sessions,
                                                const std::vector<LoopEdge>& loops,
                                                const std::vector<LoopEdge>& rejected, const std::string& frame,
                                                const ros::Time& stamp, double threshold,
                                                MarkerState* published = nullptr);

/// The same, for keyframes read through `keyframes`.
visualization_msgs::MarkerArray makeLoopMarkers(const MarkerKeyframes& keyframes, const std::vector<LoopEdge>& loops,
                                                const std::vector<LoopEdge>& rejected, const std::string& frame,
                                                const ros::Time& stamp, double threshold,
                                                MarkerState* published = nullptr);

}  // namespace scan_context_loop
