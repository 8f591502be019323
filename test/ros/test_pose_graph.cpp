// rostest: the reference backend (pose_graph) behind the loop-closure node, on a drive with drifting
// odometry. The corrected path must lie much closer to the truth than the odometry, the tf map -> odom
// must be the correction, the map must come on request, and a confident false loop must not pull it.
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <mutex>

#include <gtest/gtest.h>
#include <nav_msgs/Path.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "harness.h"
#include "latest.h"
#include "scan_context_loop/eval/trajectory_error.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace test {
namespace {

std::vector<Eigen::Isometry3d> posesOf(const nav_msgs::Path& path) {
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& p : path.poses) {
    Eigen::Isometry3d pose;
    tf2::fromMsg(p.pose, pose);
    poses.push_back(pose);
  }
  return poses;
}

class PoseGraphNode : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    drive_ = new Drive(blockDrive(false, 5));
    sim::DriftOptions drift;
    drift.translation_per_metre = 0.03;
    drift.yaw_per_metre = 0.02;
    drift.seed = 3;
    odometry_ = new std::vector<Eigen::Isometry3d>(sim::driftedOdometry(drive_->truth, drift));
  }
  static Drive* drive_;
  static std::vector<Eigen::Isometry3d>* odometry_;
};
Drive* PoseGraphNode::drive_ = nullptr;
std::vector<Eigen::Isometry3d>* PoseGraphNode::odometry_ = nullptr;

TEST_F(PoseGraphNode, CorrectsTheDriftPublishesTheTfAndTheMapAndHoldsOffAFalseLoop) {
  ros::NodeHandle nh;
  Harness harness(nh);
  harness.odometry = odometry_;
  Latest<nav_msgs::Path> corrected(nh, "corrected_path"), odometry(nh, "odometry_path");
  Latest<visualization_msgs::MarkerArray> markers(nh, "graph_markers");
  Latest<sensor_msgs::PointCloud2> map(nh, "map_cloud");
  DiagnosticsWatch diagnostics(nh, "pose_graph", "pose graph");
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  ASSERT_TRUE(harness.waitForNode(30.0));
  ASSERT_TRUE(ros::service::waitForService("pose_graph/publish_map", 30000));

  const std::size_t n = drive_->truth.size();
  harness.publish(*drive_, 0, n, 10.0);
  harness.settle(3.0, 60.0);
  std::size_t loops = 0;  // the verified ones: only they enter the graph (verified_only)
  for (const auto& loop : harness.loops()) loops += loop.verified ? 1 : 0;
  ASSERT_GT(loops, 5u) << "the loop-closure node verified too few loops to test the backend";

  nav_msgs::Path path, raw;
  const auto complete = [&](const nav_msgs::Path& p) { return p.poses.size() == n; };
  ASSERT_TRUE(corrected.waitFor(complete, 30.0, &path)) << "no corrected path with every keyframe (" << n
                                                         << "); the latest has " << path.poses.size();
  ASSERT_TRUE(odometry.waitFor(complete, 30.0, &raw));
  EXPECT_EQ(path.header.frame_id, "map");
  for (std::size_t k = 0; k < n; ++k) {
    ASSERT_EQ(path.poses[k].header.stamp, harness.base + ros::Duration(drive_->times[k]));
    Eigen::Isometry3d pose;
    tf2::fromMsg(raw.poses[k].pose, pose);
    ASSERT_LT((pose.translation() - (*odometry_)[k].translation()).norm(), 1e-6) << "odometry_path is not the input";
  }
  // The graph's first keyframe is held where the odometry put it.
  const auto fixed = posesOf(path);
  EXPECT_LT((fixed.front().translation() - (*odometry_)[0].translation()).norm(), 1e-6);

  const TrajectoryError before = absoluteTrajectoryError(*odometry_, drive_->truth);
  const TrajectoryError after = absoluteTrajectoryError(fixed, drive_->truth);
  ASSERT_EQ(after.poses, n);
  std::printf("ATE RMSE: odometry %.2f m, corrected %.2f m (%zu verified loops)\n", before.rmse, after.rmse, loops);
  EXPECT_GT(before.rmse, 0.5) << "the drift is too small to show anything";
  EXPECT_LT(after.rmse, 0.5 * before.rmse) << "odometry " << before.rmse << " m, corrected " << after.rmse << " m";

  // tf map -> odom is the correction at the newest keyframe: corrected pose x inverse(odometry pose).
  const Eigen::Isometry3d expected = fixed.back() * (*odometry_)[n - 1].inverse();
  geometry_msgs::TransformStamped tf;
  ASSERT_NO_THROW(tf = tf_buffer.lookupTransform("map", "odom", ros::Time(0), ros::Duration(5.0)));
  const Eigen::Isometry3d correction = tf2::transformToEigen(tf);
  EXPECT_LT((correction.translation() - expected.translation()).norm(), 1e-3);
  EXPECT_LT(Eigen::AngleAxisd(correction.rotation().transpose() * expected.rotation()).angle(), 1e-4);

  // Every loop the node verified is drawn between the corrected poses.
  visualization_msgs::MarkerArray shown;
  ASSERT_TRUE(markers.waitFor([&](const visualization_msgs::MarkerArray& m) {
    return !m.markers.empty() && m.markers[0].points.size() == 2 * loops; }, 10.0, &shown));
  EXPECT_EQ(shown.markers[0].ns, "verified loops");

  // The map on request: the keyframe clouds at the corrected poses, thinned, in the map frame.
  std_srvs::Trigger trigger;
  ASSERT_TRUE(ros::service::call("pose_graph/publish_map", trigger));
  EXPECT_TRUE(trigger.response.success) << trigger.response.message;
  sensor_msgs::PointCloud2 cloud;
  ASSERT_TRUE(map.waitFor([](const sensor_msgs::PointCloud2& c) { return c.width * c.height > 1000; }, 30.0, &cloud));
  EXPECT_EQ(cloud.header.frame_id, "map");
  EXPECT_LT(cloud.width * cloud.height, n * harness.cloud(*drive_, 0).width / 4) << "the map is not thinned";

  // A confident false loop (keyframe 5 said to lie on the far side of the block, 0.1 m standard deviation)
  // and bad inputs (a loop at stamps of no keyframe, one with a zero covariance, a keyframe stamped before
  // the last, one with a NaN position): the robust loss holds the graph, the rest is counted and skipped.
  scan_context_loop::LoopClosure false_loop = harness.loops().front();
  false_loop.query_stamp = harness.base + ros::Duration(drive_->times[n / 2]);
  false_loop.match_stamp = harness.base + ros::Duration(drive_->times[5]);
  false_loop.relative_pose = tf2::toMsg(Eigen::Isometry3d::Identity());
  false_loop.covariance.fill(0.0);
  for (int i = 0; i < 6; ++i) false_loop.covariance[7 * i] = i < 3 ? 0.01 : 1e-4;
  false_loop.verified = true;
  ros::Publisher loop_pub = nh.advertise<scan_context_loop::LoopClosure>("loop_closures", 10);
  scan_context_loop::LoopClosure unknown = false_loop;
  unknown.query_stamp = harness.base + ros::Duration(0.05);  // between two keyframes
  scan_context_loop::LoopClosure bad_covariance = harness.loops().back();
  bad_covariance.covariance.fill(0.0);
  nav_msgs::Odometry back_in_time = harness.odom(*drive_, n - 1);
  back_in_time.header.stamp -= ros::Duration(0.05);  // between the last two keyframes
  nav_msgs::Odometry nan_pose = harness.odom(*drive_, n - 1);
  nan_pose.header.stamp += ros::Duration(1.0);
  nan_pose.pose.pose.position.x = std::numeric_limits<double>::quiet_NaN();
  ros::WallDuration(0.5).sleep();  // the node connects to the new publisher
  loop_pub.publish(false_loop);
  loop_pub.publish(unknown);
  loop_pub.publish(bad_covariance);
  harness.odom_pub.publish(back_in_time);
  harness.odom_pub.publish(nan_pose);
  ASSERT_TRUE(markers.waitFor([&](const visualization_msgs::MarkerArray& m) {
    return !m.markers.empty() && m.markers[0].points.size() == 2 * (loops + 1); }, 10.0, &shown));
  ASSERT_TRUE(corrected.waitFor(complete, 10.0, &path));
  const TrajectoryError held = absoluteTrajectoryError(posesOf(path), drive_->truth);
  EXPECT_LT(held.rmse, 0.5 * before.rmse) << "the false loop pulled the graph: " << held.rmse << " m";
  std::printf("ATE RMSE with a confident false loop added: %.2f m\n", held.rmse);
  const ros::WallTime now = ros::WallTime::now();
  EXPECT_EQ(diagnostics.value("inputs rejected", now, 10.0), 4);
  EXPECT_EQ(diagnostics.value("keyframes", now, 10.0), static_cast<long>(n));
  EXPECT_EQ(diagnostics.value("loops in the graph", now, 10.0), static_cast<long>(loops + 1));
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_pose_graph"); }
