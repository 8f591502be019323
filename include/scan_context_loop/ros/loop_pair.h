// A loop in standard types, for backends that take no custom message: two
// geometry_msgs/PoseWithCovarianceStamped, published back to back on one topic.
#pragma once

#include <array>

#include <Eigen/Geometry>
#include <geometry_msgs/PoseWithCovarianceStamped.h>

#include "scan_context_loop/LoopClosure.h"

namespace scan_context_loop {

/// [0]: the match keyframe, stamped with its stamp, at its sensor pose `world_from_match` as the node
/// received it (the reference: covariance all zero). [1]: the query keyframe, stamped with its stamp,
/// where the loop puts it: world_from_match * T_match<-query, with the loop's covariance turned into the
/// axes of the pose frame (position and rotation about the pose frame's axes). Both in
/// loop.header.frame_id. inverse([0]) * [1] is T_match<-query, the inverse of loop.relative_pose.
std::array<geometry_msgs::PoseWithCovarianceStamped, 2> loopPair(const scan_context_loop::LoopClosure& loop,
                                                                 const Eigen::Isometry3d& world_from_match);

}  // namespace scan_context_loop
