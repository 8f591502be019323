#include "team/team_base_ros.h"

#include <set>
#include <sstream>

#include "scan_context_loop/core/team_matcher.h"

namespace scan_context_loop {

bool parseRobotList(XmlRpc::XmlRpcValue& value, std::vector<std::string>* robots, std::string* error) {
  std::vector<std::string> items;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeString) {
    std::istringstream words(static_cast<std::string>(value));
    for (std::string word; words >> word;) items.push_back(word);
  } else if (value.getType() == XmlRpc::XmlRpcValue::TypeArray) {
    for (int i = 0; i < value.size(); ++i) {
      items.push_back(value[i].getType() == XmlRpc::XmlRpcValue::TypeString ? static_cast<std::string>(value[i]) : "");
    }
  }
  if (items.empty()) {
    *error = "robots must list the robot ids (the robots' namespaces): [robot1, robot2] or \"robot1 robot2\"";
    return false;
  }
  std::set<std::string> seen;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (!validRobotId(items[i])) {
      *error = "robots[" + std::to_string(i) + "] is not a robot id (" + kRobotIdRule + ")";
      return false;
    }
    const std::string robot = items[i];
    if (!seen.insert(robot).second) {
      *error = "robots lists " + robot + " twice";
      return false;
    }
    robots->push_back(robot);
  }
  return true;
}

TeamBaseRos::TeamBaseRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const std::string& name)
    : nh_(nh), pnh_(pnh), name_(name) {}

bool TeamBaseRos::start() {
  XmlRpc::XmlRpcValue value;
  std::vector<std::string> robots;
  std::string error;
  if (!pnh_.getParam("robots", value) || !parseRobotList(value, &robots, &error)) {
    ROS_FATAL_NAMED(name_, "not starting: %s", error.empty() ? "parameter robots is not set" : error.c_str());
    return false;
  }
  const std::string base = pnh_.getNamespace() + "/";
  std::vector<std::string> names;
  ros::param::getParamNames(names);
  for (const std::string& robot : robots) {
    ros::NodeHandle robot_pnh(pnh_, robot);
    // The node's private parameters, for every robot (its own ~<robot>/KEY wins), but the list and the
    // other robots' sections.
    for (const std::string& full : names) {
      if (full.compare(0, base.size(), base) != 0) continue;
      const std::string key = full.substr(base.size());
      const std::string first = key.substr(0, key.find('/'));
      if (first == "robots" || std::find(robots.begin(), robots.end(), first) != robots.end()) continue;
      XmlRpc::XmlRpcValue v;
      if (!robot_pnh.hasParam(key) && ros::param::get(full, v)) robot_pnh.setParam(key, v);
    }
    robot_pnh.setParam("robot_id", robot);
    auto adapter = std::make_unique<LoopClosureRos>(ros::NodeHandle(nh_, robot), robot_pnh, name_ + "/" + robot);
    if (!adapter->start()) {
      ROS_FATAL_NAMED(name_, "not starting: robot %s's configuration was refused (above)", robot.c_str());
      robots_.clear();
      return false;
    }
    robots_.push_back(std::move(adapter));
  }
  ROS_INFO_NAMED(name_, "base station for %zu robots", robots_.size());
  return true;
}

}  // namespace scan_context_loop
