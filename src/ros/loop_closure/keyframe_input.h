// The node's keyframe input: the cloud and odometry subscriptions (message_filters' synchroniser in odom
// mode, the cloud alone in tf mode), the callbacks that check what arrived and queue it for the worker,
// and the timers that warn when the inputs are silent or never pair.
#pragma once

#include <memory>
#include <string>

#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include "loop_closure/keyframe_queue.h"
#include "loop_closure/node_counters.h"
#include "shared/parameters.h"

namespace scan_context_loop {

/// Its callbacks run on the spinner threads and touch only the queue (thread-safe), the counters
/// (atomics) and the options, which they only read (none of those they read is live).
class KeyframeInput {
 public:
  /// `nh` resolves the topics; `name` prefixes the logs. The others must outlive this.
  KeyframeInput(const ros::NodeHandle& nh, const std::string& name, const NodeOptions& options, KeyframeQueue* queue,
                NodeCounters* counters);
  /// Subscribes and starts the input checks.
  void start();
  /// Unsubscribes and stops the checks.
  void stop();
  /// The resolved cloud topic, and where the poses come from (the odometry topic, or "tf (frame)").
  std::string cloudTopic() const;
  std::string poseSource() const;

 private:
  using ApproxPolicy = message_filters::sync_policies::ApproximateTime<sensor_msgs::PointCloud2, nav_msgs::Odometry>;
  using ExactPolicy = message_filters::sync_policies::ExactTime<sensor_msgs::PointCloud2, nav_msgs::Odometry>;

  void onCloudAndOdom(const sensor_msgs::PointCloud2ConstPtr& cloud, const nav_msgs::OdometryConstPtr& odom);
  void onCloudOnly(const sensor_msgs::PointCloud2ConstPtr& cloud);
  void onAnyCloud(const sensor_msgs::PointCloud2ConstPtr& cloud);
  void onAnyOdom(const nav_msgs::OdometryConstPtr& odom);
  void enqueue(QueuedKeyframe keyframe);
  void checkSynchronisation(const ros::WallTimerEvent&);
  /// Warns, naming the topic, when no cloud (odom mode: no odometry either) came for no_input_warning s.
  void checkInputs(const ros::WallTimerEvent&);

  ros::NodeHandle nh_;
  std::string name_;
  const NodeOptions& options_;
  KeyframeQueue* queue_;
  NodeCounters* counters_;
  message_filters::Subscriber<sensor_msgs::PointCloud2> cloud_sub_;
  message_filters::Subscriber<nav_msgs::Odometry> odom_sub_;
  std::unique_ptr<message_filters::Synchronizer<ApproxPolicy>> approx_sync_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_sync_;
  ros::Subscriber cloud_only_sub_;
  ros::WallTimer sync_timer_, input_timer_;
  double start_wall_ = 0.0;  // when start() subscribed (set before any callback)
};

}  // namespace scan_context_loop
