#include "scan_context_loop/ros/keyframe_publisher.h"

#include <nav_msgs/Odometry.h>
#include <pcl_conversions/pcl_conversions.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>

namespace scan_context_loop {

void SelectedKeyframePublisher::advertise(const ros::NodeHandle& nh) {
  ros::NodeHandle handle(nh);
  // A backend must see every keyframe: a deep queue rides out a slow subscriber's burst.
  odom_pub_ = handle.advertise<nav_msgs::Odometry>("selected_keyframe_odom", 1000);
  cloud_pub_ = handle.advertise<sensor_msgs::PointCloud2>("selected_keyframe_cloud", 100);
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
