// The pose_graph node's robots: each robot's topics, keyframes (by stamp) and chain in the graph, and
// what is published per robot. Without the `robots` parameter there is one robot, id "", whose topics
// are the node's own (today's single-robot node); with it, robot r's topics are `<r>/...`, its
// keyframes are chain r's (the anchor's chain 0), and a loop names its robots by query_robot /
// match_robot (empty: the robot whose topic it came on). doc/pose_graph.md#several-robots.
#pragma once

#include <cstddef>
#include <deque>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include "scan_context_loop/graph/pose_graph.h"

namespace scan_context_loop {

/// One robot of the pose_graph node. The subscribers and publishers are set up once at start; the rest
/// belongs to the worker.
struct GraphRobot {
  std::string id;         ///< "" for the single robot
  std::size_t chain = 0;  ///< its chain in the graph
  ros::Subscriber odom_sub, cloud_sub, loop_sub;
  ros::Publisher path_pub, odometry_path_pub;

  // Worker-only.
  std::vector<ros::Time> stamps;                              ///< its keyframes' stamps, increasing
  std::vector<std::size_t> keyframes;                         ///< their graph indices, by stamp
  std::deque<sensor_msgs::PointCloud2ConstPtr> early_clouds;  ///< clouds that came before their pose
  std::string odom_frame;  ///< its keyframes' frame (the first keyframe's), "" before it

  /// `name` in this robot's namespace: "<id>/<name>", or `name` for the single robot.
  std::string topic(const std::string& name) const { return id.empty() ? name : id + "/" + name; }
  /// The graph index of its keyframe whose stamp is nearest `stamp` within `tolerance` [s], or -1.
  long keyframeAt(const ros::Time& stamp, double tolerance) const;
  /// A keyframe at `stamp` may still come: it is after the newest (or none came yet).
  bool stillToCome(const ros::Time& stamp) const { return stamps.empty() || stamp > stamps.back(); }
};

/// The robot named `id` in `robots`, or -1; "" (a loop without robot ids) is `fallback`, the robot whose
/// topic the loop came on.
long robotNamed(const std::vector<GraphRobot>& robots, const std::string& id, std::size_t fallback);

/// What the worker publishes of one robot, from the graph: its corrected and its odometry path in
/// the frame they are in (map_frame once joined; until then its own odometry frame, the graph's estimate
/// moved by inverse(frame)), and the tf it carries.
struct RobotView {
  nav_msgs::Path corrected, odometry;
  bool joined = false;
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();  ///< T_map<-odom at its newest keyframe
};

/// `robot`'s paths: corrected poses, and its odometry placed by frame(chain) (the first keyframe is
/// where both start), in `map_frame` when joined, else in its odometry frame (poses moved by
/// inverse(frame(chain))). Empty paths before its first keyframe.
RobotView viewOf(const PoseGraph& graph, const GraphRobot& robot, const std::string& map_frame);

/// Per graph keyframe: true for those of robots not joined (left out of the map).
std::vector<bool> unjoinedKeyframes(const PoseGraph& graph, const std::vector<GraphRobot>& robots);

/// The graph's keyframe stamps [ns] by graph index.
std::vector<std::int64_t> stampsByIndex(const PoseGraph& graph, const std::vector<GraphRobot>& robots);

}  // namespace scan_context_loop
