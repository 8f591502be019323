// A loop in standard types, for backends that take no custom message: one std_msgs/Float64MultiArray
// a loop, self-contained (loop_closure_array), and the older pair of
// geometry_msgs/PoseWithCovarianceStamped published back to back on one topic (loop_closure_pairs).
#pragma once

#include <array>

#include <Eigen/Geometry>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <std_msgs/Float64MultiArray.h>

#include "scan_context_loop/LoopClosure.h"

namespace scan_context_loop {

/// [0]: the match keyframe, stamped with its stamp, at its sensor pose `world_from_match` as the node
/// received it (the reference: covariance all zero). [1]: the query keyframe, stamped with its stamp,
/// where the loop puts it: world_from_match * T_match<-query, with the loop's covariance turned into the
/// axes of the pose frame (position and rotation about the pose frame's axes). Both in
/// loop.header.frame_id. inverse([0]) * [1] is T_match<-query, the inverse of loop.relative_pose.
/// The fields of loopArray(), in order; also its layout's label.
extern const char* const kLoopArrayLayout;
constexpr std::size_t kLoopArraySize = 52;

/// One loop as 52 numbers: query_id, match_id, query_session, match_session, query_stamp, match_stamp
/// (seconds), verified (0 or 1), fitness, distance, relative_pose (x, y, z, qx, qy, qz, qw: T_query<-match)
/// and the 36 covariance entries, row-major, as in LoopClosure. layout.dim[0] is labelled with the field
/// names (kLoopArrayLayout). Ids are exact as doubles; stamps are exact to 0.25 us at today's Unix times
/// (to the nanosecond below 104 days, e.g. a bag's time from 0). Match a stamp within a microsecond.
std_msgs::Float64MultiArray loopArray(const scan_context_loop::LoopClosure& loop);

std::array<geometry_msgs::PoseWithCovarianceStamped, 2> loopPair(const scan_context_loop::LoopClosure& loop,
                                                                 const Eigen::Isometry3d& world_from_match);

}  // namespace scan_context_loop
