#include "shared/stored_keyframe.h"

#include <cmath>

namespace scan_context_loop {

namespace {

constexpr double kTagAgreement = 1e-6;  // [s] between the tag's nanoseconds and the stamp
constexpr double kLatestStamp = 4e9;    // [s] ros::Time holds seconds in 32 bits

}  // namespace

void setKeyframeStamp(const ros::Time& stamp, KeyframeInfo* info) {
  info->stamp = stamp.toSec();
  info->tag = static_cast<std::int64_t>(stamp.toNSec());
}

ros::Time keyframeStamp(const KeyframeInfo& info) {
  if (!(info.stamp >= 0.0 && info.stamp < kLatestStamp)) return ros::Time();
  if (info.tag >= 0 && std::abs(static_cast<double>(info.tag) * 1e-9 - info.stamp) <= kTagAgreement) {
    ros::Time stamp;
    stamp.fromNSec(static_cast<std::uint64_t>(info.tag));
    return stamp;
  }
  return ros::Time(info.stamp);
}

Eigen::Isometry3d keyframePose(const Keyframe& keyframe) {
  return keyframe.info.pose ? *keyframe.info.pose : Eigen::Isometry3d::Identity();
}

Eigen::Vector3d keyframePosition(const Keyframe& keyframe) {
  return keyframe.info.pose ? Eigen::Vector3d(keyframe.info.pose->translation()) : Eigen::Vector3d::Zero();
}

}  // namespace scan_context_loop
