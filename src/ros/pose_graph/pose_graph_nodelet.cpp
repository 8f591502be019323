// The pose_graph nodelet: the reference backend's adapter in a nodelet.
#include <pluginlib/class_list_macros.hpp>

#include "shared/adapter_nodelet.h"
#include "pose_graph/pose_graph_ros.h"

namespace scan_context_loop {
using PoseGraphNodelet = AdapterNodelet<PoseGraphRos>;
}  // namespace scan_context_loop

PLUGINLIB_EXPORT_CLASS(scan_context_loop::PoseGraphNodelet, nodelet::Nodelet)
