// PoseGraphRos's worker: the only thread that touches the graph and the map.
#include <algorithm>
#include <chrono>
#include <cstring>

#include <nav_msgs/Path.h>
#include <pcl_conversions/pcl_conversions.h>
#include <tf2_eigen/tf2_eigen.h>
#include <visualization_msgs/MarkerArray.h>

#include "shared/cloud_input.h"
#include "shared/exception_barrier.h"
#include "shared/frame_ids.h"
#include "pose_graph/pose_graph_ros.h"
#include "shared/pose_input.h"
#include "pose_graph/pose_graph_robots.h"

namespace scan_context_loop {

namespace {

/// Loops and clouds that came before their keyframes wait at most this many (the oldest go first).
constexpr std::size_t kMaxWaiting = 1000;
/// Paths and markers go out at most this often while messages keep coming [s]; once the queue is empty
/// the latest state always goes out.
constexpr double kPublishPeriod = 1.0;

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
    addKeyframe(*event.odom, &robots_[event.robot]);
  } else if (event.cloud) {
    addCloud(*event.cloud, &robots_[event.robot]);
  } else if (event.loop) {
    if (!addLoop(*event.loop, event.robot)) {
      if (waiting_.size() >= kMaxWaiting) waiting_.erase(waiting_.begin());
      waiting_.push_back({*event.loop, event.robot});
    }
    loops_waiting_ = waiting_.size();
  }
}

void PoseGraphRos::addKeyframe(const nav_msgs::Odometry& msg, GraphRobot* robot) {
  const ros::Time stamp = msg.header.stamp;
  const char* of = robot->id.empty() ? "" : " of robot ";
  if (!robot->stamps.empty() && stamp <= robot->stamps.back()) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_,
                             "keyframe%s%s at %.3f skipped: its stamp is not after the last one (%.3f); the "
                             "reference graph holds one session",
                             of, robot->id.c_str(), stamp.toSec(), robot->stamps.back().toSec());
    return;
  }
  const std::string frame = normaliseFrameId(msg.header.frame_id);
  if (!robot->odom_frame.empty() && frame != robot->odom_frame) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe%s%s at %.3f skipped: its frame %s is not the odometry frame %s", of,
                             robot->id.c_str(), stamp.toSec(), frame.c_str(), robot->odom_frame.c_str());
    return;
  }
  Eigen::Isometry3d pose;
  std::string why;
  long index = -1;
  if (!poseFromMsg(msg.pose.pose, &pose, &why) || (index = graph_->addKeyframe(pose, robot->chain)) < 0) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "keyframe%s%s at %.3f skipped: its pose is unusable: %s", of,
                             robot->id.c_str(), stamp.toSec(), why.c_str());
    return;
  }
  robot->odom_frame = frame;
  robot->stamps.push_back(stamp);
  robot->keyframes.push_back(static_cast<std::size_t>(index));
  keyframes_ = graph_->size();
  // A cloud may have come first (separate topics); and loops wait for both their keyframes.
  for (auto it = robot->early_clouds.begin(); it != robot->early_clouds.end();) {
    if (robot->keyframeAt((*it)->header.stamp, options_.stamp_tolerance) >= 0) {
      addCloud(**it, robot);
      it = robot->early_clouds.erase(it);
    } else {
      ++it;
    }
  }
  retryWaitingLoops();
}

void PoseGraphRos::addCloud(const sensor_msgs::PointCloud2& msg, GraphRobot* robot) {
  const long index = robot->keyframeAt(msg.header.stamp, options_.stamp_tolerance);
  if (index < 0) {
    // Not a keyframe yet: its pose may follow. Clouds older than the newest keyframe never match one.
    if (robot->stillToCome(msg.header.stamp)) {
      if (robot->early_clouds.size() >= 50) robot->early_clouds.pop_front();
      robot->early_clouds.push_back(boost::make_shared<sensor_msgs::PointCloud2>(msg));
    }
    return;
  }
  PointView view;
  std::string why;
  if (!viewCloud(msg, &view, &why)) {
    ++rejected_;
    ROS_ERROR_THROTTLE_NAMED(5.0, name_, "cloud at %.3f left out of the map: %s", msg.header.stamp.toSec(),
                             why.c_str());
    return;
  }
  std::vector<Eigen::Vector3f> points(view.count);
  for (std::size_t i = 0; i < view.count; ++i) {
    const std::uint8_t* p = view.data + i * view.stride;
    std::memcpy(points[i].data(), p + view.offset_x, 4);
    std::memcpy(points[i].data() + 1, p + view.offset_y, 4);
    std::memcpy(points[i].data() + 2, p + view.offset_z, 4);
  }
  // The stride counts each robot's own keyframes (the single robot's are the graph's).
  const auto own = std::lower_bound(robot->keyframes.begin(), robot->keyframes.end(), static_cast<std::size_t>(index));
  if (map_->add(static_cast<std::size_t>(index), points, team_ ? own - robot->keyframes.begin() : -1) > 0) {
    map_changed_ = true;
  }
  map_points_ = map_->points();
}

bool PoseGraphRos::addLoop(const scan_context_loop::LoopClosure& msg, std::size_t came_on) {
  // Without robots the robot fields are not read: every loop is the single robot's.
  const long qr = team_ ? robotNamed(robots_, msg.query_robot, came_on) : 0;
  const long mr = team_ ? robotNamed(robots_, msg.match_robot, came_on) : 0;
  if (qr < 0 || mr < 0) {
    ++rejected_;
    ROS_WARN_THROTTLE_NAMED(5.0, name_, "loop %u -> %u left out: robot %s is not one of robots", msg.query_id,
                            msg.match_id, (qr < 0 ? msg.query_robot : msg.match_robot).c_str());
    return true;
  }
  const GraphRobot &query_robot = robots_[qr], &match_robot = robots_[mr];
  const long query = query_robot.keyframeAt(msg.query_stamp, options_.stamp_tolerance);
  const long match = match_robot.keyframeAt(msg.match_stamp, options_.stamp_tolerance);
  if (query < 0 || match < 0) {
    // Its keyframes are still to come (both of one robot: the later stamp decides, as without robots).
    if (qr == mr ? query_robot.stillToCome(std::max(msg.query_stamp, msg.match_stamp))
                 : (query < 0 && query_robot.stillToCome(msg.query_stamp)) ||
                       (match < 0 && match_robot.stillToCome(msg.match_stamp))) {
      return false;
    }
    ++rejected_;
    ROS_WARN_THROTTLE_NAMED(5.0, name_,
                            "loop %u -> %u left out: no keyframe at its stamps %.3f / %.3f (another "
                            "session, or a keyframe this node skipped)",
                            msg.query_id, msg.match_id, msg.query_stamp.toSec(), msg.match_stamp.toSec());
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
  std::vector<WaitingLoop> still;
  for (const auto& loop : waiting_) {
    if (!addLoop(loop.msg, loop.robot)) still.push_back(loop);
  }
  waiting_.swap(still);
  loops_waiting_ = waiting_.size();
}

}  // namespace scan_context_loop
