#include "pose_graph/pose_graph_robots.h"

#include <algorithm>

#include <tf2_eigen/tf2_eigen.h>

namespace scan_context_loop {

namespace {

nav_msgs::Path makePath(const std::vector<Eigen::Isometry3d>& poses, const std::vector<ros::Time>& stamps,
                        const std::string& frame) {
  nav_msgs::Path path;
  path.header.frame_id = frame;
  path.header.stamp = stamps.empty() ? ros::Time() : stamps.back();
  path.poses.resize(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    path.poses[i].header.frame_id = frame;
    path.poses[i].header.stamp = stamps[i];
    path.poses[i].pose = tf2::toMsg(poses[i]);
  }
  return path;
}

}  // namespace

long GraphRobot::keyframeAt(const ros::Time& stamp, double tolerance_seconds) const {
  const ros::Duration tolerance(tolerance_seconds);
  auto it = std::lower_bound(stamps.begin(), stamps.end(), stamp - tolerance);
  if (it == stamps.end() || *it > stamp + tolerance) return -1;
  // The nearest within the tolerance (keyframes closer together than it are ambiguous; take the nearest).
  auto best = it;
  for (++it; it != stamps.end() && *it <= stamp + tolerance; ++it) {
    if ((*it - stamp).toSec() * (*it - stamp).toSec() < (*best - stamp).toSec() * (*best - stamp).toSec()) best = it;
  }
  return static_cast<long>(keyframes[static_cast<std::size_t>(best - stamps.begin())]);
}

long robotNamed(const std::vector<GraphRobot>& robots, const std::string& id, std::size_t fallback) {
  if (id.empty()) return static_cast<long>(fallback);
  for (std::size_t r = 0; r < robots.size(); ++r) {
    if (robots[r].id == id) return static_cast<long>(r);
  }
  return -1;
}

RobotView viewOf(const PoseGraph& graph, const GraphRobot& robot, const std::string& map_frame) {
  RobotView view;
  view.joined = graph.joined(robot.chain);
  // Until joined, the robot's own odometry frame: its estimates in its group's frame, moved back by it.
  const Eigen::Isometry3d frame = graph.frame(robot.chain);
  const Eigen::Isometry3d into = view.joined ? Eigen::Isometry3d::Identity() : frame.inverse();
  const std::string frame_id = view.joined ? map_frame : robot.odom_frame;
  std::vector<Eigen::Isometry3d> corrected, odometry;
  for (const std::size_t i : robot.keyframes) {
    corrected.push_back(into * graph.pose(i));
    odometry.push_back(into * frame * graph.odometryPose(i));
  }
  view.corrected = makePath(corrected, robot.stamps, frame_id);
  view.odometry = makePath(odometry, robot.stamps, frame_id);
  view.correction = graph.correction(robot.chain);
  return view;
}

std::vector<bool> unjoinedKeyframes(const PoseGraph& graph, const std::vector<GraphRobot>& robots) {
  std::vector<bool> out(graph.size(), false);
  for (const GraphRobot& robot : robots) {
    if (graph.joined(robot.chain)) continue;
    for (const std::size_t i : robot.keyframes) out[i] = true;
  }
  return out;
}

std::vector<std::int64_t> stampsByIndex(const PoseGraph& graph, const std::vector<GraphRobot>& robots) {
  std::vector<std::int64_t> out(graph.size(), 0);
  for (const GraphRobot& robot : robots) {
    for (std::size_t k = 0; k < robot.keyframes.size(); ++k) {
      out[robot.keyframes[k]] = static_cast<std::int64_t>(robot.stamps[k].toNSec());
    }
  }
  return out;
}

}  // namespace scan_context_loop
