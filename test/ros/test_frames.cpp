// rostest: frame ids with tf1's leading '/' in, tf2's names out (loops, their standard-type copies,
// markers, timing, the selected keyframes); the extrinsic sent tf1's way (repeated on /tf, slashed) is
// found and reported once, and the selected keyframes carry the sensor's pose with it applied; clouds
// registered in the world come out as selected keyframes in the sensor frame; a node whose inputs are
// silent says so on /rosout, naming the topics.
#include <algorithm>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/common/transforms.h>
#include <pcl_conversions/pcl_conversions.h>
#include <rosgraph_msgs/Log.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/transform_broadcaster.h>

#include "harness.h"
#include "topic_watch.h"

namespace scan_context_loop {
namespace test {
namespace {


/// T_base<-velodyne: the sensor 1.2 m above and 0.3 m ahead of the base, turned 90 degrees.
Eigen::Isometry3d baseFromVelodyne() {
  Eigen::Isometry3d e = Eigen::Isometry3d::Identity();
  e.translation() << 0.3, 0.0, 1.2;
  e.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  return e;
}

/// Clouds of the selected keyframes the tests look at, point by point (each is a whole scan).
constexpr std::size_t kCloudsChecked = 3;

/// Expects the selected keyframes (`poses`, in arrival order) to be keyframes 0, 1, ... of `drive`, each
/// at its stamp, in `frame` with child `sensor`, at the drive's sensor pose.
void expectSelectedPoses(const Drive& drive, const ros::Time& base, const std::vector<nav_msgs::Odometry>& poses,
                         const std::string& frame, const std::string& sensor) {
  ASSERT_EQ(poses.size(), drive.truth.size()) << "one selected keyframe per keyframe stored";
  for (std::size_t k = 0; k < poses.size(); ++k) {
    SCOPED_TRACE("keyframe " + std::to_string(k));
    EXPECT_EQ(poses[k].header.stamp, base + ros::Duration(drive.times[k]));
    EXPECT_EQ(poses[k].header.frame_id, frame);
    EXPECT_EQ(poses[k].child_frame_id, sensor);
    Eigen::Isometry3d pose;
    tf2::fromMsg(poses[k].pose.pose, pose);
    EXPECT_LT((pose.translation() - drive.truth[k].translation()).norm(), 1e-6);
    EXPECT_LT(Eigen::AngleAxisd(pose.linear().transpose() * drive.truth[k].linear()).angle(), 1e-6);
  }
}

/// Expects `cloud` to be keyframe k's scan in the sensor frame `sensor`, at its stamp: its points are the
/// scan's, in order, within `tolerance` [m]: the finite ones within max_radius (80 m by default).
void expectSensorFrameCloud(const Drive& drive, const ros::Time& base, std::size_t k,
                            const sensor_msgs::PointCloud2& cloud, const std::string& sensor, double tolerance) {
  SCOPED_TRACE("cloud of keyframe " + std::to_string(k));
  EXPECT_EQ(cloud.header.stamp, base + ros::Duration(drive.times[k]));
  EXPECT_EQ(cloud.header.frame_id, sensor);
  pcl::PointCloud<pcl::PointXYZ> published;
  pcl::fromROSMsg(cloud, published);
  const pcl::PointCloud<pcl::PointXYZI> scan = drive.scan(k);
  std::size_t in_range = 0, next = 0, matched = 0;
  for (const auto& p : scan) {
    in_range += std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::hypot(p.x, p.y) <= 80.0f;
  }
  for (const auto& p : published) {
    while (next < scan.size() && (scan[next].getVector3fMap() - p.getVector3fMap()).norm() > tolerance) ++next;
    if (next == scan.size()) break;
    ++matched;
    ++next;
  }
  EXPECT_EQ(matched, published.size()) << "a point that is not the scan's, in the scan's order";
  // A point on the 80 m border may fall either side once registered and brought back in float.
  EXPECT_NEAR(static_cast<double>(published.size()), static_cast<double>(in_range), 3.0);
  EXPECT_GT(published.size(), 1000u);
}

TEST(Frames, SlashedInputsPublishedWithTf2Names) {
  ros::NodeHandle nh;
  RosoutWatch rosout(nh);
  Harness harness(nh);
  Collected<nav_msgs::Odometry> selected(nh, "selected_keyframe_odom");
  Collected<sensor_msgs::PointCloud2> selected_clouds(nh, "selected_keyframe_cloud", kCloudsChecked);
  ASSERT_TRUE(harness.waitForNode(30.0)) << "the loop-closure node never subscribed";
  ASSERT_TRUE(selected.waitForPublisher(10.0) && selected_clouds.waitForPublisher(10.0));
  // This node, the loop-closure node and the silent one log to /rosout.
  for (int i = 0; i < 100 && rosout.publishers() < 3; ++i) ros::WallDuration(0.1).sleep();

  // tf1's static_transform_publisher: /base -> /velodyne every 10 ms, stamped 10 ms ahead; from a second
  // after the first keyframe, which waits for it meanwhile.
  tf2_ros::TransformBroadcaster broadcaster;
  const ros::WallTime tf_from = ros::WallTime::now() + ros::WallDuration(1.0);
  const ros::WallTimer tf1 = nh.createWallTimer(ros::WallDuration(0.01), [&](const ros::WallTimerEvent&) {
    if (ros::WallTime::now() < tf_from) return;
    geometry_msgs::TransformStamped t = tf2::eigenToTransform(baseFromVelodyne());
    t.header.stamp = ros::Time::now() + ros::Duration(0.01);
    t.header.frame_id = "/base";
    t.child_frame_id = "/velodyne";
    broadcaster.sendTransform(t);
  });

  const Drive drive = blockDrive(true, 7);
  ros::WallRate rate(12.0);
  for (std::size_t k = 0; k < drive.truth.size() && ros::ok(); ++k) {
    sensor_msgs::PointCloud2 cloud = harness.cloud(drive, k);
    cloud.header.frame_id = "/velodyne";
    nav_msgs::Odometry odom = harness.odom(drive, k);
    odom.header.frame_id = "/odom";
    odom.child_frame_id = "/base";
    odom.pose.pose = tf2::toMsg(drive.truth[k] * baseFromVelodyne().inverse());
    harness.cloud_pub.publish(cloud);
    harness.odom_pub.publish(odom);
    rate.sleep();
  }
  ASSERT_TRUE(harness.waitForKeyframes(drive.truth.size(), 30.0)) << "keyframes held for the extrinsic were lost";
  harness.settle(3.0, 30.0);

  // The extrinsic: found from the slashed names, reported once with both frames; no fallback.
  EXPECT_EQ(rosout.count(rosgraph_msgs::Log::INFO, "/loop_closure", "tf extrinsic base <- velodyne"), 1u);
  EXPECT_EQ(rosout.count(rosgraph_msgs::Log::WARN, "/loop_closure", "poses are used as the sensor's"), 0u);

  const auto loops = harness.loops();
  ASSERT_GE(loops.size(), 10u);
  expectTrueLoops(drive, harness.base, loops, false);
  for (const auto& loop : loops) EXPECT_EQ(loop.header.frame_id, "odom");
  const auto pairs = harness.loopPairs();
  ASSERT_FALSE(pairs.empty());
  for (const auto& pair : pairs) EXPECT_EQ(pair.header.frame_id, "odom");
  const auto markers = harness.shownMarkers();
  ASSERT_FALSE(markers.markers.empty());
  for (const auto& marker : markers.markers) EXPECT_EQ(marker.header.frame_id, "odom") << marker.ns;
  const auto timings = harness.timings();
  ASSERT_FALSE(timings.empty());
  for (const auto& timing : timings) EXPECT_EQ(timing.header.frame_id, "odom");
  // Loops in the sensor's poses: the odometry gate and the positions use the velodyne, not the base.
  const auto& keyframes =
      std::find_if(markers.markers.begin(), markers.markers.end(),
                   [](const visualization_msgs::Marker& m) { return m.ns == "keyframes" && m.id == 0; });
  ASSERT_NE(keyframes, markers.markers.end());
  ASSERT_FALSE(keyframes->points.empty());
  EXPECT_NEAR(keyframes->points[0].z, drive.truth[0].translation().z(), 1e-3) << "the first keyframe at the sensor";

  // The selected keyframes: the odometry's frame, the clouds' frame as the sensor, and the base's pose
  // moved to the sensor by the extrinsic; the clouds as they came (the sensor frame), without NaN.
  expectSelectedPoses(drive, harness.base, selected.messages(), "odom", "velodyne");
  const auto clouds = selected_clouds.messages();
  ASSERT_EQ(clouds.size(), kCloudsChecked);
  for (std::size_t k = 0; k < clouds.size(); ++k)
    expectSensorFrameCloud(drive, harness.base, k, clouds[k], "velodyne", 1e-6);
}

TEST(Frames, RegisteredCloudsSelectedInTheSensorFrame) {
  // A-LOAM's and LIO-SAM's shape: clouds registered in odom, the odometry's child the sensor
  // (cloud_in_world_frame, in the namespace "world").
  ros::NodeHandle nh("world");
  Harness harness(nh);
  Collected<nav_msgs::Odometry> selected(nh, "selected_keyframe_odom");
  Collected<sensor_msgs::PointCloud2> selected_clouds(nh, "selected_keyframe_cloud", kCloudsChecked);
  ASSERT_TRUE(harness.waitForNode(30.0)) << "the loop-closure node in world never subscribed";
  ASSERT_TRUE(selected.waitForPublisher(10.0) && selected_clouds.waitForPublisher(10.0));
  Drive drive = blockDrive(false, 9);
  drive.truth.resize(8);
  drive.times.resize(8);
  ros::WallRate rate(10.0);
  for (std::size_t k = 0; k < drive.truth.size() && ros::ok(); ++k) {
    pcl::PointCloud<pcl::PointXYZI> registered;
    pcl::transformPointCloud(drive.scan(k), registered, drive.truth[k].matrix().cast<float>());
    sensor_msgs::PointCloud2 cloud;
    pcl::toROSMsg(registered, cloud);
    cloud.header.stamp = harness.base + ros::Duration(drive.times[k]);
    cloud.header.frame_id = "odom";
    harness.cloud_pub.publish(cloud);
    harness.odom_pub.publish(harness.odom(drive, k));
    rate.sleep();
  }
  ASSERT_TRUE(harness.waitForKeyframes(drive.truth.size(), 30.0));
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
  while (selected.count() < drive.truth.size() && ros::WallTime::now() < end) ros::WallDuration(0.1).sleep();
  expectSelectedPoses(drive, harness.base, selected.messages(), "odom", "velodyne");
  const auto clouds = selected_clouds.messages();
  ASSERT_EQ(clouds.size(), kCloudsChecked);
  // Registered and brought back in float: within a millimetre.
  for (std::size_t k = 0; k < clouds.size(); ++k)
    expectSensorFrameCloud(drive, harness.base, k, clouds[k], "velodyne", 1e-3);
}

TEST(Frames, SilentInputsNamedInAWarning) {
  ros::NodeHandle nh;
  RosoutWatch rosout(nh);
  // no_input_warning 2 s, repeated every 2 s while nothing comes.
  EXPECT_TRUE(rosout.waitFor(rosgraph_msgs::Log::WARN, "/silent/loop_closure",
                             "no keyframe cloud on /silent/keyframe_cloud", 20.0));
  EXPECT_TRUE(rosout.waitFor(rosgraph_msgs::Log::WARN, "/silent/loop_closure",
                             "no keyframe odometry on /silent/keyframe_odom", 20.0));
  EXPECT_GE(rosout.count(rosgraph_msgs::Log::WARN, "/silent/loop_closure", "(0 publishers)"), 1u);
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_frames"); }
