// A standalone node that loads one of the package's nodelet classes in-process.
#pragma once

#include <string>

#include <nodelet/loader.h>
#include <ros/ros.h>

namespace scan_context_loop {

/// ros::init under `node_name`, load `nodelet_class` with the command line's remappings and arguments,
/// spin. Returns main's exit status.
inline int runNodeletStandalone(int argc, char** argv, const std::string& node_name, const std::string& nodelet_class) {
  ros::init(argc, argv, node_name);
  nodelet::Loader loader;
  nodelet::M_string remappings(ros::names::getRemappings());
  nodelet::V_string arguments(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), nodelet_class, remappings, arguments)) {
    ROS_FATAL("%s not started (the lines above say why)", nodelet_class.c_str());
    return 1;
  }
  ros::spin();
  return 0;
}

}  // namespace scan_context_loop
