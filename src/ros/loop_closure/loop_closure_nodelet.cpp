// The loop-closure nodelet: the adapter in a nodelet.
#include <pluginlib/class_list_macros.hpp>

#include "shared/adapter_nodelet.h"
#include "loop_closure/loop_closure_ros.h"

namespace scan_context_loop {
using LoopClosureNodelet = AdapterNodelet<LoopClosureRos>;
}  // namespace scan_context_loop

PLUGINLIB_EXPORT_CLASS(scan_context_loop::LoopClosureNodelet, nodelet::Nodelet)
