// Fuzz target: nav_msgs/Odometry input (poseFromMsg) and the core's use of the poses and stamps.
//
// Input bytes, in order: u8 configuration choice (smallConfig), u8 mode (odd: every finite pose goes to
// the core as the quaternion's matrix, unchecked and unnormalised, as other callers of the core may
// pass it; even: through poseFromMsg, as the node does), then up to 4 messages while bytes
// remain, each: u32 stamp sec, u32 stamp nsec, position x, y, z and orientation x, y, z, w (each a
// FuzzBytes::number: raw doubles, small values, or NaN, Inf, huge and denormal ones).
#include <nav_msgs/Odometry.h>

#include "fuzz_input.h"
#include "scan_context_loop/core/keyframes.h"
#include "shared/pose_input.h"

namespace scan_context_loop::fuzz {

namespace {

nav_msgs::Odometry decodeOdometry(FuzzBytes* in) {
  nav_msgs::Odometry msg;
  // Straight into the message's fields, as deserialisation does (ros::Time's constructor would
  // normalise them).
  msg.header.stamp.sec = in->take<std::uint32_t>();
  msg.header.stamp.nsec = in->take<std::uint32_t>();
  auto& pose = msg.pose.pose;
  pose.position.x = in->number();
  pose.position.y = in->number();
  pose.position.z = in->number();
  pose.orientation.x = in->number();
  pose.orientation.y = in->number();
  pose.orientation.z = in->number();
  pose.orientation.w = in->number();
  return msg;
}

}  // namespace

int odometryInput(const std::uint8_t* data, std::size_t size) {
  FuzzBytes in(data, size);
  KeyframePipeline pipeline(smallConfig(in.take<std::uint8_t>()));
  const bool unchecked = (in.take<std::uint8_t>() & 1) != 0;
  const PointView view = fixedCloud();
  for (int i = 0; i < 4 && in.remaining() > 0; ++i) {
    const nav_msgs::Odometry msg = decodeOdometry(&in);
    KeyframeInfo info;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    std::string why;
    if (unchecked) {
      const auto& o = msg.pose.pose.orientation;
      const auto& p = msg.pose.pose.position;
      pose.linear() = Eigen::Quaterniond(o.w, o.x, o.y, o.z).toRotationMatrix();
      pose.translation() = Eigen::Vector3d(p.x, p.y, p.z);
      if (!pose.matrix().allFinite()) continue;
    } else if (!poseFromMsg(msg.pose.pose, &pose, &why)) {
      continue;
    }
    info.stamp = msg.header.stamp.toSec();
    info.pose = pose;
    info.tag = i;
    pipeline.process(view, info);
  }
  return 0;
}

}  // namespace scan_context_loop::fuzz
