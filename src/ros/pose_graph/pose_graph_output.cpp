// PoseGraphRos's output, on its worker: the graph solved, the corrected path and poses, the loops it
// took, the graph's markers and the map.
#include <algorithm>
#include <chrono>

#include <nav_msgs/Path.h>
#include <pcl_conversions/pcl_conversions.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>

#include "pose_graph/pose_graph_ros.h"
#include "shared/frame_ids.h"

namespace scan_context_loop {

void PoseGraphRos::solveAndPublish(bool solve) {
  if (graph_->size() == 0) return;
  if (solve) {
    const PoseGraphResult result = graph_->optimize();
    last_solve_ = ros::WallTime::now();
    solve_pending_ = false;
    ++solves_;
    last_solve_ms_ = result.seconds * 1e3;
    last_cost_ = result.final_cost;
    map_changed_ = true;
    if (!result.solved) {
      ROS_WARN_THROTTLE_NAMED(5.0, name_, "the solve did not converge (%s); the last estimate is kept",
                              result.message.c_str());
    }
  }
  std::vector<TfFrame> tf_frames;
  std::size_t joined = 0;
  ros::Time newest;
  for (const GraphRobot& robot : robots_) {
    if (robot.keyframes.empty()) continue;  // nothing to show yet
    const RobotView view = viewOf(*graph_, robot, options_.map_frame);
    robot.path_pub.publish(view.corrected);
    robot.odometry_path_pub.publish(view.odometry);
    newest = std::max(newest, robot.stamps.back());
    if (!view.joined) continue;  // no tf: its frame is not in the map yet
    ++joined;
    tf_frames.push_back({robot.odom_frame, view.correction});
  }
  robots_joined_ = joined;
  {
    std::lock_guard<std::mutex> lock(correction_mutex_);
    tf_frames_.swap(tf_frames);
  }
  publishMarkers(graph_->poses(), newest);
}

void PoseGraphRos::publishMarkers(const std::vector<Eigen::Isometry3d>& poses, const ros::Time& stamp) {
  // The loops between the corrected poses: verified green, unverified (verified_only false) orange; those
  // of a robot not joined yet are in another frame and left out.
  const std::vector<bool> unjoined = unjoinedKeyframes(*graph_, robots_);
  visualization_msgs::MarkerArray markers;
  for (const bool verified : {true, false}) {
    visualization_msgs::Marker lines;
    lines.header.frame_id = options_.map_frame;
    lines.header.stamp = stamp;
    lines.ns = verified ? "verified loops" : "unverified loops";
    lines.id = 0;
    lines.type = visualization_msgs::Marker::LINE_LIST;
    lines.action = visualization_msgs::Marker::ADD;
    lines.pose.orientation.w = 1.0;
    lines.scale.x = 1.5;
    lines.color.a = 1.0;
    lines.color.r = verified ? 0.1f : 1.0f;
    lines.color.g = verified ? 0.9f : 0.55f;
    lines.color.b = 0.1f;
    for (const auto& loop : used_) {
      if (loop.verified != verified || unjoined[loop.query] || unjoined[loop.match]) continue;
      lines.points.push_back(tf2::toMsg(Eigen::Vector3d(poses[loop.query].translation())));
      lines.points.push_back(tf2::toMsg(Eigen::Vector3d(poses[loop.match].translation())));
    }
    if (lines.points.empty()) lines.action = visualization_msgs::Marker::DELETE;
    markers.markers.push_back(lines);
  }
  marker_pub_.publish(markers);
}

void PoseGraphRos::publishMap() {
  // Every joined robot's clouds at their corrected poses; a robot not joined yet is in another frame.
  const auto cloud = map_->assemble(graph_->poses(), unjoinedKeyframes(*graph_, robots_));
  sensor_msgs::PointCloud2 msg;
  pcl::toROSMsg(cloud, msg);
  msg.header.frame_id = options_.map_frame;
  for (const GraphRobot& robot : robots_) {
    if (!robot.stamps.empty()) msg.header.stamp = std::max(msg.header.stamp, robot.stamps.back());
  }
  map_pub_.publish(msg);
  last_map_ = ros::WallTime::now();
  map_changed_ = false;
}

}  // namespace scan_context_loop
