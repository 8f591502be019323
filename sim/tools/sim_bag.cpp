#include "sim_bag.h"

#include <nav_msgs/Odometry.h>
#include <pcl/common/transforms.h>
#include <pcl_conversions/pcl_conversions.h>
#include <rosbag/bag.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

#include "scan_context_loop/eval/kitti_io.h"

namespace scan_context_loop {
namespace sim {

namespace {

nav_msgs::Odometry odometry(const Eigen::Isometry3d& lidar_pose, const ros::Time& stamp, const StackShape& shape) {
  nav_msgs::Odometry msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = shape.odom_frame;
  msg.child_frame_id = shape.child_frame;
  msg.pose.pose = tf2::toMsg(toStackPose(shape, lidar_pose));
  return msg;
}

/// The static tf child_frame -> cloud_frame, latched as tf2_ros' static broadcaster publishes it.
void writeExtrinsic(const StackShape& shape, const ros::Time& stamp, rosbag::Bag* bag) {
  tf2_msgs::TFMessage msg;
  msg.transforms.push_back(tf2::eigenToTransform(odometryAxes(shape)));
  msg.transforms.back().header.stamp = stamp;
  msg.transforms.back().header.frame_id = shape.child_frame;
  msg.transforms.back().child_frame_id = shape.cloud_frame;
  // A connection header of our own replaces rosbag's, so it names the type too.
  auto header = boost::make_shared<ros::M_string>();
  (*header)["type"] = ros::message_traits::datatype<tf2_msgs::TFMessage>();
  (*header)["md5sum"] = ros::message_traits::md5sum<tf2_msgs::TFMessage>();
  (*header)["message_definition"] = ros::message_traits::definition<tf2_msgs::TFMessage>();
  (*header)["callerid"] = "/scan_context_simulate";
  (*header)["latching"] = "1";
  bag->write("/tf_static", stamp, msg, header);
}

}  // namespace

bool writeBag(const std::string& sequence_dir, const std::vector<Eigen::Isometry3d>& truth,
              const std::vector<Eigen::Isometry3d>& odom, const std::vector<double>& times, const BagOptions& options,
              std::string* error) {
  const StackShape& shape = options.shape;
  try {
    rosbag::Bag bag(options.path, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::LZ4);
    if (shape.camera_axes && !truth.empty()) writeExtrinsic(shape, ros::Time(options.start_stamp + times[0]), &bag);
    for (std::size_t k = 0; k < truth.size(); ++k) {
      pcl::PointCloud<pcl::PointXYZI> cloud;
      if (!kitti::readScan(kitti::scanPath(sequence_dir, static_cast<int>(k)), &cloud, error)) return false;
      if (shape.registered) {
        pcl::transformPointCloud(cloud, cloud, (odometryAxes(shape) * odom[k]).matrix().cast<float>());
      }
      const ros::Time stamp(options.start_stamp + times[k]);
      sensor_msgs::PointCloud2 msg;
      pcl::toROSMsg(cloud, msg);
      msg.header.stamp = stamp;
      msg.header.frame_id = shape.cloud_frame;
      bag.write(shape.cloud_topic, stamp, msg);
      bag.write(shape.odom_topic, stamp, odometry(odom[k], stamp, shape));
      bag.write(options.truth_topic, stamp, odometry(truth[k], stamp, shape));
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
