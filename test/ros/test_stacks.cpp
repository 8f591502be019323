// The launch file next to each odometry stack, fed a short simulated bag shaped like that stack's output
// (scan_context_simulate --block --stack NAME, played by rosbag in stack_bag.test): loops must arrive,
// every one verified and true against the bag's ground truth, in the odometry's frame as tf2 names it
// (without the leading '/' A-LOAM and LeGO-LOAM write). With the reference backend (pose_graph:=true) its
// corrected path must hold every selected keyframe, in the stack's frame, and lie closer to the truth
// than the odometry.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <XmlRpcClient.h>
#include <XmlRpcValue.h>
#include <gtest/gtest.h>
#include <nav_msgs/Path.h>
#include <ros/master.h>
#include <ros/network.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include "harness.h"
#include "topic_watch.h"
#include "scan_context_sim/stack_shape.h"

namespace scan_context_loop {
namespace test {
namespace {

/// The bag's ground truth (shaped like the stack's odometry) as LiDAR poses by stamp.
class GroundTruth {
 public:
  GroundTruth(ros::NodeHandle nh, const sim::StackShape& shape) : shape_(shape) {
    sub_ = nh.subscribe<nav_msgs::Odometry>("ground_truth", 10000, [this](const nav_msgs::Odometry::ConstPtr& m) {
      Eigen::Isometry3d pose;
      tf2::fromMsg(m->pose.pose, pose);
      std::lock_guard<std::mutex> lock(mutex_);
      poses_[m->header.stamp] = sim::fromStackPose(shape_, pose);
      last_ = ros::WallTime::now();
    });
  }

  /// Waits for the first pose (at most `first` seconds), then until none came for `quiet` seconds (at
  /// most `limit`): the bag has been played. False when no pose came.
  bool waitUntilPlayed(double first, double quiet, double limit) {
    const ros::WallTime start = ros::WallTime::now();
    while (ros::ok() && (ros::WallTime::now() - start).toSec() < limit) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (poses_.empty() && (ros::WallTime::now() - start).toSec() > first) return false;
        if (!poses_.empty() && (ros::WallTime::now() - last_).toSec() > quiet) return true;
      }
      ros::WallDuration(0.1).sleep();
    }
    return false;
  }

  /// The true LiDAR pose at `stamp`; false when the bag has none.
  bool pose(const ros::Time& stamp, Eigen::Isometry3d* pose) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = poses_.find(stamp);
    if (it == poses_.end()) return false;
    *pose = it->second;
    return true;
  }

 private:
  const sim::StackShape shape_;
  mutable std::mutex mutex_;  // guards poses_ and last_ (callback vs. test thread)
  std::map<ros::Time, Eigen::Isometry3d> poses_;
  ros::WallTime last_;
  // Last: unsubscribed first on destruction (waiting for a callback in progress), before the data goes.
  ros::Subscriber sub_;
};

/// The RMS of `path`'s position errors [m] against the truth, each taken relative to its pose at the path's
/// first keyframe (the backend holds that keyframe where the odometry put it); -1 when the truth lacks a
/// stamp of the path.
double errorFromFirstKeyframe(const nav_msgs::Path& path, const GroundTruth& truth) {
  if (path.poses.empty()) return -1.0;
  Eigen::Isometry3d first, first_truth;
  double sum = 0.0;
  for (std::size_t i = 0; i < path.poses.size(); ++i) {
    Eigen::Isometry3d pose, true_pose;
    tf2::fromMsg(path.poses[i].pose, pose);
    if (!truth.pose(path.poses[i].header.stamp, &true_pose)) return -1.0;
    if (i == 0) {
      first = pose;
      first_truth = true_pose;
    }
    sum += ((first.inverse() * pose).translation() - (first_truth.inverse() * true_pose).translation()).squaredNorm();
  }
  return std::sqrt(sum / path.poses.size());
}

/// The backend behind the stack's launch file (pose_graph:=true): once it is done, its corrected path
/// holds every keyframe the node selected, at its stamp, in `frame` (with the tf `frame` -> `odom_frame`
/// when `tf` is set), and its error against the truth is under `max_ratio` times the odometry's.
void expectCorrectedPath(ros::NodeHandle nh, const Latest<nav_msgs::Path>& corrected,
                         const Latest<nav_msgs::Path>& odometry, const std::vector<nav_msgs::Odometry>& selected,
                         const GroundTruth& truth, const std::string& stack, const std::string& frame,
                         const std::string& odom_frame, bool tf, double max_ratio) {
  ASSERT_GT(selected.size(), 100u) << "too few keyframes selected";
  const auto complete = [&](const nav_msgs::Path& p) { return p.poses.size() == selected.size(); };
  nav_msgs::Path path, raw;
  // Final: no path came for 3 s (the last loop was solved; it solves at most every 0.5 s).
  ASSERT_TRUE(corrected.waitForFinal(complete, 3.0, 30.0, &path))
      << "no corrected path with every selected keyframe (" << selected.size() << "); the latest has "
      << path.poses.size();
  ASSERT_TRUE(odometry.waitForFinal(complete, 3.0, 30.0, &raw));
  EXPECT_EQ(path.header.frame_id, frame);
  for (std::size_t k = 0; k < selected.size(); ++k) {
    ASSERT_EQ(path.poses[k].header.stamp, selected[k].header.stamp) << "keyframe " << k;
  }
  if (tf) {
    tf2_ros::Buffer buffer;
    tf2_ros::TransformListener listener(buffer, nh);
    EXPECT_TRUE(buffer.canTransform(frame, odom_frame, ros::Time(0), ros::Duration(5.0)))
        << "no tf " << frame << " -> " << odom_frame << " from the backend";
  }
  const double before = errorFromFirstKeyframe(raw, truth), after = errorFromFirstKeyframe(path, truth);
  ASSERT_GE(before, 0.0) << "a keyframe the bag's truth does not have";
  ASSERT_GE(after, 0.0);
  const double ratio = after / before;
  std::printf(
      "%s: position RMSE from the first keyframe: odometry %.3f m, corrected %.3f m, ratio %.3f "
      "(%zu keyframes)\n",
      stack.c_str(), before, after, ratio, selected.size());
  ::testing::Test::RecordProperty("odometry_rmse_m", std::to_string(before));
  ::testing::Test::RecordProperty("corrected_rmse_m", std::to_string(after));
  ::testing::Test::RecordProperty("corrected_to_odometry", std::to_string(ratio));
  EXPECT_GT(before, 0.5) << "the bag's odometry drifts too little to show a correction";
  EXPECT_LT(ratio, max_ratio) << "odometry " << before << " m, corrected " << after << " m";
}

/// The nodes the master lists in `payload` (a getSystemState list of [topic, [node, ...]]) for `topic`.
std::vector<std::string> nodesOn(XmlRpc::XmlRpcValue& payload, const std::string& topic) {
  std::vector<std::string> nodes;
  for (int i = 0; i < payload.size(); ++i) {
    if (static_cast<std::string>(payload[i][0]) != topic) continue;
    for (int j = 0; j < payload[i][1].size(); ++j) nodes.push_back(payload[i][1][j]);
  }
  return nodes;
}

/// Whether `publisher` (a node name) has a connection up on `topic` to a node other than `self`: its own
/// account (the slave API's getBusInfo: [id, destination, direction, transport, topic, connected, ...]).
bool connectedToAnother(const std::string& publisher, const std::string& topic, const std::string& self) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = self;
  args[1] = publisher;
  if (!ros::master::execute("lookupNode", args, result, payload, false)) return false;
  std::string host, path;
  std::uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(payload), host, port)) return false;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue call, reply;
  call[0] = self;
  if (!client.execute("getBusInfo", call, reply) || client.isFault() || reply.size() < 3) return false;
  XmlRpc::XmlRpcValue& links = reply[2];
  for (int i = 0; i < links.size(); ++i) {
    if (links[i].size() < 5) continue;
    const std::string destination = links[i][1], direction = links[i][2], on = links[i][4];
    if (direction == "o" && on == topic && destination != self) return true;
  }
  return false;
}

/// Waits until a node other than this test is connected to `topic`'s publisher, by the publisher's own
/// account; false after `seconds`. The node publishes its selected keyframes once and unlatched, so a
/// backend in its own process must be connected before the first one: the master listing the backend's
/// subscription is not enough (the connection comes after it, late on a loaded machine).
bool waitForOtherSubscriber(const ros::NodeHandle& nh, const std::string& topic, double seconds) {
  const std::string resolved = nh.resolveName(topic), self = ros::this_node::getName();
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    XmlRpc::XmlRpcValue args, result, payload;
    args[0] = self;
    // payload: [publishers, subscribers, services].
    if (ros::master::execute("getSystemState", args, result, payload, false) && payload.size() > 0) {
      for (const std::string& publisher : nodesOn(payload[0], resolved)) {
        if (publisher != self && connectedToAnother(publisher, resolved, self)) return true;
      }
    }
    ros::WallDuration(0.1).sleep();
  }
  return false;
}

/// Waits until `count` loops join a later session to the first; false after `seconds`.
bool waitForLoopsAcrossSessions(const Harness& harness, std::size_t count, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    std::size_t across = 0;
    for (const auto& loop : harness.loops()) across += loop.query_session > 0 && loop.match_session == 0 ? 1 : 0;
    if (across >= count) return true;
    ros::WallDuration(0.2).sleep();
  }
  return false;
}

TEST(Stacks, TrueVerifiedLoopsFromTheStacksBag) {
  ros::NodeHandle nh, pnh("~");
  const std::string name = pnh.param("stack", std::string());
  const sim::StackShape* shape = sim::findStackShape(name);
  ASSERT_NE(shape, nullptr) << "unknown stack '" << name << "'";
  Harness harness(nh);
  const bool backend = pnh.param("pose_graph", false);
  Collected<nav_msgs::Odometry> selected(nh, "selected_keyframe_odom");
  Latest<nav_msgs::Path> corrected(nh, "corrected_path"), odometry(nh, "odometry_path");
  // Connected before the bag plays (it waits for the ground truth's subscriber, made next), and so is the
  // backend: a keyframe published before it subscribed would be missing from its corrected path.
  if (backend) {
    ASSERT_TRUE(selected.waitForPublisher(30.0)) << "the loop-closure node never advertised";
    ASSERT_TRUE(waitForOtherSubscriber(nh, "selected_keyframe_odom", 30.0)) << "the backend never subscribed";
  }
  GroundTruth truth(nh, *shape);
  const bool replayed = pnh.param("replayed", false);
  if (replayed) {
    // rosbag play -l: every pass starts a session whose loops reach the first pass's keyframes.
    ASSERT_TRUE(waitForLoopsAcrossSessions(harness, 10, 130.0)) << "too few loops into the first pass";
  } else {
    // rosbag play waits for a subscriber on every topic of the bag, the ground truth included.
    ASSERT_TRUE(truth.waitUntilPlayed(30.0, 2.0, 90.0)) << "the bag was not played";
    harness.settle(3.0, 30.0);
  }
  const auto loops = harness.loops();
  ASSERT_GE(loops.size(), 10u);
  const std::string frame = shape->odom_frame.substr(shape->odom_frame.find_first_not_of('/'));
  for (const auto& loop : loops) {
    SCOPED_TRACE("loop " + std::to_string(loop.query_id) + " -> " + std::to_string(loop.match_id));
    EXPECT_EQ(loop.header.frame_id, frame);
    Eigen::Isometry3d query_pose, match_pose;
    ASSERT_TRUE(truth.pose(loop.query_stamp, &query_pose)) << "a loop from a keyframe the bag does not have";
    ASSERT_TRUE(truth.pose(loop.match_stamp, &match_pose)) << "a loop to a keyframe the bag does not have";
    EXPECT_TRUE(loop.verified);
    expectTrueLoop(query_pose, match_pose, loop);
  }
  if (pnh.param("expect_lio", false) && !replayed) {
    // LIO-SAM's hook gets verified loops, one per keyframe, at most one a second.
    const auto lio = harness.lioLoops();
    ASSERT_FALSE(lio.empty());
    EXPECT_LT(lio.size(), loops.size());
  }
  if (backend) {
    expectCorrectedPath(nh, corrected, odometry, selected.messages(), truth, name,
                        pnh.param("graph_frame", std::string()), frame, pnh.param("graph_tf", false),
                        pnh.param("max_ratio", 0.7));
  }
}

// SC-A-LOAM's local clouds (sensor-frame points labelled camera_init, the odometry's world frame) read the
// way A-LOAM's registered ones would be with cloud_in_world_frame false: the transform the node would take
// as the extrinsic is the vehicle's moving pose. Every keyframe is refused, and the error names the fix.
TEST(Stacks, SensorPointsUnderTheWorldsNameAreRefusedWithTheFix) {
  ros::NodeHandle nh;
  RosoutWatch rosout(nh);
  Collected<nav_msgs::Odometry> selected(nh, "selected_keyframe_odom");
  GroundTruth truth(nh, *sim::findStackShape("sc_aloam"));
  ASSERT_TRUE(truth.waitUntilPlayed(30.0, 2.0, 90.0)) << "the bag was not played";
  ros::WallDuration(2.0).sleep();
  EXPECT_TRUE(rosout.waitFor(rosgraph_msgs::Log::ERROR, "/loop_closure", "set sensor_frame: aft_mapped", 10.0))
      << "no error names the fix";
  EXPECT_TRUE(selected.messages().empty()) << selected.messages().size() << " keyframes taken with a moving extrinsic";
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_stacks"); }
