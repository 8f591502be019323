// rostest: the reference backend (pose_graph) behind the loop-closure node, on a drive with drifting
// odometry. The corrected path must lie much closer to the truth than the odometry, the tf map -> odom
// must be the correction, the map must come on request, and a confident false loop must not pull it.
// The map saved (~save_map, and map_save at shutdown by a second backend the test unloads) must read
// back with PCL's, evo's and g2o's formats, and paths out of map_directory must be refused.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <mutex>

#include <gtest/gtest.h>
#include <nav_msgs/Path.h>
#include <nodelet/NodeletLoad.h>
#include <nodelet/NodeletUnload.h>
#include <pcl/io/pcd_io.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "../common/map_file_readers.h"
#include "harness.h"
#include "scan_context_loop/SaveMap.h"
#include "path_poses.h"
#include "topic_watch.h"
#include "scan_context_loop/eval/trajectory_error.h"
#include "scan_context_sim/trajectory.h"

namespace scan_context_loop {
namespace test {
namespace {

/// The stamps of a path as the map files write them (seconds, nine decimals).
std::vector<std::string> stampTexts(const nav_msgs::Path& path) {
  std::vector<std::string> out;
  for (const auto& p : path.poses) {
    char text[32];
    std::snprintf(text, sizeof(text), "%u.%09u", p.header.stamp.sec, p.header.stamp.nsec);
    out.push_back(text);
  }
  return out;
}

/// Reads the six map files in `dir` back and checks them against `path` (the corrected poses they must
/// hold) and `loops` (the loop factors in the graph); returns the PCD's point count.
std::size_t expectMapFiles(const std::string& dir, const nav_msgs::Path& path, std::size_t loops) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  EXPECT_EQ(pcl::io::loadPCDFile(dir + "/map.pcd", cloud), 0) << dir;
  const Tum corrected = readTum(dir + "/corrected_tum.txt"), odometry = readTum(dir + "/odometry_tum.txt");
  EXPECT_EQ(corrected.poses.size(), path.poses.size());
  EXPECT_EQ(odometry.poses.size(), path.poses.size());
  EXPECT_EQ(corrected.stamp_text, stampTexts(path));
  EXPECT_EQ(readKitti(dir + "/corrected_kitti.txt").size(), path.poses.size());
  EXPECT_EQ(rows(dir + "/times.txt").size(), path.poses.size());
  const G2o g2o = readG2o(dir + "/pose_graph.g2o");
  EXPECT_EQ(g2o.vertices.size(), path.poses.size());
  EXPECT_EQ(g2o.edges.size(), path.poses.size() - 1 + loops);
  EXPECT_EQ(g2o.fixed, std::vector<long>{0});
  for (const auto& edge : g2o.edges) {
    EXPECT_EQ(Eigen::LLT<Matrix6>(edge.information).info(), Eigen::Success) << edge.a << " -> " << edge.b;
  }
  return cloud.size();
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
  ASSERT_TRUE(ros::service::waitForService("pose_graph/save_map", 30000));
  std::string map_directory;
  ASSERT_TRUE(ros::param::get("pose_graph/map_directory", map_directory));
  ASSERT_EQ(map_directory.compare(0, 5, "/tmp/"), 0) << map_directory;
  // A second backend on the same inputs (its outputs elsewhere) with map_save: it writes when unloaded.
  const std::string second = "/pose_graph_at_shutdown";
  ros::param::set(second + "/map_directory", map_directory);
  ros::param::set(second + "/map_save", std::string("at_shutdown"));
  ros::param::set(second + "/publish_tf", false);
  nodelet::NodeletLoad load;
  load.request.name = second;
  load.request.type = "scan_context_loop/PoseGraphNodelet";
  for (const char* topic : {"corrected_path", "odometry_path", "graph_markers", "map_cloud"}) {
    load.request.remap_source_args.push_back(nh.resolveName(topic));
    load.request.remap_target_args.push_back(second + "/" + topic);
  }
  ASSERT_TRUE(ros::service::call("/manager/load_nodelet", load));
  ASSERT_TRUE(load.response.success);
  ASSERT_TRUE(ros::service::waitForService(second + "/save_map", 30000));
  DiagnosticsWatch second_diagnostics(nh, second.substr(1), "pose graph");
  // Its first status comes a second after its start, which subscribes: then the drive may begin.
  ASSERT_EQ(second_diagnostics.value("keyframes", ros::WallTime::now(), 30.0), 0) << "the second backend is not up";

  const std::size_t n = drive_->truth.size();
  harness.publish(*drive_, 0, n, 10.0);
  const ros::WallTime drive_end = ros::WallTime::now();
  harness.settle(3.0, 60.0);
  std::size_t loops = 0;  // the verified ones: only they enter the graph (verified_only)
  for (const auto& loop : harness.loops()) loops += loop.verified ? 1 : 0;
  ASSERT_GT(loops, 5u) << "the loop-closure node verified too few loops to test the backend";

  nav_msgs::Path path, raw;
  const auto complete = [&](const nav_msgs::Path& p) { return p.poses.size() == n; };
  ASSERT_TRUE(corrected.waitFor(complete, 30.0, &path))
      << "no corrected path with every keyframe (" << n << "); the latest has " << path.poses.size();
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
  // It carries the data's time, not the clock's: the drive's stamps (from 1000 s) are far from the wall
  // clock, as in a replay without --clock, and a tf user (RViz) looks the transform up at the data's stamps.
  const ros::Time newest = harness.base + ros::Duration(drive_->times[n - 1]);
  const double since_drive = (ros::WallTime::now() - drive_end).toSec();
  EXPECT_GE(tf.header.stamp, newest) << tf.header.stamp;
  EXPECT_LE((tf.header.stamp - newest).toSec(), since_drive + 1.0) << tf.header.stamp << " vs data at " << newest;
  EXPECT_TRUE(tf_buffer.canTransform("map", "odom", tf.header.stamp - ros::Duration(0.01), ros::Duration(2.0)))
      << "the tf is not found between its two newest stamps";

  // Every loop the node verified is drawn between the corrected poses.
  visualization_msgs::MarkerArray shown;
  ASSERT_TRUE(markers.waitFor(
      [&](const visualization_msgs::MarkerArray& m) {
        return !m.markers.empty() && m.markers[0].points.size() == 2 * loops;
      },
      10.0, &shown));
  EXPECT_EQ(shown.markers[0].ns, "verified loops");

  // The map on request: the keyframe clouds at the corrected poses, thinned, in the map frame.
  std_srvs::Trigger trigger;
  ASSERT_TRUE(ros::service::call("pose_graph/publish_map", trigger));
  EXPECT_TRUE(trigger.response.success) << trigger.response.message;
  sensor_msgs::PointCloud2 cloud;
  ASSERT_TRUE(map.waitFor([](const sensor_msgs::PointCloud2& c) { return c.width * c.height > 1000; }, 30.0, &cloud));
  EXPECT_EQ(cloud.header.frame_id, "map");
  EXPECT_LT(cloud.width * cloud.height, n * harness.cloud(*drive_, 0).width / 4) << "the map is not thinned";

  // The map saved on request into map_directory: six files that read back, the trajectory the path's.
  scan_context_loop::SaveMap save;
  save.request.path = "run1";
  ASSERT_TRUE(ros::service::call("pose_graph/save_map", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  std::printf("save_map: %s\n", save.response.message.c_str());
  EXPECT_EQ(save.response.files.size(), 6u);
  EXPECT_EQ(save.response.files.front(), map_directory + "/run1/map.pcd");
  EXPECT_NE(save.response.message.find("voxel-filtered at 0.50 m"), std::string::npos) << save.response.message;
  ASSERT_TRUE(corrected.waitFor(complete, 10.0, &path));
  const std::size_t saved_points = expectMapFiles(map_directory + "/run1", path, loops);
  EXPECT_GT(saved_points, 1000u);
  EXPECT_LT(saved_points, n * harness.cloud(*drive_, 0).width / 4) << "the saved map is not thinned";

  // Paths out of map_directory are refused and nothing is written: "..", an absolute path outside, a
  // symbolic link (to a directory outside, and through it).
  const std::string outside = map_directory + "_outside";
  ASSERT_TRUE(std::filesystem::create_directory(outside));
  ASSERT_EQ(::symlink(outside.c_str(), (map_directory + "/link").c_str()), 0);
  const std::vector<std::pair<std::string, std::string>> hostile = {{"../x", "\"..\""},
                                                                    {outside + "/run", "outside the map directory"},
                                                                    {"link", "symbolic link"},
                                                                    {"link/run", "outside the map directory"}};
  for (const auto& call : hostile) {
    scan_context_loop::SaveMap refused;
    refused.request.path = call.first;
    ASSERT_TRUE(ros::service::call("pose_graph/save_map", refused));
    EXPECT_FALSE(refused.response.success) << call.first;
    EXPECT_TRUE(refused.response.files.empty()) << call.first;
    EXPECT_NE(refused.response.message.find(call.second), std::string::npos)
        << call.first << ": " << refused.response.message;
  }
  EXPECT_TRUE(std::filesystem::is_empty(outside)) << "a refused save wrote outside map_directory";
  EXPECT_FALSE(std::filesystem::exists(map_directory + "/../x"));
  {
    const ros::WallTime now = ros::WallTime::now();
    EXPECT_EQ(diagnostics.value("map saves written", now, 10.0), 1);
    EXPECT_EQ(diagnostics.value("map saves failed", now, 10.0), static_cast<long>(hostile.size()));
  }

  // A confident false loop (keyframe 5 said to lie on the far side of the block, 0.1 m standard deviation)
  // and bad inputs (a loop at stamps of no keyframe, one with a zero covariance, a keyframe stamped before
  // the last, one with a NaN position, both sent as the loop-closure node sends selected keyframes): the
  // robust loss holds the graph, the rest is counted and skipped.
  scan_context_loop::LoopClosure false_loop = harness.loops().front();
  false_loop.query_stamp = harness.base + ros::Duration(drive_->times[n / 2]);
  false_loop.match_stamp = harness.base + ros::Duration(drive_->times[5]);
  false_loop.relative_pose = tf2::toMsg(Eigen::Isometry3d::Identity());
  false_loop.covariance.fill(0.0);
  for (int i = 0; i < 6; ++i) false_loop.covariance[7 * i] = i < 3 ? 0.01 : 1e-4;
  false_loop.verified = true;
  ros::Publisher loop_pub = nh.advertise<scan_context_loop::LoopClosure>("loop_closures", 10);
  ros::Publisher keyframe_pub = nh.advertise<nav_msgs::Odometry>("selected_keyframe_odom", 10);
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
  keyframe_pub.publish(back_in_time);
  keyframe_pub.publish(nan_pose);
  ASSERT_TRUE(markers.waitFor(
      [&](const visualization_msgs::MarkerArray& m) {
        return !m.markers.empty() && m.markers[0].points.size() == 2 * (loops + 1);
      },
      10.0, &shown));
  ASSERT_TRUE(corrected.waitFor(complete, 10.0, &path));
  const TrajectoryError held = absoluteTrajectoryError(posesOf(path), drive_->truth);
  EXPECT_LT(held.rmse, 0.5 * before.rmse) << "the false loop pulled the graph: " << held.rmse << " m";
  std::printf("ATE RMSE with a confident false loop added: %.2f m\n", held.rmse);
  const ros::WallTime now = ros::WallTime::now();
  EXPECT_EQ(diagnostics.value("inputs rejected", now, 10.0), 4);
  EXPECT_EQ(diagnostics.value("keyframes", now, 10.0), static_cast<long>(n));
  EXPECT_EQ(diagnostics.value("loops in the graph", now, 10.0), static_cast<long>(loops + 1));

  // The second backend, unloaded, writes map_save (relative: inside map_directory) with what it had:
  // every keyframe (the bad inputs refused there too) and the loops, the false one included.
  EXPECT_EQ(second_diagnostics.value("keyframes", ros::WallTime::now(), 10.0), static_cast<long>(n));
  const long second_loops = second_diagnostics.value("loops in the graph", ros::WallTime::now(), 10.0);
  nodelet::NodeletUnload unload;
  unload.request.name = second;
  ASSERT_TRUE(ros::service::call("/manager/unload_nodelet", unload));
  EXPECT_TRUE(unload.response.success);
  const std::size_t shutdown_points = expectMapFiles(map_directory + "/at_shutdown", path, second_loops);
  EXPECT_GT(shutdown_points, 1000u);
  std::printf("map saved at shutdown: %zu points; on request: %zu points\n", shutdown_points, saved_points);
  std::filesystem::remove_all(outside);
  std::filesystem::remove_all(map_directory);
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_pose_graph"); }
