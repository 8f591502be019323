// Checking nav_msgs/Odometry input and turning it into the keyframe pose the core takes.
#pragma once

#include <string>

#include <Eigen/Geometry>
#include <nav_msgs/Odometry.h>

namespace scan_context_loop {

/// The sensor pose of `msg` (position and orientation; the covariance and twist are not used). Returns
/// false with a reason, leaving *pose as it was, when a value is not finite or the orientation is not
/// a unit quaternion (|q|^2 more than 0.01 from 1, tf2's own tolerance: an all-zero quaternion from an
/// odometry that never set it, say). A quaternion within the tolerance is normalised.
bool poseFromOdometry(const nav_msgs::Odometry& msg, Eigen::Isometry3d* pose, std::string* why);

}  // namespace scan_context_loop
