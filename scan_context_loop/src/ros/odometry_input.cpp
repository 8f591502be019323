#include "scan_context_loop/ros/odometry_input.h"

#include <cmath>

namespace scan_context_loop {

bool poseFromOdometry(const nav_msgs::Odometry& msg, Eigen::Isometry3d* pose, std::string* why) {
  const auto& p = msg.pose.pose.position;
  const auto& o = msg.pose.pose.orientation;
  const Eigen::Vector3d position(p.x, p.y, p.z);
  const Eigen::Quaterniond q(o.w, o.x, o.y, o.z);
  if (!position.allFinite() || !q.coeffs().allFinite()) {
    *why = "its pose is not finite";
    return false;
  }
  const double squared_norm = q.squaredNorm();
  if (!(std::abs(squared_norm - 1.0) <= 0.01)) {
    *why = "its orientation is not a unit quaternion (squared norm " + std::to_string(squared_norm) + ")";
    return false;
  }
  pose->setIdentity();
  pose->linear() = q.normalized().toRotationMatrix();
  pose->translation() = position;
  return true;
}

}  // namespace scan_context_loop
