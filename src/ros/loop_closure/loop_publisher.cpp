#include "loop_closure/loop_publisher.h"

#include <cmath>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <std_msgs/Float64MultiArray.h>
#include <tf2_eigen/tf2_eigen.h>

#include "scan_context_loop/core/keyframes.h"
#include "loop_closure/loop_pair.h"
#include "shared/stored_keyframe.h"
#include "loop_closure/topic_names.h"

namespace scan_context_loop {

LoopPublisher::LoopPublisher(const std::string& name, const Config& config, const NodeOptions& options,
                             NodeCounters* counters, MarkerPublisher* markers)
    : name_(name), config_(config), options_(options), counters_(counters), markers_(markers) {}

void LoopPublisher::advertise(const ros::NodeHandle& nh) {
  ros::NodeHandle handle(nh);
  loop_pub_ = handle.advertise<scan_context_loop::LoopClosure>(topic_names::kLoopClosures, 100);
  if (config_.verification.enabled) {
    rejected_pub_ = handle.advertise<scan_context_loop::LoopClosure>(topic_names::kLoopCandidatesRejected, 100);
  }
  if (options_.lio_sam_output) lio_pub_ = handle.advertise<std_msgs::Float64MultiArray>(topic_names::kLioLoop, 100);
  pair_pub_ = handle.advertise<geometry_msgs::PoseWithCovarianceStamped>(topic_names::kLoopClosurePairs, 200);
  array_pub_ = handle.advertise<std_msgs::Float64MultiArray>(topic_names::kLoopClosureArray, 100);
  if (options_.mode == NodeMode::kRelocalize) {
    relocalization_pub_ = handle.advertise<geometry_msgs::PoseWithCovarianceStamped>(topic_names::kRelocalization, 10);
  }
}

scan_context_loop::LoopClosure LoopPublisher::makeLoop(const Loop& found, const std::string& frame,
                                                       const Database& database) const {
  scan_context_loop::LoopClosure loop =
      loopMessage(found, frame, database.keyframe(found.query), database.keyframe(found.match), config_);
  loop.query_robot = loop.match_robot = options_.robot_id;
  return loop;
}

void LoopPublisher::publishTeamLoop(const scan_context_loop::LoopClosure& loop) {
  ++counters_->loops_found;
  ++counters_->team_loops;
  loop_pub_.publish(loop);
  if (array_pub_.getNumSubscribers() > 0) array_pub_.publish(loopArray(loop));
  ROS_INFO_THROTTLE_NAMED(1.0, name_, "loop %u -> %s's %u: yaw %.1f deg, distance %.3f, verified (fitness %.4f m^2)",
                          loop.query_id, loop.match_robot.c_str(), loop.match_id, loop.yaw * 180.0 / M_PI,
                          loop.distance, loop.fitness);
}

scan_context_loop::LoopClosure loopMessage(const Loop& found, const std::string& frame, const Keyframe& query,
                                           const Keyframe& match, const Config& config) {
  scan_context_loop::LoopClosure loop;
  loop.header.stamp = keyframeStamp(query.info);
  loop.header.frame_id = frame;
  loop.query_id = static_cast<std::uint32_t>(found.query);
  loop.match_id = static_cast<std::uint32_t>(found.match);
  loop.query_stamp = loop.header.stamp;
  loop.match_stamp = keyframeStamp(match.info);
  loop.query_session = query.session;
  loop.match_session = match.session;
  loop.distance = found.alignment.distance;
  loop.yaw = found.alignment.yaw;
  loop.shift = found.alignment.shift;
  loop.relative_pose = tf2::toMsg(found.relative());
  loop.support = static_cast<std::uint32_t>(found.support);
  const Eigen::Matrix<double, 6, 6> covariance = loopCovariance(found, config);
  for (int i = 0; i < 36; ++i) loop.covariance[i] = covariance(i / 6, i % 6);
  if (found.verified || !found.verification.reason.empty()) {
    // The registration's T_query<-match and covariance (row-major, x y z roll pitch yaw); for a
    // rejected candidate, where registration left it.
    loop.relative_pose = tf2::toMsg(found.verification.relative);
    // A verified loop's yaw is the registered one (the descriptor's prior may have been a wrong
    // column that another yaw hypothesis corrected).
    if (found.verified) {
      loop.yaw = std::atan2(found.verification.relative(1, 0), found.verification.relative(0, 0));
    }
    loop.verified = found.verified;
    loop.fitness = found.verification.fitness;
    if (!found.verified) {
      loop.rejected_by = found.verification.rejected_by;
      loop.rejection_value = found.verification.rejection_value;
      loop.rejection_limit = found.verification.rejection_limit;
      loop.rejection_reason = found.verification.reason;
    }
    return loop;
  }
  // T_query<-match from the descriptor prior (yaw, and the viewpoint's offset), large variances.
  loop.verified = false;
  loop.fitness = 0.0;
  return loop;
}

void LoopPublisher::publishRejected(const Loop& rejected, const std::string& frame, const Database& database) {
  markers_->addRejected({rejected.query, rejected.match, rejected.alignment.distance});
  if (rejected_pub_.getNumSubscribers() > 0) rejected_pub_.publish(makeLoop(rejected, frame, database));
}

void LoopPublisher::publishLoops(const Detection& detection, const std::string& frame, const Database& database) {
  // Candidates that verification turned down, and verified loops the consistency check dropped, for
  // diagnosis and RViz.
  for (const auto& v : detection.verifications) {
    // One that needs support waits in the consistency check: it is published as a loop or as dropped.
    if (!v.result.accepted && !v.result.needs_support && !v.result.odometry_contradicted) {
      publishRejected(v.toLoop(detection.index), frame, database);
    }
  }
  // A dropped loop carries the consistency check's verdict (ConsistencyFilter::advance).
  for (const Loop& dropped : detection.dropped) publishRejected(dropped, frame, database);
  for (const Loop& found : detection.loops) {
    const scan_context_loop::LoopClosure loop = makeLoop(found, frame, database);
    ++counters_->loops_found;
    markers_->addLoop({loop.query_id, loop.match_id, loop.distance});
    loop_pub_.publish(loop);
    if (array_pub_.getNumSubscribers() > 0) array_pub_.publish(loopArray(loop));
    const Eigen::Isometry3d match_pose = keyframePose(database.keyframe(found.match));
    if (pair_pub_.getNumSubscribers() > 0) {
      for (const auto& pose : loopPair(loop, match_pose)) pair_pub_.publish(pose);
    }
    const double apart =
        (keyframePosition(database.keyframe(found.query)) - keyframePosition(database.keyframe(found.match))).norm();
    if (loop.verified) {
      ROS_INFO_THROTTLE_NAMED(1.0, name_,
                              "loop %u -> %u: %.1f m apart by odometry, yaw %.1f deg, distance %.3f, verified "
                              "(fitness %.4f m^2, support %u)",
                              loop.query_id, loop.match_id, apart, loop.yaw * 180.0 / M_PI, loop.distance, loop.fitness,
                              loop.support);
    } else {
      ROS_INFO_THROTTLE_NAMED(1.0, name_, "loop %u -> %u: %.1f m apart by odometry, yaw %.1f deg, distance %.3f",
                              loop.query_id, loop.match_id, apart, loop.yaw * 180.0 / M_PI, loop.distance);
    }
    if (options_.lio_sam_output) sendToLioSam(loop);
    if (options_.mode == NodeMode::kRelocalize) publishRelocalization(loop, database);
  }
}

void LoopPublisher::sendToLioSam(const scan_context_loop::LoopClosure& loop) {
  // LIO-SAM reads its loop hook one message at a time, once per loop-closure cycle (1 Hz by default):
  // send only verified loops (all when verification is off), one per keyframe, at most one per
  // lio_sam_min_interval; the rest are skipped and counted.
  // ROS time: a bag played again with --loop goes back in time, and the interval starts afresh.
  const double now = ros::Time::now().toSec();
  const bool due = lio_interval_.due(now, options_.lio_sam_min_interval);
  if ((config_.verification.enabled && !loop.verified) || loop.query_id == lio_last_query_ || !due) {
    ++counters_->lio_skipped;
    return;
  }
  if (!lio_unheard_warned_ && lio_pub_.getNumSubscribers() == 0) {
    // Once: LIO-SAM subscribes to its hook only with loopClosureEnableFlag true (and under the topic's
    // name in its namespace), so a loop sent now is lost.
    lio_unheard_warned_ = true;
    ROS_WARN_NAMED(name_,
                   "lio_sam_output: nobody subscribes to %s, so LIO-SAM does not get this loop or the next: set "
                   "loopClosureEnableFlag: true in LIO-SAM's params.yaml and check that the topic names match "
                   "(this warning is given once)",
                   lio_pub_.getTopic().c_str());
  }
  std_msgs::Float64MultiArray hook;
  hook.data = {loop.query_stamp.toSec(), loop.match_stamp.toSec()};
  lio_pub_.publish(hook);
  lio_interval_.record(now);
  lio_last_query_ = loop.query_id;
}

void LoopPublisher::publishRelocalization(const scan_context_loop::LoopClosure& loop, const Database& database) {
  if (loop.match_session == loop.query_session || !loop.verified) return;
  geometry_msgs::PoseWithCovarianceStamped pose = loopPair(loop, keyframePose(database.keyframe(loop.match_id)))[1];
  pose.header.frame_id = options_.map_frame;
  relocalization_pub_.publish(pose);
}

}  // namespace scan_context_loop
