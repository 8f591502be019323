// A keyframe the core's database holds, as the node publishes it: its stamp as the ROS stamp it came
// with, and its pose. The database keeps the stamp in seconds (KeyframeInfo::stamp), a double that
// cannot give back every nanosecond of a ROS stamp at today's Unix times, so the node also keeps the
// ROS stamp in nanoseconds in the keyframe's tag (free for the caller); the tag travels with the
// database file.
#pragma once

#include <Eigen/Geometry>
#include <ros/time.h>

#include "scan_context_loop/core/database.h"

namespace scan_context_loop {

/// Sets `info`'s stamp (seconds) and tag (nanoseconds) from `stamp`.
void setKeyframeStamp(const ros::Time& stamp, KeyframeInfo* info);

/// The ROS stamp of a stored keyframe: the tag's nanoseconds when they agree with the stamp within a
/// microsecond (a keyframe this node stored, or a file it saved), else the stamp in seconds (a keyframe
/// whose tag is unset or means something else, e.g. the evaluator's frame index); zero for a stamp out
/// of ros::Time's range.
ros::Time keyframeStamp(const KeyframeInfo& info);

/// A stored keyframe's sensor pose in its pose frame; the identity when it has none (a loaded keyframe
/// stored without one).
Eigen::Isometry3d keyframePose(const Keyframe& keyframe);
/// Its position: keyframePose(keyframe).translation().
Eigen::Vector3d keyframePosition(const Keyframe& keyframe);

}  // namespace scan_context_loop
