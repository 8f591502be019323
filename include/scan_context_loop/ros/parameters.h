// The node's parameters: every core Config key plus the ROS options, read once and validated.
#pragma once

#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "scan_context_loop/config.h"

namespace scan_context_loop {

struct RosOptions {
  std::string pose_source = "odom";     ///< "odom": keyframe_odom messages; "tf": look the pose up
  std::string fixed_frame = "odom";     ///< tf mode: the frame poses are looked up in
  double tf_timeout = 0.1;              ///< tf mode: how long to wait for a transform [s]
  std::string sensor_frame;             ///< tf mode: the sensor's frame (empty: the cloud's frame_id)
  bool approximate_sync = true;         ///< approximate (true) or exact time synchronisation
  int sync_queue_size = 20;             ///< message_filters queue per input
  bool cloud_in_world_frame = false;    ///< clouds arrive registered in the pose frame
  double keyframe_min_distance = 0.0;   ///< keyframe selection: metres since the last keyframe (0: off)
  double keyframe_min_angle = 0.0;      ///< keyframe selection: degrees of yaw since the last keyframe (0: off)
  double voxel_leaf = 0.0;              ///< voxel downsampling before describing [m] (0: off)
  int queue_size = 20;                  ///< keyframes waiting for the worker; more are dropped and counted
  bool lio_sam_output = false;          ///< also publish std_msgs/Float64MultiArray [query, match stamps]
  double unsynchronised_warning = 5.0;  ///< warn when clouds come without poses for this long [s]
  double covariance_translation = 100.0;  ///< variance of x, y, z of a yaw-prior-only constraint [m^2]
  double covariance_rotation = 0.01;      ///< variance of roll and pitch [rad^2]; yaw from half a sector
};

/// Reads every parameter from the private node handle, each with the struct's default. Returns the
/// problems found (unknown values, impossible numbers), empty when all is well.
std::vector<std::string> readParameters(const ros::NodeHandle& pnh, Config* config, RosOptions* options);

}  // namespace scan_context_loop
