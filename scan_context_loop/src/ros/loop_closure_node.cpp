// The standalone node: loads the same nodelet class in-process.
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv) {
  ros::init(argc, argv, "loop_closure");
  nodelet::Loader loader;
  nodelet::M_string remappings(ros::names::getRemappings());
  nodelet::V_string arguments(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "scan_context_loop/LoopClosureNodelet", remappings, arguments)) {
    ROS_FATAL("cannot load scan_context_loop/LoopClosureNodelet");
    return 1;
  }
  ros::spin();
  return 0;
}
