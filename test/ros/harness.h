// Publishes a simulated drive to the loop-closure node and collects what it publishes.
#pragma once

#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Float64MultiArray.h>
#include <visualization_msgs/MarkerArray.h>

#include "../common/sim_drive.h"
#include "scan_context_loop/KeyframeTiming.h"
#include "scan_context_loop/LoopClosure.h"

namespace scan_context_loop {
namespace test {

class Harness {
 public:
  /// Subscribes to the node's outputs (lio_loop only when `listen_lio`: LIO-SAM's hook unheard).
  explicit Harness(ros::NodeHandle nh, bool listen_lio = true);
  /// Unsubscribes first (waiting for a callback in progress), so that no callback runs on the members
  /// below while they are destroyed.
  ~Harness();

  /// Waits until the node subscribes to the clouds (and the poses, unless `poses` is false); false
  /// after `seconds`.
  bool waitForNode(double seconds, bool poses = true);
  /// Keyframe k of the drive as messages stamped base + times[k].
  sensor_msgs::PointCloud2 cloud(const Drive& drive, std::size_t k) const;
  nav_msgs::Odometry odom(const Drive& drive, std::size_t k) const;
  /// Publishes keyframes [first, last) at `rate` Hz, each cloud with its pose.
  void publish(const Drive& drive, std::size_t first, std::size_t last, double rate);
  /// The same with poses as tf (odom -> velodyne) and clouds registered in odom.
  void publishTfAndWorldClouds(const Drive& drive, double rate);
  /// Waits until the markers show `count` keyframes (the worker has processed them); false after
  /// `seconds`.
  bool waitForKeyframes(std::size_t count, double seconds) const;
  /// Spins until no loop arrived for `quiet` seconds (at most `limit`).
  void settle(double quiet, double limit);

  std::vector<scan_context_loop::LoopClosure> loops() const;
  std::vector<std_msgs::Float64MultiArray> lioLoops() const;
  /// The standard-type copies of the loops (loop_closure_pairs), in arrival order.
  std::vector<geometry_msgs::PoseWithCovarianceStamped> loopPairs() const;
  /// Every marker as RViz would show it now: the latest of each (namespace, id).
  visualization_msgs::MarkerArray shownMarkers() const;
  std::size_t markerMessages() const;
  /// The most points any one marker message carried (markers go out incrementally).
  std::size_t largestMarkerMessage() const;
  /// Every keyframe_timing message, in arrival order.
  std::vector<scan_context_loop::KeyframeTiming> timings() const;
  /// When each lio_loop message arrived [wall seconds].
  std::vector<double> lioArrivals() const;

  ros::Publisher cloud_pub, odom_pub;
  ros::Time base{1000.0};
  /// When set, the poses odom() sends (a drifting odometry, one per keyframe) instead of the truth.
  const std::vector<Eigen::Isometry3d>* odometry = nullptr;

 private:
  ros::NodeHandle nh_;
  ros::Subscriber loop_sub_, marker_sub_, lio_sub_, pair_sub_, timing_sub_;
  mutable std::mutex mutex_;  // guards everything below (callbacks vs. test thread)
  std::vector<scan_context_loop::LoopClosure> loops_;
  std::vector<std_msgs::Float64MultiArray> lio_;
  std::vector<geometry_msgs::PoseWithCovarianceStamped> pairs_;
  std::vector<scan_context_loop::KeyframeTiming> timings_;
  std::map<std::pair<std::string, int>, visualization_msgs::Marker> markers_;
  std::size_t marker_messages_ = 0, largest_marker_message_ = 0;
  std::vector<double> lio_arrivals_;
  ros::WallTime last_loop_ = ros::WallTime::now();
};

/// The latest values of a node's diagnostics status ("<node>: <status>", by default a loop-closure
/// node's), by key.
class DiagnosticsWatch {
 public:
  /// Watches the status of the node named `node` (its full name without the leading slash, "ns/name", as
  /// the diagnostics name it; any loop-closure node's when empty).
  explicit DiagnosticsWatch(ros::NodeHandle nh, std::string node = "", std::string status = "loop closure");
  /// Unsubscribes first (waiting for a callback in progress), as ~Harness does.
  ~DiagnosticsWatch();
  /// The integer value of `key` from a status that arrived after `after`; -1 if none within `seconds`.
  long value(const std::string& key, const ros::WallTime& after, double seconds) const;

 private:
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray& msg);
  std::string node_, status_;
  mutable std::mutex mutex_;  // guards values_ and received_ (callback thread vs. test thread)
  std::map<std::string, std::string> values_;
  ros::WallTime received_;
  // Last: subscribed once the data its callback writes exists (a message may come at once).
  ros::Subscriber sub_;
};

/// main() of a rostest node: gtest and ROS initialised, callbacks served by two threads.
int runRosTests(int argc, char** argv, const char* node_name);

/// Index of the keyframe published with this stamp, or -1.
int keyframeAt(const Drive& drive, const ros::Time& base, const ros::Time& stamp);

/// Expects a loop between keyframes at these true LiDAR poses to be true: a verified loop is a constraint,
/// so its registered pose must be the true one within 0.3 m (however far apart the keyframes are); a
/// descriptor loop must join keyframes under 5 m apart.
void expectTrueLoop(const Eigen::Isometry3d& query_pose, const Eigen::Isometry3d& match_pose,
                    const scan_context_loop::LoopClosure& loop);
/// The same for loop q -> m of the drive.
void expectTrueLoop(const Drive& drive, int q, int m, const scan_context_loop::LoopClosure& loop);
/// expectTrueLoop for every loop (each must join two published keyframes), and each verified when
/// `verified` is set.
void expectTrueLoops(const Drive& drive, const ros::Time& base,
                     const std::vector<scan_context_loop::LoopClosure>& loops, bool verified);

}  // namespace test
}  // namespace scan_context_loop
