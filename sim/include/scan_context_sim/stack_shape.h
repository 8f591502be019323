// How the odometry stacks that scan_context_loop ships launch files for publish their scans and poses:
// topic names, frames as the stacks spell them (tf1's leading '/' included), registered or sensor-frame
// clouds, camera-axes odometry, the tf they and their launch files send, and the scan rate. The simulator
// writes bags in these shapes (--stack) and the tests read them back with the same table.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace scan_context_loop {
namespace sim {

struct StackShape {
  std::string name;  ///< "aloam", "lego_loam", "lio_sam", "fast_lio", "sc_aloam", "hdl_graph_slam"; empty: the default
  std::string cloud_topic = "keyframe_cloud";
  std::string odom_topic = "keyframe_odom";  ///< nav_msgs/Odometry, the same stamps as the clouds
  std::string cloud_frame = "velodyne";      ///< the clouds' frame_id
  std::string odom_frame = "odom";           ///< the odometry's frame_id
  std::string child_frame = "velodyne";      ///< the odometry's child_frame_id
  /// Clouds registered in odom_frame with the odometry's pose, else the sensor's points labelled cloud_frame
  /// (SC-A-LOAM's local clouds: labelled odom_frame although they are not registered).
  bool registered = false;
  /// Odometry in camera axes (y up), with the fixed extrinsic extrinsic_parent -> extrinsic_child.
  bool camera_axes = false;
  /// The camera-axes extrinsic's frames as the stack's launch file writes them (child_frame and
  /// cloud_frame, maybe with tf1's leading '/').
  std::string extrinsic_parent, extrinsic_child;
  /// A fixed map_frame -> odom_frame the stack's launch file sends too, turning camera axes back to z up
  /// (empty: none).
  std::string map_frame;
  /// tf1's static_transform_publisher period [s]: the fixed transforms go on /tf every period, each
  /// stamped a period ahead, as that tool sends them. 0: once, latched, on /tf_static (tf2's static
  /// broadcaster).
  double fixed_tf_period = 0.0;
  bool odom_tf = false;  ///< the odometry is also broadcast on /tf (odom_frame -> child_frame, its stamps)
  /// The odometry's world frame is the first scan's (LiDAR-only odometry, and FAST-LIO, which estimates
  /// gravity but leaves its world frame at the first IMU frame): as tilted as the sensor was then, not
  /// gravity-aligned. Otherwise the world is z up (LIO-SAM aligns it with gravity from the IMU).
  bool world_at_first_scan = false;
  double rate_hz = 0.0;  ///< scans a second the stack publishes (0: one cloud per keyframe)
};

/// A transform that never changes: T_parent<-child.
struct FixedTransform {
  std::string parent, child;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

/// A-LOAM, LeGO-LOAM, LIO-SAM, FAST-LIO, SC-A-LOAM and hdl_graph_slam, in that order.
const std::vector<StackShape>& stackShapes();
/// The stack's shape by name; nullptr when there is none.
const StackShape* findStackShape(const std::string& name);
/// "aloam | lego_loam | lio_sam | fast_lio | sc_aloam | hdl_graph_slam".
std::string stackNames();

/// A topic in a robot's namespace: "/<robot>/<topic>" (the topic's own leading '/' dropped); the topic as
/// it is for an empty robot.
std::string robotTopic(const std::string& robot, const std::string& topic);
/// A frame of a robot of a team: "<robot>/<frame>" (tf1's leading '/' dropped); as it is for an empty robot.
std::string robotFrame(const std::string& robot, const std::string& frame);
/// The shape one robot of a team publishes in: every topic in its namespace and every frame its own
/// (robotTopic, robotFrame). An empty robot: the shape as it is.
StackShape forRobot(const StackShape& shape, const std::string& robot);

/// T_odometry-axes<-LiDAR-axes: camera axes (x_camera = y_lidar, y_camera = z_lidar, z_camera = x_lidar)
/// or the identity. It is also the fixed extrinsic child_frame -> cloud_frame of a camera-axes stack.
Eigen::Isometry3d odometryAxes(const StackShape& shape);
/// The fixed transforms of the stack (the camera-axes extrinsic, map -> odometry frame), none for most.
std::vector<FixedTransform> fixedTransforms(const StackShape& shape);
/// The odometry a stack publishes for a LiDAR pose (x forward, z up) in a z-up world, and back.
Eigen::Isometry3d toStackPose(const StackShape& shape, const Eigen::Isometry3d& lidar_pose);
Eigen::Isometry3d fromStackPose(const StackShape& shape, const Eigen::Isometry3d& stack_pose);

}  // namespace sim
}  // namespace scan_context_loop
