#include "harness.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include <pcl/common/transforms.h>
#include <pcl_conversions/pcl_conversions.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_eigen/tf2_eigen.h>

namespace scan_context_loop {
namespace test {

Harness::Harness(ros::NodeHandle nh, bool listen_lio) : nh_(nh) {
  cloud_pub = nh_.advertise<sensor_msgs::PointCloud2>("keyframe_cloud", 50);
  odom_pub = nh_.advertise<nav_msgs::Odometry>("keyframe_odom", 50);
  loop_sub_ = nh_.subscribe<scan_context_loop::LoopClosure>("loop_closures", 1000,
                                                            [this](const scan_context_loop::LoopClosure::ConstPtr& m) {
                                                              std::lock_guard<std::mutex> lock(mutex_);
                                                              loops_.push_back(*m);
                                                              last_loop_ = ros::WallTime::now();
                                                            });
  marker_sub_ = nh_.subscribe<visualization_msgs::MarkerArray>(
      "loop_markers", 10, [this](const visualization_msgs::MarkerArray::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex_);
        std::size_t points = 0;
        for (const auto& marker : m->markers) {
          markers_[{marker.ns, marker.id}] = marker;
          points += marker.points.size();
        }
        largest_marker_message_ = std::max(largest_marker_message_, points);
        ++marker_messages_;
      });
  if (listen_lio) {
    lio_sub_ = nh_.subscribe<std_msgs::Float64MultiArray>("lio_loop", 1000,
                                                        [this](const std_msgs::Float64MultiArray::ConstPtr& m) {
                                                          std::lock_guard<std::mutex> lock(mutex_);
                                                          lio_.push_back(*m);
                                                          lio_arrivals_.push_back(ros::WallTime::now().toSec());
                                                        });
  }
  pair_sub_ = nh_.subscribe<geometry_msgs::PoseWithCovarianceStamped>(
      "loop_closure_pairs", 2000, [this](const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex_);
        pairs_.push_back(*m);
      });
  timing_sub_ = nh_.subscribe<scan_context_loop::KeyframeTiming>(
      "keyframe_timing", 2000, [this](const scan_context_loop::KeyframeTiming::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex_);
        timings_.push_back(*m);
      });
}

Harness::~Harness() {
  // The subscribers are declared before the data their callbacks fill, so they would otherwise be shut
  // down last, while a spinner thread may still be writing to the vectors and maps being freed.
  for (auto* sub : {&loop_sub_, &marker_sub_, &lio_sub_, &pair_sub_, &timing_sub_}) sub->shutdown();
}

bool Harness::waitForNode(double seconds, bool poses) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    if (cloud_pub.getNumSubscribers() > 0 && (!poses || odom_pub.getNumSubscribers() > 0) &&
        loop_sub_.getNumPublishers() > 0) {
      ros::WallDuration(0.5).sleep();  // let the markers connection settle too
      return true;
    }
    ros::WallDuration(0.05).sleep();
  }
  return false;
}

sensor_msgs::PointCloud2 Harness::cloud(const Drive& drive, std::size_t k) const {
  sensor_msgs::PointCloud2 msg;
  pcl::toROSMsg(drive.scan(k), msg);
  msg.header.stamp = base + ros::Duration(drive.times[k]);
  msg.header.frame_id = "velodyne";
  return msg;
}

nav_msgs::Odometry Harness::odom(const Drive& drive, std::size_t k) const {
  nav_msgs::Odometry msg;
  msg.header.stamp = base + ros::Duration(drive.times[k]);
  msg.header.frame_id = "odom";
  msg.child_frame_id = "velodyne";
  msg.pose.pose = tf2::toMsg(odometry != nullptr ? (*odometry)[k] : drive.truth[k]);
  return msg;
}

void Harness::publish(const Drive& drive, std::size_t first, std::size_t last, double rate) {
  ros::WallRate r(rate);
  for (std::size_t k = first; k < last && ros::ok(); ++k) {
    cloud_pub.publish(cloud(drive, k));
    odom_pub.publish(odom(drive, k));
    r.sleep();
  }
}

void Harness::publishTfAndWorldClouds(const Drive& drive, double rate) {
  tf2_ros::TransformBroadcaster broadcaster;
  ros::WallRate r(rate);
  for (std::size_t k = 0; k < drive.truth.size() && ros::ok(); ++k) {
    geometry_msgs::TransformStamped t = tf2::eigenToTransform(drive.truth[k]);
    t.header.stamp = base + ros::Duration(drive.times[k]);
    t.header.frame_id = "odom";
    t.child_frame_id = "velodyne";
    broadcaster.sendTransform(t);
    pcl::PointCloud<pcl::PointXYZI> world;
    pcl::transformPointCloud(drive.scan(k), world, drive.truth[k].matrix().cast<float>());
    sensor_msgs::PointCloud2 msg;
    pcl::toROSMsg(world, msg);
    msg.header.stamp = t.header.stamp;
    msg.header.frame_id = "odom";
    // Let the transform arrive first, as a SLAM stack's tf precedes its registered cloud.
    ros::WallDuration(0.02).sleep();
    cloud_pub.publish(msg);
    r.sleep();
  }
}

DiagnosticsWatch::DiagnosticsWatch(ros::NodeHandle nh, std::string node, std::string status)
    : node_(std::move(node)),
      status_(std::move(status)),
      sub_(nh.subscribe("/diagnostics", 10, &DiagnosticsWatch::onDiagnostics, this)) {}

DiagnosticsWatch::~DiagnosticsWatch() { sub_.shutdown(); }

long DiagnosticsWatch::value(const std::string& key, const ros::WallTime& after, double seconds) const {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto it = values_.find(key);
      if (it != values_.end() && received_ > after) return std::stol(it->second);
    }
    ros::WallDuration(0.1).sleep();
  }
  return -1;
}

void DiagnosticsWatch::onDiagnostics(const diagnostic_msgs::DiagnosticArray& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& status : msg.status) {
    if (status.name.find(status_) == std::string::npos) continue;
    if (!node_.empty() && status.name.compare(0, node_.size() + 1, node_ + ":") != 0) continue;
    for (const auto& kv : status.values) values_[kv.key] = kv.value;
    received_ = ros::WallTime::now();
  }
}

void Harness::settle(double quiet, double limit) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(limit);
  while (ros::ok() && ros::WallTime::now() < end) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if ((ros::WallTime::now() - last_loop_).toSec() > quiet) return;
    }
    ros::WallDuration(0.1).sleep();
  }
}

std::vector<scan_context_loop::LoopClosure> Harness::loops() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return loops_;
}

bool Harness::waitForKeyframes(std::size_t count, double seconds) const {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    std::size_t shown = 0;
    // A team's node prefixes its namespaces with the robot ("robot1/keyframes").
    for (const auto& m : shownMarkers().markers) {
      const bool keyframes =
          m.ns == "keyframes" || (m.ns.size() > 10 && m.ns.compare(m.ns.size() - 10, 10, "/keyframes") == 0);
      shown += keyframes ? m.points.size() : 0;
    }
    if (shown >= count) return true;
    ros::WallDuration(0.1).sleep();
  }
  return false;
}

std::vector<geometry_msgs::PoseWithCovarianceStamped> Harness::loopPairs() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return pairs_;
}

std::vector<std_msgs::Float64MultiArray> Harness::lioLoops() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return lio_;
}

visualization_msgs::MarkerArray Harness::shownMarkers() const {
  std::lock_guard<std::mutex> lock(mutex_);
  visualization_msgs::MarkerArray shown;
  for (const auto& m : markers_) shown.markers.push_back(m.second);
  return shown;
}

std::size_t Harness::largestMarkerMessage() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return largest_marker_message_;
}

std::vector<scan_context_loop::KeyframeTiming> Harness::timings() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return timings_;
}

std::vector<double> Harness::lioArrivals() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return lio_arrivals_;
}

std::size_t Harness::markerMessages() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return marker_messages_;
}

int runRosTests(int argc, char** argv, const char* node_name) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, node_name);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}

int keyframeAt(const Drive& drive, const ros::Time& base, const ros::Time& stamp) {
  for (std::size_t k = 0; k < drive.times.size(); ++k) {
    if (std::fabs((base + ros::Duration(drive.times[k]) - stamp).toSec()) < 1e-6) return static_cast<int>(k);
  }
  return -1;
}

void expectTrueLoop(const Eigen::Isometry3d& query_pose, const Eigen::Isometry3d& match_pose,
                    const scan_context_loop::LoopClosure& loop) {
  const Eigen::Isometry3d truth = query_pose.inverse() * match_pose;
  if (loop.verified) {
    Eigen::Isometry3d relative;
    tf2::fromMsg(loop.relative_pose, relative);
    EXPECT_LT((relative.translation() - truth.translation()).norm(), 0.3);
  } else {
    EXPECT_LT(truth.translation().norm(), 5.0);
  }
}

void expectTrueLoop(const Drive& drive, int q, int m, const scan_context_loop::LoopClosure& loop) {
  SCOPED_TRACE("loop " + std::to_string(q) + " -> " + std::to_string(m));
  expectTrueLoop(drive.truth[q], drive.truth[m], loop);
}

void expectTrueLoops(const Drive& drive, const ros::Time& base,
                     const std::vector<scan_context_loop::LoopClosure>& loops, bool verified) {
  for (const auto& loop : loops) {
    const int q = keyframeAt(drive, base, loop.query_stamp);
    const int m = keyframeAt(drive, base, loop.match_stamp);
    ASSERT_GE(q, 0) << "a loop from an unknown keyframe";
    ASSERT_GE(m, 0) << "a loop to an unknown keyframe";
    if (verified) EXPECT_TRUE(loop.verified) << "loop " << q << " -> " << m;
    expectTrueLoop(drive, q, m, loop);
  }
}

}  // namespace test
}  // namespace scan_context_loop
