// Several robots, one base station (doc/multi_robot.md): one node subscribed to N robots' keyframe topics.
// The private parameter `robots` lists the robots' namespaces (their ids); for each, the node runs a
// loop-closure adapter with the handles <robot> (topics: <robot>/keyframe_cloud, <robot>/keyframe_odom,
// <robot>/loop_closures, ...) and ~<robot> (parameters: the node's own private parameters, which
// ~<robot>/KEY overrides, and robot_id set to the robot). The robots' adapters share their keyframes as
// the robots' own nodes would (team_exchange.h), within this process: the same code finds the same loops,
// and only the keyframe clouds and poses cross the link from each robot.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <ros/ros.h>

#include "loop_closure/loop_closure_ros.h"

namespace scan_context_loop {

class TeamBaseRos {
 public:
  TeamBaseRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& name);
  /// Reads `robots` and starts an adapter per robot; false (each problem logged as fatal) when the list is
  /// missing, empty, holds an invalid or repeated id, or an adapter refuses its configuration.
  bool start();

 private:
  ros::NodeHandle nh_, pnh_;
  std::string name_;
  std::vector<std::unique_ptr<LoopClosureRos>> robots_;
};

/// The robot ids of a `robots` parameter value (a list, or one string of ids separated by spaces, as the
/// pose_graph node takes it); false with the reason when it is not a non-empty list of distinct valid ids.
bool parseRobotList(XmlRpc::XmlRpcValue& value, std::vector<std::string>* robots, std::string* error);

}  // namespace scan_context_loop
