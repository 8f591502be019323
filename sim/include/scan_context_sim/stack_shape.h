// How the odometry stacks that scan_context_loop ships launch files for publish their scans and poses:
// topic names, frames, registered or sensor-frame clouds, camera-axes odometry and the scan rate. The
// simulator writes bags in these shapes (--stack) and the tests read them back with the same table.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {
namespace sim {

struct StackShape {
  std::string name;                     ///< "aloam", "lego_loam", "lio_sam", "fast_lio"; empty: the default shape
  std::string cloud_topic = "keyframe_cloud";
  std::string odom_topic = "keyframe_odom";  ///< nav_msgs/Odometry, the same stamps as the clouds
  std::string cloud_frame = "velodyne";  ///< the clouds' frame_id
  std::string odom_frame = "odom";       ///< the odometry's frame_id
  std::string child_frame = "velodyne";  ///< the odometry's child_frame_id
  bool registered = false;   ///< clouds registered in odom_frame with the odometry's pose, else in cloud_frame
  bool camera_axes = false;  ///< odometry in camera axes (y up) with a static tf child_frame -> cloud_frame
  double rate_hz = 0.0;      ///< scans a second the stack publishes (0: one cloud per keyframe)
};

/// A-LOAM, LeGO-LOAM, LIO-SAM and FAST-LIO, in that order.
const std::vector<StackShape>& stackShapes();
/// The stack's shape by name; nullptr when there is none.
const StackShape* findStackShape(const std::string& name);
/// "aloam | lego_loam | lio_sam | fast_lio".
std::string stackNames();

/// T_odometry-axes<-LiDAR-axes: camera axes (x_camera = y_lidar, y_camera = z_lidar, z_camera = x_lidar)
/// or the identity. It is also the static tf child_frame -> cloud_frame of a camera-axes stack.
Eigen::Isometry3d odometryAxes(const StackShape& shape);
/// The odometry a stack publishes for a LiDAR pose (x forward, z up) in a z-up world, and back.
Eigen::Isometry3d toStackPose(const StackShape& shape, const Eigen::Isometry3d& lidar_pose);
Eigen::Isometry3d fromStackPose(const StackShape& shape, const Eigen::Isometry3d& stack_pose);

}  // namespace sim
}  // namespace scan_context_loop
