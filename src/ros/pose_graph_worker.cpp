// PoseGraphRos's worker: the only thread that touches the graph and the map.
#include <algorithm>
#include <chrono>
#include <cstring>

#include <nav_msgs/Path.h>
#include <pcl_conversions/pcl_conversions.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>

#include "scan_context_loop/ros/cloud_input.h"
#include "scan_context_loop/ros/exception_barrier.h"
#include "scan_context_loop/ros/frame_ids.h"
#include "scan_context_loop/ros/pose_graph_ros.h"
#include "scan_context_loop/ros/pose_input.h"

namespace scan_context_loop {

namespace {

/// Loops and clouds that came before their keyframes wait at most this many (the oldest go first).
constexpr std::size_t kMaxWaiting = 1000;
/// Paths and markers go out at most this often while messages keep coming [s]; once the queue is empty
/// the latest state always goes out.
constexpr double kPublishPeriod = 1.0;

nav_msgs::Path makePath(const std::vector<Eigen::Isometry3d>& poses, const std::vector<ros::Time>& stamps,
                        const std::string& frame) {
  nav_msgs::Path path;
  path.header.frame_id = frame;
  path.header.stamp = stamps.empty() ? ros::Time() : stamps.back();
  path.poses.resize(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    path.poses[i].header.frame_id = frame;
    path.poses[i].header.stamp = stamps[i];
    path.poses[i].pose = tf2::toMsg(poses[i]);
  }
  return path;
}

}  // namespace

void PoseGraphRos::work() {
  bool changed = false;  // paths and markers behind the graph
  ros::WallTime last_publish;
  while (true) {
    std::deque<Event> batch;
    {
      std::unique_lock<std::mutex> lock(queue_mutex_);
      // While a solve is held back by min_solve_interval, wake up when it is due.
      const auto wait = std::chrono::milliseconds(solve_pending_ ? 50 : 500);
      queue_cv_.wait_for(lock, wait, [this] { return stop_ || !queue_.empty(); });
      if (stop_) {
        // With a map to save at shutdown, what came before the stop goes into it (no publishing).
        if (!options_.map_save.empty()) batch.swap(queue_);
        lock.unlock();
        handleBatch(batch, &changed);
        return;
      }
      batch.swap(queue_);
    }
    const bool map_asked = handleBatch(batch, &changed);
    const ros::WallTime now = ros::WallTime::now();
    const bool idle = batch.empty();
    const bool solve = solve_pending_ && (now - last_solve_).toSec() >= options_.min_solve_interval;
    if (solve || (changed && (idle || (now - last_publish).toSec() >= kPublishPeriod))) {
      std::string what;
      if (!runCatching([&] { solveAndPublish(solve); }, &what)) {
        ROS_ERROR_THROTTLE_NAMED(5.0, name_, "solving or publishing threw: %s (the graph is kept)", what.c_str());
      }
      changed = false;
      last_publish = now;
    }
    const bool map_due = options_.map_period > 0.0 && map_changed_ && map_pub_.getNumSubscribers() > 0 &&
                         (now - last_map_).toSec() >= options_.map_period;
    if (map_asked || map_due) {
      std::string what;
      if (!runCatching([&] { publishMap(); }, &what)) {
        ROS_ERROR_THROTTLE_NAMED(5.0, name_, "the map was not published: %s", what.c_str());
      }
    }
  }
}

bool PoseGraphRos::handleBatch(const std::deque<Event>& batch, bool* changed) {
  bool map_asked = false;
  for (const Event& event : batch) {
    if (event.publish_map) {
      map_asked = true;
      continue;
    }
    if (event.task) {
      event.task();  // runOnWorker's: catches what it throws itself
      continue;
    }
    std::string what;
    if (!runCatching([&] { handle(event); }, &what)) {
      ++rejected_;
      ROS_ERROR_THROTTLE_NAMED(5.0, name_, "a message was dropped: handling it threw: %s", what.c_str());
    }
    *changed = true;
  }
  return map_asked;
}

void PoseGraphRos::handle(const Event& event) {
  if (event.odom) {
    addKeyframe(*event.odom);
  } else if (event.cloud) {
    addCloud(*event.cloud);
  } else if (event.loop) {
    if (!addLoop(*event.loop)) {
      if (waiting_.size() >= kMaxWaiting) waiting_.erase(waiting_.begin());
      waiting_.push_back(*event.loop);
    }
    loops_waiting_ = waiting_.size();
  }
}

void PoseGraphRos::addKeyframe(const nav_msgs::Odometry& msg) {
  const ros::Time stamp = msg.header.stamp;
  if (!stamps_.empty() && stamp <= stamps_.back()) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: its stamp is not after the last one (%.3f); the "
                             "reference graph holds one session", stamp.toSec(), stamps_.back().toSec());
    return;
  }
  const std::string frame = normaliseFrameId(msg.header.frame_id);
  if (!odom_frame_.empty() && frame != odom_frame_) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: its frame %s is not the odometry frame %s",
                             stamp.toSec(), frame.c_str(), odom_frame_.c_str());
    return;
  }
  Eigen::Isometry3d pose;
  std::string why;
  if (!poseFromMsg(msg.pose.pose, &pose, &why) || graph_->addKeyframe(pose) < 0) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe at %.3f skipped: its pose is unusable: %s", stamp.toSec(),
                             why.c_str());
    return;
  }
  if (odom_frame_.empty()) {
    std::lock_guard<std::mutex> lock(correction_mutex_);
    odom_frame_ = frame;
  }
  stamps_.push_back(stamp);
  keyframes_ = stamps_.size();
  // A cloud may have come first (separate topics); and loops wait for both their keyframes.
  for (auto it = early_clouds_.begin(); it != early_clouds_.end();) {
    if (keyframeAt((*it)->header.stamp) >= 0) {
      addCloud(**it);
      it = early_clouds_.erase(it);
    } else {
      ++it;
    }
  }
  retryWaitingLoops();
}

void PoseGraphRos::addCloud(const sensor_msgs::PointCloud2& msg) {
  const long index = keyframeAt(msg.header.stamp);
  if (index < 0) {
    // Not a keyframe yet: its pose may follow. Clouds older than the newest keyframe never match one.
    if (stamps_.empty() || msg.header.stamp > stamps_.back()) {
      if (early_clouds_.size() >= 50) early_clouds_.pop_front();
      early_clouds_.push_back(boost::make_shared<sensor_msgs::PointCloud2>(msg));
    }
    return;
  }
  PointView view;
  std::string why;
  if (!viewCloud(msg, &view, &why)) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "cloud at %.3f left out of the map: %s", msg.header.stamp.toSec(), why.c_str());
    return;
  }
  std::vector<Eigen::Vector3f> points(view.count);
  for (std::size_t i = 0; i < view.count; ++i) {
    const std::uint8_t* p = view.data + i * view.stride;
    std::memcpy(points[i].data(), p + view.offset_x, 4);
    std::memcpy(points[i].data() + 1, p + view.offset_y, 4);
    std::memcpy(points[i].data() + 2, p + view.offset_z, 4);
  }
  if (map_->add(static_cast<std::size_t>(index), points) > 0) map_changed_ = true;
  map_points_ = map_->points();
}

bool PoseGraphRos::addLoop(const scan_context_loop::LoopClosure& msg) {
  const long query = keyframeAt(msg.query_stamp);
  const long match = keyframeAt(msg.match_stamp);
  if (query < 0 || match < 0) {
    const ros::Time latest = std::max(msg.query_stamp, msg.match_stamp);
    if (stamps_.empty() || latest > stamps_.back()) return false;  // its keyframes are still to come
    ++rejected_;
    ROS_WARN_THROTTLE_NAMED(5.0, name_, "loop %u -> %u left out: no keyframe at its stamps %.3f / %.3f (another "
                            "session, or a keyframe this node skipped)", msg.query_id, msg.match_id,
                            msg.query_stamp.toSec(), msg.match_stamp.toSec());
    return true;
  }
  Eigen::Isometry3d relative;
  std::string why;
  Matrix6d covariance;
  for (int i = 0; i < 36; ++i) covariance(i / 6, i % 6) = msg.covariance[i];
  if (!poseFromMsg(msg.relative_pose, &relative, &why) ||
      !graph_->addLoop(static_cast<std::size_t>(query), static_cast<std::size_t>(match), relative, covariance, &why)) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "loop %u -> %u left out: %s", msg.query_id, msg.match_id, why.c_str());
    return true;
  }
  used_.push_back({static_cast<std::size_t>(query), static_cast<std::size_t>(match), static_cast<bool>(msg.verified)});
  loops_used_ = used_.size();
  solve_pending_ = true;
  return true;
}

void PoseGraphRos::retryWaitingLoops() {
  if (waiting_.empty()) return;
  std::vector<scan_context_loop::LoopClosure> still;
  for (const auto& loop : waiting_) {
    if (!addLoop(loop)) still.push_back(loop);
  }
  waiting_.swap(still);
  loops_waiting_ = waiting_.size();
}

long PoseGraphRos::keyframeAt(const ros::Time& stamp) const {
  const ros::Duration tolerance(options_.stamp_tolerance);
  auto it = std::lower_bound(stamps_.begin(), stamps_.end(), stamp - tolerance);
  if (it == stamps_.end() || *it > stamp + tolerance) return -1;
  // The nearest within the tolerance (keyframes closer together than it are ambiguous; take the nearest).
  auto best = it;
  for (++it; it != stamps_.end() && *it <= stamp + tolerance; ++it) {
    if ((*it - stamp).toSec() * (*it - stamp).toSec() < (*best - stamp).toSec() * (*best - stamp).toSec()) best = it;
  }
  return static_cast<long>(best - stamps_.begin());
}

void PoseGraphRos::solveAndPublish(bool solve) {
  if (graph_->size() == 0) return;
  if (solve) {
    const PoseGraphResult result = graph_->optimize();
    last_solve_ = ros::WallTime::now();
    solve_pending_ = false;
    ++solves_;
    last_solve_ms_ = result.seconds * 1e3;
    last_cost_ = result.final_cost;
    map_changed_ = true;
    if (!result.solved) {
      ROS_WARN_THROTTLE_NAMED(5.0, name_, "the solve did not converge (%s); the last estimate is kept",
                              result.message.c_str());
    }
  }
  const std::vector<Eigen::Isometry3d> poses = graph_->poses();
  {
    std::lock_guard<std::mutex> lock(correction_mutex_);
    correction_ = graph_->correction();
    have_correction_ = true;
  }
  path_pub_.publish(makePath(poses, stamps_, options_.map_frame));
  std::vector<Eigen::Isometry3d> odometry(graph_->size());
  for (std::size_t i = 0; i < odometry.size(); ++i) odometry[i] = graph_->odometryPose(i);
  odometry_path_pub_.publish(makePath(odometry, stamps_, options_.map_frame));

  // The loops between the corrected poses: verified green, unverified (verified_only false) orange.
  visualization_msgs::MarkerArray markers;
  for (const bool verified : {true, false}) {
    visualization_msgs::Marker lines;
    lines.header.frame_id = options_.map_frame;
    lines.header.stamp = stamps_.back();
    lines.ns = verified ? "verified loops" : "unverified loops";
    lines.id = 0;
    lines.type = visualization_msgs::Marker::LINE_LIST;
    lines.action = visualization_msgs::Marker::ADD;
    lines.pose.orientation.w = 1.0;
    lines.scale.x = 1.5;
    lines.color.a = 1.0;
    lines.color.r = verified ? 0.1f : 1.0f;
    lines.color.g = verified ? 0.9f : 0.55f;
    lines.color.b = 0.1f;
    for (const auto& loop : used_) {
      if (loop.verified != verified) continue;
      lines.points.push_back(tf2::toMsg(Eigen::Vector3d(poses[loop.query].translation())));
      lines.points.push_back(tf2::toMsg(Eigen::Vector3d(poses[loop.match].translation())));
    }
    if (lines.points.empty()) lines.action = visualization_msgs::Marker::DELETE;
    markers.markers.push_back(lines);
  }
  marker_pub_.publish(markers);
}

void PoseGraphRos::publishMap() {
  const auto cloud = map_->assemble(graph_->poses());
  sensor_msgs::PointCloud2 msg;
  pcl::toROSMsg(cloud, msg);
  msg.header.frame_id = options_.map_frame;
  msg.header.stamp = stamps_.empty() ? ros::Time() : stamps_.back();
  map_pub_.publish(msg);
  last_map_ = ros::WallTime::now();
  map_changed_ = false;
}

}  // namespace scan_context_loop
