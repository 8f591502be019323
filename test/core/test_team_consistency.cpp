// Loops between two robots' odometry frames are reported once another loop of the same frames agrees.
#include <gtest/gtest.h>

#include "scan_context_loop/core/team_consistency.h"

namespace scan_context_loop {
namespace {

/// Robot B's odometry frame lies at `frame` in robot A's; a loop from A's keyframe at x = `along` on a
/// straight street to B's keyframe beside it, its relative pose off by `slide` metres along the street.
TeamLoopOffer loopAt(double along, double slide, std::size_t handle, const std::string& robot = "b") {
  const Eigen::Isometry3d frame =
      Eigen::Translation3d(40.0, -3.0, 0.0) * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ());
  TeamLoopOffer loop;
  loop.robot = robot;
  loop.run = 1;
  loop.own_pose = Eigen::Translation3d(along, 0.0, 0.0) * Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d other_world =
      Eigen::Translation3d(along + 1.0, 3.5, 0.0) * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ());
  loop.other_pose = frame.inverse() * other_world;  // in B's odometry frame
  loop.relative = loop.own_pose.inverse() * other_world;
  loop.relative.translation().x() += slide;
  loop.own_path = along;
  loop.other_path = 100.0 - along;
  loop.handle = handle;
  return loop;
}

TEST(TeamConsistency, ReportsLoopsOnceAnotherAgreesAndHoldsBackOneThatSlid) {
  TeamConsistency check{Config()};  // consistency_min_support 1, 1 m and 2 deg, 0.05 per metre
  TeamRelease r = check.offer(loopAt(0.0, 0.0, 0));
  EXPECT_TRUE(r.report.empty());         // alone: it waits
  r = check.offer(loopAt(2.0, 3.0, 1));  // slid 3 m along the street: agrees with nothing
  EXPECT_TRUE(r.report.empty());
  r = check.offer(loopAt(4.0, 0.0, 2));  // agrees with the first: both go out
  EXPECT_EQ(r.report, (std::vector<std::size_t>{0, 2}));
  r = check.offer(loopAt(6.0, 0.05, 3));  // agrees with the nearest confirmed one
  EXPECT_EQ(r.report, (std::vector<std::size_t>{3}));
  r = check.offer(loopAt(8.0, -2.5, 4));  // slid the other way: waits
  EXPECT_TRUE(r.report.empty());
  EXPECT_EQ(check.waiting(), 2u);
  // Another robot's frame is checked apart: its first loop waits.
  EXPECT_TRUE(check.offer(loopAt(0.0, 0.0, 5, "c")).report.empty());
}

TEST(TeamConsistency, DropsWhatWaitsTooLongAndReportsAtOnceWithoutTheCheck) {
  Config config;
  config.consistency_window = 3;
  TeamConsistency check(config);
  std::vector<std::size_t> dropped;
  for (std::size_t i = 0; i < 6; ++i) {
    const double slide = (i % 2 ? 1.0 : -1.0) * 3.0 * static_cast<double>(i + 1);  // none agrees with another
    const TeamRelease r = check.offer(loopAt(2.0 * static_cast<double>(i), slide, i));
    EXPECT_TRUE(r.report.empty());
    dropped.insert(dropped.end(), r.dropped.begin(), r.dropped.end());
  }
  EXPECT_EQ(dropped, (std::vector<std::size_t>{0, 1, 2}));
  config.consistency_min_support = 0;
  TeamConsistency off(config);
  EXPECT_EQ(off.offer(loopAt(0.0, 5.0, 9)).report, (std::vector<std::size_t>{9}));
}

}  // namespace
}  // namespace scan_context_loop
