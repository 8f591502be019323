// Odometry and tf poses as Eigen isometries, checked.
#pragma once

#include <string>

#include <Eigen/Geometry>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>

namespace scan_context_loop {

/// How far from 1 a quaternion's norm may be [-]: within it the quaternion is normalised (rounding in
/// the publisher, a float on the way); beyond it (all zero, NaN, badly scaled) it is refused.
constexpr double kQuaternionNormTolerance = 1e-3;

/// The pose as T_frame<-child. Returns false with a reason, leaving `pose` alone, when the orientation
/// is not a unit quaternion within kQuaternionNormTolerance or the position is not finite.
bool poseFromMsg(const geometry_msgs::Pose& msg, Eigen::Isometry3d* pose, std::string* why);
bool poseFromMsg(const geometry_msgs::Transform& msg, Eigen::Isometry3d* pose, std::string* why);

}  // namespace scan_context_loop
