#include "sim_bag.h"

#include <nav_msgs/Odometry.h>
#include <pcl_conversions/pcl_conversions.h>
#include <rosbag/bag.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>

#include "scan_context_common/kitti_io.h"

namespace scan_context_loop {
namespace sim {

namespace {

nav_msgs::Odometry odometry(const Eigen::Isometry3d& pose, const ros::Time& stamp, const BagOptions& o) {
  nav_msgs::Odometry msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = o.odom_frame;
  msg.child_frame_id = o.sensor_frame;
  msg.pose.pose = tf2::toMsg(pose);
  return msg;
}

}  // namespace

bool writeBag(const std::string& sequence_dir, const std::vector<Eigen::Isometry3d>& truth,
              const std::vector<Eigen::Isometry3d>& odom, const std::vector<double>& times, const BagOptions& options,
              std::string* error) {
  try {
    rosbag::Bag bag(options.path, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::LZ4);
    for (std::size_t k = 0; k < truth.size(); ++k) {
      pcl::PointCloud<pcl::PointXYZI> cloud;
      if (!kitti::readScan(kitti::scanPath(sequence_dir, static_cast<int>(k)), &cloud, error)) return false;
      const ros::Time stamp(options.start_stamp + times[k]);
      sensor_msgs::PointCloud2 msg;
      pcl::toROSMsg(cloud, msg);
      msg.header.stamp = stamp;
      msg.header.frame_id = options.sensor_frame;
      bag.write(options.cloud_topic, stamp, msg);
      bag.write(options.odom_topic, stamp, odometry(odom[k], stamp, options));
      bag.write(options.truth_topic, stamp, odometry(truth[k], stamp, options));
    }
    bag.close();
  } catch (const std::exception& e) {
    *error = std::string("cannot write ") + options.path + ": " + e.what();
    return false;
  }
  return true;
}

}  // namespace sim
}  // namespace scan_context_loop
