#include "loop_closure/corrected_poses.h"

#include <cmath>

#include <ros/console.h>

#include "shared/frame_ids.h"
#include "shared/stored_keyframe.h"

namespace scan_context_loop {

namespace {

/// How far a pose's quaternion may be from unit length and still be taken (normalised) as a rotation.
constexpr double kQuaternionTolerance = 1e-3;

/// The pose of `pose`, or why it is no sensor pose.
std::string poseOf(const geometry_msgs::Pose& pose, Eigen::Isometry3d* out) {
  const Eigen::Vector3d p(pose.position.x, pose.position.y, pose.position.z);
  Eigen::Quaterniond q(pose.orientation.w, pose.orientation.x, pose.orientation.y, pose.orientation.z);
  if (!p.allFinite() || !q.coeffs().allFinite()) return "a value that is not finite";
  if (!(std::abs(q.norm() - 1.0) <= kQuaternionTolerance)) return "an orientation that is not a unit quaternion";
  q.normalize();
  *out = Eigen::Isometry3d::Identity();
  out->linear() = q.toRotationMatrix();
  out->translation() = p;
  return "";
}

}  // namespace

bool CorrectedPoses::offer(const nav_msgs::PathConstPtr& path) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_ = path;
  if (queued_) return false;
  queued_ = true;
  return true;
}

void CorrectedPoses::applyNewest(const Database& database) {
  nav_msgs::PathConstPtr path;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    path.swap(pending_);
    queued_ = false;
  }
  if (path) apply(*path, database);
}

void CorrectedPoses::loaded(const Database& database, std::size_t first) {
  for (std::size_t i = first; i < database.size(); ++i) loaded_.insert(database.keyframe(i).session);
}

void CorrectedPoses::reset() {
  frame_.clear();
  by_stamp_.clear();
  sessions_.clear();
  loaded_.clear();
  indexed_ = 0;
  corrections_.reset();
  ++version_;
  counters_->corrected_keyframes = 0;
}

void CorrectedPoses::index(const Database& database) {
  for (; indexed_ < database.size(); ++indexed_) {
    const Keyframe& k = database.keyframe(indexed_);
    if (loaded_.count(k.session) != 0) continue;
    by_stamp_[keyframeStamp(k.info).toNSec()].push_back(indexed_);
    auto [range, added] = sessions_.emplace(k.session, std::make_pair(indexed_, indexed_ + 1));
    if (!added) range->second.second = indexed_ + 1;
  }
}

void CorrectedPoses::unknown(std::size_t count) {
  counters_->corrections_unknown += count;
  ROS_DEBUG_THROTTLE_NAMED(5.0, name_,
                           "corrected_path: %zu poses skipped: their stamps name no keyframe recorded here "
                           "(%zu so far)",
                           count, counters_->corrections_unknown.load());
}

void CorrectedPoses::refuse(std::size_t count, const std::string& why) {
  counters_->corrections_refused += count;
  ROS_ERROR_THROTTLE_NAMED(5.0, name_, "corrected_path: %s (%zu poses or paths refused so far)", why.c_str(),
                           counters_->corrections_refused.load());
}

void CorrectedPoses::apply(const nav_msgs::Path& path, const Database& database) {
  if (path.poses.empty()) return refuse(1, "an empty path skipped");
  const std::string frame = normaliseFrameId(path.header.frame_id);
  if (frame.empty()) return refuse(1, "a path without a frame_id skipped");
  if (!frame_.empty() && frame != frame_) {
    return refuse(1, "a path in frame \"" + frame + "\" skipped: the corrections so far are in \"" + frame_ + "\"");
  }
  index(database);
  // The session: the newest recorded one holding the first stamp that names a keyframe recorded here.
  const std::pair<std::size_t, std::size_t>* session = nullptr;
  for (const auto& pose : path.poses) {
    const auto found = by_stamp_.find(pose.header.stamp.toNSec());
    if (found == by_stamp_.end()) continue;
    session = &sessions_.at(database.keyframe(found->second.back()).session);
    break;
  }
  // A path none of whose stamps names a keyframe recorded here is no error: a backend that was not reset
  // goes on publishing the keyframes a ~reset forgot.
  if (!session) return unknown(path.poses.size());
  const auto [begin, end] = *session;
  PoseCorrections next;
  if (corrections_) {
    next = *corrections_;
    next.erase(next.lower_bound(begin), next.lower_bound(end));
  }
  std::size_t unnamed = 0, elsewhere = 0, unusable = 0, accepted = 0;
  std::string problem;
  for (const auto& stamped : path.poses) {
    const auto found = by_stamp_.find(stamped.header.stamp.toNSec());
    if (found == by_stamp_.end()) {
      ++unnamed;
      continue;
    }
    std::size_t index = end;
    for (std::size_t i : found->second) index = i >= begin && i < end ? i : index;
    if (index == end) {
      ++elsewhere;
      continue;
    }
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    if (const std::string why = poseOf(stamped.pose, &pose); !why.empty()) {
      ++unusable;
      problem = why;
      continue;
    }
    next[index] = pose;
    ++accepted;
  }
  if (unusable > 0) {
    refuse(unusable, std::to_string(unusable) + " poses skipped: the last had " + problem);
  }
  if (elsewhere > 0) {
    refuse(elsewhere, std::to_string(elsewhere) +
                          " poses skipped: their stamps name keyframes of another session "
                          "than the one this path corrects (recorded here, keyframes " +
                          std::to_string(begin) + " to " + std::to_string(end - 1) + ")");
  }
  if (unnamed > 0) unknown(unnamed);
  if (accepted == 0) return;
  frame_ = frame;
  corrections_ = std::make_shared<const PoseCorrections>(std::move(next));
  ++version_;
  counters_->corrected_keyframes = corrections_->size();
}

}  // namespace scan_context_loop
