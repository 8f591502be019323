// The launch file next to each odometry stack, fed a short simulated bag shaped like that stack's output
// (scan_context_simulate --block --stack NAME, played by rosbag in stack_bag.test): loops must arrive,
// every one verified and true against the bag's ground truth, in the odometry's frame as tf2 names it
// (without the leading '/' A-LOAM and LeGO-LOAM write).
#include <map>
#include <mutex>
#include <string>

#include <gtest/gtest.h>
#include <tf2_eigen/tf2_eigen.h>

#include "harness.h"
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
  ros::Subscriber sub_;
  mutable std::mutex mutex_;  // guards poses_ and last_ (callback vs. test thread)
  std::map<ros::Time, Eigen::Isometry3d> poses_;
  ros::WallTime last_;
};

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
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_stacks"); }
