// The keyframes the node selected, for a backend behind any odometry stack: each keyframe that entered
// the database on selected_keyframe_odom (its sensor pose, the extrinsic applied) and, while someone
// subscribes, selected_keyframe_cloud (its points in the sensor frame as described).
#pragma once

#include <string>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <ros/ros.h>

namespace scan_context_loop {

/// Worker-only but advertise(): the publishers (thread-safe handles) are its only state.
class SelectedKeyframePublisher {
 public:
  /// Advertises both topics.
  void advertise(const ros::NodeHandle& nh);
  /// Whether the cloud is wanted: someone subscribes to selected_keyframe_cloud.
  bool cloudListened() const { return cloud_pub_.getNumSubscribers() > 0; }
  /// Publishes keyframe at `stamp`: T_frame<-sensor as `pose`, and `cloud` (sensor frame) unless it is null.
  void publish(const ros::Time& stamp, const std::string& frame, const std::string& sensor_frame,
               const Eigen::Isometry3d& pose, const pcl::PointCloud<pcl::PointXYZ>* cloud);

 private:
  ros::Publisher odom_pub_, cloud_pub_;
};

}  // namespace scan_context_loop
