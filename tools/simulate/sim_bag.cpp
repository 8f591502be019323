#include "sim_bag.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

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

geometry_msgs::TransformStamped stampedTransform(const Eigen::Isometry3d& pose, const std::string& parent,
                                                 const std::string& child, const ros::Time& stamp) {
  geometry_msgs::TransformStamped t = tf2::eigenToTransform(pose);
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  return t;
}

/// The fixed transforms once, latched, on /tf_static, as tf2_ros' static broadcaster publishes them.
void writeLatched(const std::vector<FixedTransform>& fixed, const ros::Time& stamp, rosbag::Bag* bag) {
  tf2_msgs::TFMessage msg;
  for (const FixedTransform& f : fixed) msg.transforms.push_back(stampedTransform(f.pose, f.parent, f.child, stamp));
  // A connection header of our own replaces rosbag's, so it names the type too.
  auto header = boost::make_shared<ros::M_string>();
  (*header)["type"] = ros::message_traits::datatype<tf2_msgs::TFMessage>();
  (*header)["md5sum"] = ros::message_traits::md5sum<tf2_msgs::TFMessage>();
  (*header)["message_definition"] = ros::message_traits::definition<tf2_msgs::TFMessage>();
  (*header)["callerid"] = "/scan_context_simulate";
  (*header)["latching"] = "1";
  bag->write("/tf_static", stamp, msg, header);
}

/// The fixed transforms as tf1's static_transform_publisher sends them: each on /tf every period (one
/// publisher each), stamped a period ahead of when it is sent.
class RepeatedTransforms {
 public:
  RepeatedTransforms(std::vector<FixedTransform> fixed, double period, const ros::Time& start)
      : fixed_(std::move(fixed)), period_(period), next_(start) {}

  /// Writes every message due before `end`.
  void writeUntil(const ros::Time& end, rosbag::Bag* bag) {
    if (fixed_.empty() || period_ <= 0.0) return;
    for (; next_ < end; next_ += ros::Duration(period_)) {
      for (const FixedTransform& f : fixed_) {
        tf2_msgs::TFMessage msg;
        msg.transforms.push_back(stampedTransform(f.pose, f.parent, f.child, next_ + ros::Duration(period_)));
        bag->write("/tf", next_, msg);
      }
    }
  }

 private:
  std::vector<FixedTransform> fixed_;
  double period_;
  ros::Time next_;
};

/// One robot's part of the bag: its shape, its poses as its stack publishes them, its repeated tf.
struct Robot {
  const BagSequence* sequence;
  StackShape shape;
  std::string truth_topic;
  std::vector<Eigen::Isometry3d> truth, odom;
  RepeatedTransforms repeated;
};

}  // namespace

bool writeBag(const std::vector<BagSequence>& sequences, const BagOptions& options, std::string* error) {
  std::vector<Robot> robots;
  // Every keyframe of every robot, (stamp, robot, keyframe), in time order.
  std::vector<std::tuple<double, std::size_t, std::size_t>> order;
  std::vector<FixedTransform> latched;
  double first_time = std::numeric_limits<double>::infinity();
  for (const BagSequence& sequence : sequences) {
    if (sequence.truth.size() != sequence.odom.size() || sequence.truth.size() != sequence.times.size()) {
      *error = "the sequence " + sequence.dir + " has different numbers of poses and times";
      return false;
    }
    if (!sequence.times.empty()) first_time = std::min(first_time, sequence.times.front());
  }
  if (!std::isfinite(first_time)) first_time = 0.0;
  const ros::Time first(options.start_stamp + first_time);
  for (const BagSequence& sequence : sequences) {
    const StackShape shape = forRobot(options.shape, sequence.robot);
    const std::vector<FixedTransform> fixed = fixedTransforms(shape);
    // A stack whose world is its first scan's frame publishes every pose (and the truth shaped like it)
    // relative to that scan.
    std::vector<Eigen::Isometry3d> truth = sequence.truth, odom = sequence.odom;
    if (shape.world_at_first_scan && !truth.empty()) {
      const Eigen::Isometry3d truth_origin = truth.front().inverse(), odom_origin = odom.front().inverse();
      for (auto& pose : truth) pose = truth_origin * pose;
      for (auto& pose : odom) pose = odom_origin * pose;
    }
    if (shape.fixed_tf_period <= 0.0 && !truth.empty()) latched.insert(latched.end(), fixed.begin(), fixed.end());
    const ros::Time start(options.start_stamp + (sequence.times.empty() ? 0.0 : sequence.times.front()));
    RepeatedTransforms repeated(shape.fixed_tf_period > 0.0 ? fixed : std::vector<FixedTransform>(),
                                shape.fixed_tf_period, start);
    for (std::size_t k = 0; k < truth.size(); ++k) order.emplace_back(sequence.times[k], robots.size(), k);
    robots.push_back({&sequence, shape, robotTopic(sequence.robot, options.truth_topic), std::move(truth),
                      std::move(odom), std::move(repeated)});
  }
  std::stable_sort(order.begin(), order.end(),
                   [](const auto& a, const auto& b) { return std::get<0>(a) < std::get<0>(b); });
  try {
    rosbag::Bag bag(options.path, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::LZ4);
    if (!latched.empty()) writeLatched(latched, first, &bag);
    for (const auto& [time, r, k] : order) {
      Robot& robot = robots[r];
      const StackShape& shape = robot.shape;
      pcl::PointCloud<pcl::PointXYZI> cloud;
      if (!kitti::readScan(kitti::scanPath(robot.sequence->dir, static_cast<int>(k)), &cloud, error)) return false;
      if (shape.registered) {
        pcl::transformPointCloud(cloud, cloud, (odometryAxes(shape) * robot.odom[k]).matrix().cast<float>());
      }
      const ros::Time stamp(options.start_stamp + time);
      // The transforms sent up to this scan (the first scan's own included), then the scan and its pose.
      robot.repeated.writeUntil(stamp + ros::Duration(1e-6), &bag);
      sensor_msgs::PointCloud2 msg;
      pcl::toROSMsg(cloud, msg);
      msg.header.stamp = stamp;
      msg.header.frame_id = shape.cloud_frame;
      if (shape.odom_tf) {
        tf2_msgs::TFMessage tf;
        tf.transforms.push_back(
            stampedTransform(toStackPose(shape, robot.odom[k]), shape.odom_frame, shape.child_frame, stamp));
        bag.write("/tf", stamp, tf);
      }
      bag.write(shape.cloud_topic, stamp, msg);
      bag.write(shape.odom_topic, stamp, odometry(robot.odom[k], stamp, shape));
      bag.write(robot.truth_topic, stamp, odometry(robot.truth[k], stamp, shape));
    }
    bag.close();
  } catch (const std::exception& e) {
    *error = std::string("cannot write ") + options.path + ": " + e.what();
    return false;
  }
  return true;
}

bool writeBag(const std::string& sequence_dir, const std::vector<Eigen::Isometry3d>& truth,
              const std::vector<Eigen::Isometry3d>& odom, const std::vector<double>& times, const BagOptions& options,
              std::string* error) {
  return writeBag({BagSequence{sequence_dir, truth, odom, times, ""}}, options, error);
}

}  // namespace sim
}  // namespace scan_context_loop
