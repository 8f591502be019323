#include "loop_closure/keyframe_publisher.h"
#include "loop_closure/topic_names.h"

#include <nav_msgs/Odometry.h>
#include <pcl_conversions/pcl_conversions.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>

namespace scan_context_loop {

void SelectedKeyframePublisher::advertise(const ros::NodeHandle& nh) {
  ros::NodeHandle handle(nh);
  // A backend must see every keyframe: a deep queue rides out a slow subscriber's burst.
  odom_pub_ = handle.advertise<nav_msgs::Odometry>(topic_names::kSelectedKeyframeOdom, 1000);
  cloud_pub_ = handle.advertise<sensor_msgs::PointCloud2>(topic_names::kSelectedKeyframeCloud, 100);
}

void SelectedKeyframePublisher::publish(const ros::Time& stamp, const std::string& frame,
                                        const std::string& sensor_frame, const Eigen::Isometry3d& pose,
                                        const pcl::PointCloud<pcl::PointXYZ>* cloud) {
  nav_msgs::Odometry odom;
  odom.header.stamp = stamp;
  odom.header.frame_id = frame;
  odom.child_frame_id = sensor_frame;
  odom.pose.pose = tf2::toMsg(pose);
  odom_pub_.publish(odom);
  if (!cloud) return;
  sensor_msgs::PointCloud2 msg;
  pcl::toROSMsg(*cloud, msg);
  msg.header.stamp = stamp;
  msg.header.frame_id = sensor_frame;
  cloud_pub_.publish(msg);
}

}  // namespace scan_context_loop
