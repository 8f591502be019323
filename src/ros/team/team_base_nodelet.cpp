// The base-station nodelet: one loop-closure adapter per robot of a team, in one process.
#include <pluginlib/class_list_macros.hpp>

#include "shared/adapter_nodelet.h"
#include "team/team_base_ros.h"

namespace scan_context_loop {
using TeamBaseNodelet = AdapterNodelet<TeamBaseRos>;
}  // namespace scan_context_loop

PLUGINLIB_EXPORT_CLASS(scan_context_loop::TeamBaseNodelet, nodelet::Nodelet)
