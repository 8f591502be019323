#include "shared/pose_input.h"

#include <cmath>
#include <sstream>

namespace scan_context_loop {

namespace {

bool isometryOf(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation, Eigen::Isometry3d* pose,
                std::string* why) {
  if (!position.allFinite()) {
    if (why) *why = "position is not finite";
    return false;
  }
  const double norm = orientation.norm();
  if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {  // NaN fails too
    std::ostringstream text;
    text << "orientation quaternion (x " << orientation.x() << ", y " << orientation.y() << ", z " << orientation.z()
         << ", w " << orientation.w() << ") has norm " << norm << ", not 1 within " << kQuaternionNormTolerance;
    if (why) *why = text.str();
    return false;
  }
  *pose = Eigen::Translation3d(position) * orientation.normalized();
  return true;
}

}  // namespace

bool poseFromMsg(const geometry_msgs::Pose& msg, Eigen::Isometry3d* pose, std::string* why) {
  const geometry_msgs::Quaternion& q = msg.orientation;
  return isometryOf({msg.position.x, msg.position.y, msg.position.z}, Eigen::Quaterniond(q.w, q.x, q.y, q.z), pose,
                    why);
}

bool poseFromMsg(const geometry_msgs::Transform& msg, Eigen::Isometry3d* pose, std::string* why) {
  const geometry_msgs::Quaternion& q = msg.rotation;
  return isometryOf({msg.translation.x, msg.translation.y, msg.translation.z}, Eigen::Quaterniond(q.w, q.x, q.y, q.z),
                    pose, why);
}

}  // namespace scan_context_loop
