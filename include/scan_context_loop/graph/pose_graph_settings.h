// The pose_graph node's keys, declared once like the loop_closure node's (core/settings.h): three tables,
// over the solver's PoseGraphConfig, the KeyframeMapConfig and the node's own PoseGraphOptions. The
// ROS reader, the validation, config/pose_graph.yaml's check and doc/parameters.md read them.
#pragma once

#include <string>
#include <vector>

#include "scan_context_loop/core/settings.h"
#include "scan_context_loop/graph/keyframe_map.h"
#include "scan_context_loop/graph/pose_graph.h"

namespace scan_context_loop {

/// The pose_graph node's own settings (ROS frames, tf, queues).
struct PoseGraphOptions {
  /// The frame of the corrected poses, the map cloud and the paths; the tf map_frame -> odometry frame
  /// carries the correction.
  std::string map_frame = "map";
  bool publish_tf = true;
  /// How often the map_frame -> odometry frame transform is sent, stamped now [Hz].
  double tf_rate = 20.0;
  /// Only verified loops enter the graph (unverified ones carry the descriptor's yaw prior and a wide
  /// covariance; with this false they enter too, under the robust loss).
  bool verified_only = true;
  /// A loop's and a cloud's stamp match a keyframe's within this [s].
  double stamp_tolerance = 0.01;
  /// Solve at most this often while loops keep coming [s] (0: after every batch with a new loop).
  double min_solve_interval = 0.5;
  /// The map_cloud topic is republished at most this often while it has subscribers and the graph
  /// changed [s] (0: only when the publish_map service is called).
  double map_period = 5.0;
  /// Events (keyframes, clouds, loops) waiting for the worker.
  int queue_size = 10000;
  /// Keyframe clouds are kept for the map (false: the selected_keyframe_cloud topic is not subscribed).
  bool build_map = true;
  /// The directory the ~save_map service writes in, and only in (empty: $ROS_HOME/scan_context_loop/maps).
  std::string map_directory;
  /// A directory the map is written to at shutdown (absolute, or relative to map_directory; empty: none).
  std::string map_save;
  /// Several robots (doc/pose_graph.md#several-robots): their ids, separated by spaces (the ROS
  /// parameter may be a list of strings); empty: one robot, the topics in the node's namespace.
  std::string robots;
  /// The robot whose odometry frame is the map's (empty: the first of `robots`).
  std::string anchor_robot;
};

/// The robot ids of `options.robots` in chain order: the anchor first (chain 0), then the others in
/// the order given. Empty without robots.
std::vector<std::string> robotIds(const PoseGraphOptions& options);

/// The solver's keys (odometry noise, robust loss, iterations).
const std::vector<Setting<PoseGraphConfig>>& poseGraphSettings();
/// The map's keys (map_voxel, map_max_range, map_keyframe_stride).
const std::vector<Setting<KeyframeMapConfig>>& keyframeMapSettings();
/// The node's own keys.
const std::vector<Setting<PoseGraphOptions>>& poseGraphNodeSettings();

}  // namespace scan_context_loop
