#include "scan_context_sim/stack_shape.h"

namespace scan_context_loop {
namespace sim {

const std::vector<StackShape>& stackShapes() {
  static const std::vector<StackShape> shapes = {
      // laserMapping: every scan registered in camera_init (z up despite the name).
      {"aloam", "/velodyne_cloud_registered", "/aft_mapped_to_init", "camera_init", "camera_init",
       "aft_mapped", true, false, 10.0},
      // imageProjection and transformFusion: sensor-frame scans, pose in camera axes (y up).
      {"lego_loam", "/full_cloud_projected", "/integrated_to_init", "base_link", "camera_init", "camera", false,
       true, 10.0},
      // mapOptimization: every deskewed scan registered in odom.
      {"lio_sam", "/lio_sam/mapping/cloud_registered_raw", "/lio_sam/mapping/odometry", "odom", "odom",
       "odom_mapping", true, false, 10.0},
      // laserMapping: every scan in the body frame, whose pose /Odometry gives.
      {"fast_lio", "/cloud_registered_body", "/Odometry", "body", "camera_init", "body", false, false, 10.0},
  };
  return shapes;
}

const StackShape* findStackShape(const std::string& name) {
  for (const StackShape& s : stackShapes()) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::string stackNames() {
  std::string names;
  for (const StackShape& s : stackShapes()) names += (names.empty() ? "" : " | ") + s.name;
  return names;
}

Eigen::Isometry3d odometryAxes(const StackShape& shape) {
  Eigen::Isometry3d axes = Eigen::Isometry3d::Identity();
  if (shape.camera_axes) axes.linear() << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  return axes;
}

Eigen::Isometry3d toStackPose(const StackShape& shape, const Eigen::Isometry3d& lidar_pose) {
  const Eigen::Isometry3d axes = odometryAxes(shape);
  return axes * lidar_pose * axes.inverse();
}

Eigen::Isometry3d fromStackPose(const StackShape& shape, const Eigen::Isometry3d& stack_pose) {
  const Eigen::Isometry3d axes = odometryAxes(shape);
  return axes.inverse() * stack_pose * axes;
}

}  // namespace sim
}  // namespace scan_context_loop
